// What a newcomer types and trips on: output names that cannot be written are refused before any
// work, the British spelling of options, -V, a suggestion for a mistyped option or command, and
// --spp's samples counted as they are taken.
#include <filesystem>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>

#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools::test {
namespace {

namespace fs = std::filesystem;

const std::string kCrambin = std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb";
const std::string kPsf = std::string(SURFTRACE_TEST_DATA) + "/trajectories/adk_dims/adk.psf.gz";
const std::string kDcd = std::string(SURFTRACE_TEST_DATA) + "/trajectories/adk_dims/adk_dims.dcd";

fs::path freshDirectory(const std::string& name) {
  return ::surftrace::test::freshTempDir(name);
}

bool says(const Result& r, const std::string& text) { return r.output.find(text) != std::string::npos; }

// An output the program cannot write is refused before the work: the camera, which --camera-out
// writes once the surface is built and framed, is never written, and nothing is left behind.
TEST(Usability, OutputNamesAreCheckedBeforeTheWork) {
  const fs::path dir = freshDirectory("names");
  const std::string cam = (dir / "cam.json").string();
  struct Case {
    std::string args, output, mustSay;
  };
  const Case cases[] = {
      {"render " + kCrambin + " --size 32x32 -o " + (dir / "x.ply").string(), "x.ply",
       "-o " + (dir / "x.ply").string() + ": .ply is not an image format"},
      {"render " + kCrambin + " --size 32x32 -o " + (dir / "noextension").string(), "noextension",
       "no extension to choose an image format by"},
      {"render " + kCrambin + " --size 32x32 --exr " + (dir / "x.png").string(), "x.png",
       "only OpenEXR holds: name it .exr"},
      {"trajectory " + kPsf + " " + kDcd + " --size 32x32 -o " + (dir / "f/%05d.obj").string(), "f/00000.obj",
       ".obj is not an image format"},
      {"trajectory " + kPsf + " " + kDcd + " --size 32x32 --exr " + (dir / "f/%05d.tif").string(), "f/00000.tif",
       "only OpenEXR holds"},
      {"trajectory " + kPsf + " " + kDcd + " --size 32x32 -o " + (dir / "f/%05d.png").string() + " --mp4 " +
           (dir / "movie.gif").string(),
       "movie.gif", ".gif is no container for the H.264 movie"},
  };
  for (const Case& c : cases) {
    const Result r = runTool(c.args + " --camera-out " + cam);
    EXPECT_EQ(r.status, 1) << c.args << "\n" << r.output;
    EXPECT_TRUE(says(r, c.mustSay)) << c.args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(cam)) << c.args << ": the work started before the output was refused\n" << r.output;
    EXPECT_FALSE(fs::exists(dir / c.output)) << c.args;
    fs::remove(cam);
  }

  // compare --diff: refused before the images are read and compared (no metrics printed).
  const std::string exr = (dir / "a.exr").string();
  ASSERT_EQ(runTool("render " + kCrambin + " --size 32x32 --quiet --exr " + exr).status, 0);
  const Result diff = runTool("compare " + exr + " " + exr + " --diff " + (dir / "d.ply").string());
  EXPECT_EQ(diff.status, 1) << diff.output;
  EXPECT_TRUE(says(diff, "--diff " + (dir / "d.ply").string() + ": .ply is not an image format")) << diff.output;
  EXPECT_FALSE(says(diff, "coverage mismatch")) << diff.output;
  // Names that are images pass, in any format OpenImageIO writes (the colour as a TIFF).
  const Result tif = runTool("render " + kCrambin + " --size 32x32 --quiet -o " + (dir / "x.tif").string());
  EXPECT_EQ(tif.status, 0) << tif.output;
  fs::remove_all(dir);
}

// `build` writes a patch list, and names it so: an .obj (or any name but .stp) is refused with
// what a .stp is, before the surface is built.
TEST(Usability, BuildRefusesANameThatIsNotAPatchList) {
  const fs::path dir = freshDirectory("build");
  for (const std::string name : {"x.obj", "x.ply", "x"}) {
    const Result r = runTool("build " + kCrambin + " -o " + (dir / name).string());
    EXPECT_EQ(r.status, 1) << name << "\n" << r.output;
    EXPECT_TRUE(says(r, "`build` writes a patch list (.stp), SurfTrace's own file of the surface's analytic patches"))
        << r.output;
    EXPECT_TRUE(says(r, "Name it " + (dir / "x.stp").string())) << r.output;
    EXPECT_FALSE(says(r, "built")) << r.output;
    EXPECT_FALSE(fs::exists(dir / name)) << name;
  }
  const Result upper = runTool("build " + kCrambin + " -o " + (dir / "X.STP").string());
  EXPECT_EQ(upper.status, 0) << upper.output;
  EXPECT_TRUE(fs::is_regular_file(dir / "X.STP"));
  fs::remove_all(dir);
}

// --colour (the README's spelling) and every other option spelt with colour are the options
// spelt with color: the image records the colouring asked for, and compare's limit applies.
TEST(Usability, BritishSpellingsAreTheSameOptions) {
  const fs::path dir = freshDirectory("colour");
  const std::string british = (dir / "british.exr").string(), american = (dir / "american.exr").string();
  const Result r = runTool("render " + kCrambin + " --size 64x64 --quiet --colour uniform --uniform-colour 0.2,0.4,0.6 "
                           "--silhouettes --silhouette-colour=1,0,0 --exr " + british);
  ASSERT_EQ(r.status, 0) << r.output;
  ASSERT_EQ(runTool("render " + kCrambin + " --size 64x64 --quiet --color uniform --uniform-color 0.2,0.4,0.6 "
                    "--silhouettes --silhouette-color=1,0,0 --exr " + american)
                .status,
            0);
  view::ImageMetadata meta;
  const view::FrameBuffers a = view::readExr(british, &meta), b = view::readExr(american);
  EXPECT_EQ(meta.at("surftrace:color"), "uniform");
  EXPECT_TRUE(a.rgba == b.rgba) << "--colour and --color gave different images";
  // A covered pixel is the uniform colour, shaded: blue above red, as 0.2,0.4,0.6 is.
  bool sawUniform = false;
  for (std::size_t p = 0; p < a.pixels(); ++p)
    if (a.kind[p] != 0 && a.rgba[4 * p + 2] > a.rgba[4 * p] + 0.1f) sawUniform = true;
  EXPECT_TRUE(sawUniform);
  // (64x64: at 32x32 the seams mask every pixel, and a limit over no pixels fails.)
  const Result compare = runTool("compare " + british + " " + american + " --max-colour-p99 0.5");
  EXPECT_EQ(compare.status, 0) << compare.output;
  fs::remove_all(dir);
}

// -V is --version, in both programs (`surftrace` answers it alone when the image program is
// missing; through it, surftrace_images answers).
TEST(Usability, DashCapitalVIsTheVersion) {
  const Result v = runTool("-V"), version = runTool("--version");
  EXPECT_EQ(v.status, 0) << v.output;
  EXPECT_EQ(v.output, version.output);
  EXPECT_EQ(v.output.rfind("surftrace ", 0), 0u) << v.output;
}

// A mistyped option or command is answered with the nearest names, in the program that runs it
// (area runs in `surftrace` itself, render in surftrace_images).
TEST(Usability, MistypedOptionsAndCommandsGetASuggestion) {
  const fs::path dir = freshDirectory("typo");
  const std::string png = (dir / "x.png").string();
  struct Case {
    std::string args, mustSay;
  };
  const Case cases[] = {
      {"render " + kCrambin + " --szie 64x64 -o " + png, "unknown option --szie; did you mean --size?"},
      {"render " + kCrambin + " --size=64x64 --shadow -o " + png, "unknown option --shadow; did you mean --shadows?"},
      {"render " + kCrambin + " --colr chain -o " + png, "unknown option --colr; did you mean --color?"},
      {"area " + kCrambin + " --prboe 1.4", "unknown option --prboe; did you mean --probe?"},
      {"trajectory " + kPsf + " " + kDcd + " --frame 0:4 -o " + png, "unknown option --frame; did you mean --frames?"},
      {"render " + kCrambin + " --depth-dark -o " + png,
       "unknown option --depth-dark; did you mean --depth-darkening, --depth-darkening-sigma, "
       "--depth-darkening-sigma-px, --depth-darkening-strength or --depth-darkening-range?"},
      {"rendr " + kCrambin + " -o " + png, "unknown command rendr; did you mean render?"},
      {"aera " + kCrambin, "unknown command aera; did you mean area?"},
  };
  for (const Case& c : cases) {
    const Result r = runTool(c.args);
    EXPECT_EQ(r.status, 1) << c.args << "\n" << r.output;
    EXPECT_TRUE(says(r, c.mustSay)) << c.args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(png)) << c.args;
  }
  // Nothing near: said so, with where the options are listed.
  const Result far = runTool("render " + kCrambin + " --frobnicate -o " + png);
  EXPECT_EQ(far.status, 1) << far.output;
  EXPECT_TRUE(says(far, "unknown option --frobnicate (`surftrace render --help` lists the options)")) << far.output;
  fs::remove_all(dir);
}

// --spp N takes a k×k grid, k = ceil(sqrt(N)): the summary counts the samples taken (2 takes 4,
// 5 takes 9), and the images say the same: --spp 2 is --spp 4 bit for bit, --spp 5 is --spp 9,
// and both differ from the single centre sample.
TEST(Usability, SppCountsTheSamplesItTakes) {
  const fs::path dir = freshDirectory("spp");
  const auto render = [&](int spp) {
    const std::string exr = (dir / ("spp" + std::to_string(spp) + ".exr")).string();
    const Result r = runTool("render " + kCrambin + " --size 48x40 --quiet --spp " + std::to_string(spp) + " --exr " + exr);
    EXPECT_EQ(r.status, 0) << r.output;
    return std::pair{r, view::readExr(exr)};
  };
  const auto [one, image1] = render(1);
  const auto [two, image2] = render(2);
  const auto [four, image4] = render(4);
  const auto [five, image5] = render(5);
  const auto [nine, image9] = render(9);
  EXPECT_TRUE(says(one, "48x40, 1 sample a pixel,")) << one.output;
  EXPECT_TRUE(says(two, "48x40, 4 samples a pixel (2x2),")) << two.output;
  EXPECT_TRUE(says(four, "48x40, 4 samples a pixel (2x2),")) << four.output;
  EXPECT_TRUE(says(five, "48x40, 9 samples a pixel (3x3),")) << five.output;
  EXPECT_TRUE(says(nine, "48x40, 9 samples a pixel (3x3),")) << nine.output;
  EXPECT_FALSE(says(two, "2 spp")) << two.output;
  EXPECT_TRUE(image2.rgba == image4.rgba);
  EXPECT_TRUE(image5.rgba == image9.rgba);
  EXPECT_FALSE(image1.rgba == image2.rgba);
  EXPECT_FALSE(image4.rgba == image9.rgba);
  const Result help = runTool("render --help");
  EXPECT_TRUE(says(help, "2 to 4 take 2×2 = 4 samples")) << help.output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace surftrace::tools::test
