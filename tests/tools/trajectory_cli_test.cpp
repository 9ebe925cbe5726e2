// `surftrace trajectory` and `surftrace area TOP TRAJ` end to end, on the AdK DIMS trajectory
// (3341 atoms, 98 frames, CHARMM DCD with a PSF topology). The oracle of every frame is an
// independent `surftrace render` of that frame alone (its own process, a fresh build, no
// builder reuse, no pipeline) with the camera the trajectory wrote into the frame's metadata.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "frame_buffers_equal.hpp"
#include "oracles/srgb.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/camera.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools::test {
namespace {

namespace fs = std::filesystem;

const std::string kData = SURFTRACE_TEST_DATA;
const std::string kPsf = kData + "/trajectories/adk_dims/adk.psf.gz";
const std::string kDcd = kData + "/trajectories/adk_dims/adk_dims.dcd";

fs::path freshDirectory(const std::string& name) { return ::surftrace::test::freshTempDir(name); }

std::string vec(const glm::dvec3& v) {
  std::ostringstream out;
  out.precision(17);
  out << v.x << ',' << v.y << ',' << v.z;
  return out.str();
}

std::string bytesOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

using ::surftrace::test::expectSameBuffers;  // frame_buffers_equal.hpp

// Renders `frames` (a --frames text) with `options` and checks each frame against an independent
// `render` of that frame with the trajectory's camera; returns the frames written.
std::size_t checkAgainstIndependentRenders(const std::string& name, const std::string& options, std::size_t stride) {
  const fs::path dir = freshDirectory(name);
  const Result run = runTool("trajectory " + kPsf + " " + kDcd + " --exr " + (dir / "%05d.exr").string() +
                             " --size 40x32 --quiet " + options);
  EXPECT_EQ(run.status, 0) << run.output;
  std::size_t checked = 0, written = 0;
  for (std::size_t k = 0; k < 98; ++k) {
    char file[32];
    std::snprintf(file, sizeof file, "%05zu.exr", k);
    if (!fs::exists(dir / file)) continue;
    ++written;
    if (k % stride != 0) continue;
    view::ImageMetadata meta;
    const view::FrameBuffers frame = view::readExr((dir / file).string(), &meta);
    EXPECT_EQ(meta.at("surftrace:frame"), std::to_string(k));
    const view::Camera camera = view::cameraFromJson(meta.at("surftrace:camera"));
    const fs::path alone = dir / ("alone_" + std::string(file));
    std::ostringstream fov;
    fov.precision(17);
    fov << camera.fovY;
    const Result r = runTool("render " + kPsf + " --trajectory " + kDcd + " --frame " + std::to_string(k) +
                             " --size 40x32 --quiet --eye " + vec(camera.eye) + " --look-at " + vec(camera.lookAt) +
                             " --up " + vec(camera.up) + " --fov " + fov.str() + " --exr " + alone.string() + " " +
                             options.substr(0, options.find(" --frames")));
    EXPECT_EQ(r.status, 0) << r.output;
    if (r.status != 0) break;
    expectSameBuffers(frame, view::readExr(alone.string()), name + " frame " + std::to_string(k));
    ++checked;
  }
  EXPECT_GT(checked, 0u);
  fs::remove_all(dir);
  return written;
}

TEST(TrajectoryCli, EveryFrameOfAdkEqualsAnIndependentRender) {
  // All 98 frames, each against its own process (the "done" criterion).
  EXPECT_EQ(checkAgainstIndependentRenders("adk_ses", "", 1), 98u);
}

// The frames' PNGs (zlib level 1, encoded and written in parallel) hold each frame's own
// colours: those of the EXR written for the same frame, clamped, sRGB-encoded and rounded to
// 8 bits as every PNG is (the EXRs are checked against independent renders above).
TEST(TrajectoryCli, FastPngFramesHoldTheirFramesColours) {
  const fs::path dir = freshDirectory("png_level");
  const Result run = runTool("trajectory " + kPsf + " " + kDcd + " --frames 0:98:16 --size 48x40 --quiet -o " +
                             (dir / "%05d.png").string() + " --exr " + (dir / "%05d.exr").string());
  ASSERT_EQ(run.status, 0) << run.output;
  std::size_t checked = 0;
  for (std::size_t k = 0; k < 98; k += 16) {
    char name[32];
    std::snprintf(name, sizeof name, "%05zu", k);
    view::ImageMetadata meta;
    const view::FrameBuffers frame = view::readExr((dir / (std::string(name) + ".exr")).string(), &meta);
    EXPECT_EQ(meta.at("surftrace:frame"), std::to_string(k));
    auto in = OIIO::ImageInput::open((dir / (std::string(name) + ".png")).string());
    ASSERT_TRUE(in) << name;
    EXPECT_EQ(in->spec().get_string_attribute("surftrace:frame"), std::to_string(k));
    std::vector<unsigned char> px(3 * frame.pixels());
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data()));
    std::size_t wrong = 0;
    for (std::size_t p = 0; p < frame.pixels(); ++p)
      for (int c = 0; c < 3; ++c)
        wrong += px[3 * p + c] != ::surftrace::test::srgbCode(frame.rgba[4 * p + c]);
    EXPECT_EQ(wrong, 0u) << "frame " << k;
    ++checked;
  }
  EXPECT_EQ(checked, 7u);
  fs::remove_all(dir);
}

TEST(TrajectoryCli, SkinFramesEqualIndependentRenders) {
  EXPECT_EQ(checkAgainstIndependentRenders("adk_mss", "--surface mss --shrink 0.5 --frames 0:98:12", 1), 9u);
}

TEST(TrajectoryCli, ShardsTogetherAreTheSingleRunEachFrameOnce) {
  const fs::path dir = freshDirectory("shards");
  const std::string common = "trajectory " + kPsf + " " + kDcd + " --frames 3:40 --size 32x32 --quiet --exr ";
  ASSERT_EQ(runTool(common + (dir / "single/%03d.exr").string()).status, 0);
  std::map<std::string, int> seen;
  for (int i = 0; i < 4; ++i) {
    const fs::path part = dir / ("shard" + std::to_string(i));
    const Result r = runTool(common + (part / "%03d.exr").string() + " --shard " + std::to_string(i) + "/4");
    ASSERT_EQ(r.status, 0) << r.output;
    ASSERT_TRUE(fs::is_directory(part)) << r.output;
    for (const auto& f : fs::directory_iterator(part)) {
      const std::string name = f.path().filename().string();
      ++seen[name];
      // Frame k is the (k - 3)-th selected frame: (k - 3) mod 4 = i for each frame this shard wrote.
      EXPECT_EQ((std::stoi(name) - 3) % 4, i) << name;
      // The same pixels and buffers (the files' metadata differ: each records its command line).
      expectSameBuffers(view::readExr(f.path().string()), view::readExr((dir / "single" / name).string()), name);
    }
  }
  std::set<std::string> single;
  for (const auto& f : fs::directory_iterator(dir / "single")) single.insert(f.path().filename().string());
  EXPECT_EQ(single.size(), 37u);  // 3, 4, ..., 39
  EXPECT_EQ(seen.size(), single.size());
  for (const auto& [name, count] : seen) EXPECT_EQ(count, 1) << name << " written by " << count << " shards";

  // A Slurm array task chooses its shard from the environment.
  const fs::path slurm = dir / "slurm";
  const std::string env = "SLURM_ARRAY_TASK_ID=7 SLURM_ARRAY_TASK_MIN=5 SLURM_ARRAY_TASK_COUNT=4 ";
  const std::string cmd = env + SURFTRACE_TOOL + std::string(" trajectory ") + kPsf + " " + kDcd +
                          " --frames 3:40 --size 32x32 --quiet -o " + (slurm / "%03d.png").string() + " > /dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::size_t frames = 0;
  for (const auto& f : fs::directory_iterator(slurm)) {
    EXPECT_EQ((std::stoi(f.path().filename().string()) - 3) % 4, 2);
    ++frames;
  }
  EXPECT_EQ(frames, 9u);  // 5, 9, ..., 37
  fs::remove_all(dir);
}

// The frames a run wrote, by number.
std::set<int> framesIn(const fs::path& dir) {
  std::set<int> frames;
  if (fs::is_directory(dir))
    for (const auto& f : fs::directory_iterator(dir)) frames.insert(std::stoi(f.path().filename().string()));
  return frames;
}

TEST(TrajectoryCli, ShardsShareOutTheSelectedFrames) {
  // --frames 0:40:4 selects 0, 4, ..., 36, all multiples of 4: sharding by frame number would
  // give shard 0 every frame and shards 1 to 3 none. The i-th selected frame goes to shard i mod 4.
  const fs::path dir = freshDirectory("shard_selection");
  const std::string common = "trajectory " + kPsf + " " + kDcd + " --frames 0:40:4 --size 16x16 --quiet -o ";
  const std::set<int> want[4] = {{0, 16, 32}, {4, 20, 36}, {8, 24}, {12, 28}};
  std::multiset<int> all;
  for (int i = 0; i < 4; ++i) {
    const fs::path part = dir / ("shard" + std::to_string(i));
    const Result r = runTool(common + (part / "%03d.png").string() + " --shard " + std::to_string(i) + "/4");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(framesIn(part), want[i]) << "shard " << i << ": " << r.output;
    for (int k : framesIn(part)) all.insert(k);
  }
  EXPECT_EQ(all, (std::multiset<int>{0, 4, 8, 12, 16, 20, 24, 28, 32, 36}));

  // A shard whose turn never comes (2 selected frames, 4 shards) says so, writes nothing and succeeds.
  const Result r = runTool("trajectory " + kPsf + " " + kDcd + " --frames 0:8:4 --size 16x16 --quiet -o " +
                           (dir / "none/%03d.png").string() + " --shard 3/4");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("--shard 3/4: no frames to render: 2 frames are selected"), std::string::npos) << r.output;
  EXPECT_TRUE(framesIn(dir / "none").empty());
  fs::remove_all(dir);
}

// What the frames of a run cover together: no frame's molecule touches the image border (none is
// clipped), and the union of their coverage (alpha > 0) spans, along the larger axis of its
// bounding rectangle, this fraction of the image's extent along that axis.
struct Coverage {
  int frames = 0;
  std::vector<std::string> clipped;  // frames that touch the border
  double span = 0.0;
  std::set<std::string> cameras;     // surftrace:camera of each frame
};

Coverage coverageOf(const fs::path& dir) {
  Coverage c;
  int x0 = INT_MAX, y0 = INT_MAX, x1 = -1, y1 = -1, width = 0, height = 0;
  for (const auto& f : fs::directory_iterator(dir)) {
    view::ImageMetadata meta;
    const view::FrameBuffers image = view::readExr(f.path().string(), &meta);
    c.cameras.insert(meta.at("surftrace:camera"));
    width = image.width, height = image.height;
    bool touches = false;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) {
        if (!(image.rgba[4 * (static_cast<std::size_t>(y) * image.width + x) + 3] > 0.0f)) continue;
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        touches = touches || x == 0 || y == 0 || x == image.width - 1 || y == image.height - 1;
      }
    if (touches) c.clipped.push_back(f.path().filename().string());
    ++c.frames;
  }
  if (x1 >= 0)
    c.span = std::max(static_cast<double>(x1 - x0 + 1) / width, static_cast<double>(y1 - y0 + 1) / height);
  return c;
}

// AdK opens from closed to open over the 98 frames. The default camera keeps every selected frame
// whole and, with the margin of a single-frame `render`, fills the picture: the frames together
// span at least 75 % of it (0.875 here). Framed on the first frame, the open frames are clipped.
TEST(TrajectoryCli, DefaultCameraKeepsEveryFrameWholeAndFillsThePicture) {
  const fs::path dir = freshDirectory("framing");
  const std::string common = "trajectory " + kPsf + " " + kDcd + " --frames 0:98:7 --size 64x64 --quiet --exr ";
  const Result r = runTool(common + (dir / "all/%02d.exr").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const Coverage all = coverageOf(dir / "all");
  EXPECT_EQ(all.frames, 14);
  EXPECT_TRUE(all.clipped.empty()) << "clipped: " << ::testing::PrintToString(all.clipped);
  EXPECT_GE(all.span, 0.75);
  EXPECT_EQ(all.cameras.size(), 1u);
  std::printf("[ framing  ] every frame: span %.3f, %zu clipped\n", all.span, all.clipped.size());

  // Each shard frames all the selected frames, not only its own: the same camera, no messages.
  for (const char* shard : {"0/3", "2/3"}) {
    const fs::path part = dir / ("shard" + std::string(1, shard[0]));
    const Result s = runTool(common + (part / "%02d.exr").string() + " --shard " + shard);
    ASSERT_EQ(s.status, 0) << s.output;
    EXPECT_EQ(coverageOf(part).cameras, all.cameras) << shard;
  }

  // `first` frames the first selected frame only, which the opening protein outgrows.
  ASSERT_EQ(runTool(common + (dir / "first/%02d.exr").string() + " --frame-camera first").status, 0);
  const Coverage first = coverageOf(dir / "first");
  std::printf("[ framing  ] first frame: span %.3f, %zu clipped\n", first.span, first.clipped.size());
  EXPECT_FALSE(first.clipped.empty());
  fs::remove_all(dir);
}

// Crambin drifting 12 Å a frame towards the camera (the default view looks along −z) for 8 frames,
// a multi-model PDB over the atoms of tests/data/structures/1crn.pdb. Each atom travels 84 Å: the
// former `all` framing, which grew every atom by half its path, shrank the molecule to 4 % of the
// pixels (a span of 0.28), and the first frame's camera clips the nearer ones.
TEST(TrajectoryCli, DefaultCameraFollowsAMoleculeMovingAlongTheView) {
  const fs::path dir = freshDirectory("framing_drift");
  const std::string pdb = kData + "/structures/1crn.pdb";
  std::vector<std::string> atoms;
  std::ifstream in(pdb);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("ATOM", 0) == 0 || line.rfind("HETATM", 0) == 0) atoms.push_back(line);
  ASSERT_FALSE(atoms.empty());
  std::ofstream out(dir / "drift.pdb");
  for (int k = 0; k < 8; ++k) {
    char record[96];
    std::snprintf(record, sizeof record, "MODEL     %4d\n", k + 1);
    out << record;
    for (const std::string& line : atoms) {
      const double z = std::stod(line.substr(46, 8)) + 12.0 * k;
      std::snprintf(record, sizeof record, "%8.3f", z);
      out << line.substr(0, 46) << record << line.substr(54) << '\n';
    }
    out << "ENDMDL\n";
  }
  out << "END\n";
  out.close();
  const std::string common = "trajectory " + pdb + " " + (dir / "drift.pdb").string() + " --size 64x64 --quiet --exr ";
  const Result r = runTool(common + (dir / "all/%02d.exr").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const Coverage all = coverageOf(dir / "all");
  EXPECT_EQ(all.frames, 8);
  EXPECT_TRUE(all.clipped.empty()) << "clipped: " << ::testing::PrintToString(all.clipped);
  EXPECT_GE(all.span, 0.75);
  std::printf("[ framing  ] every frame: span %.3f, %zu clipped\n", all.span, all.clipped.size());
  ASSERT_EQ(runTool(common + (dir / "first/%02d.exr").string() + " --frame-camera first").status, 0);
  const Coverage first = coverageOf(dir / "first");
  std::printf("[ framing  ] first frame: span %.3f, %zu clipped\n", first.span, first.clipped.size());
  EXPECT_FALSE(first.clipped.empty());
  fs::remove_all(dir);
}

// The skin of a trajectory at a small shrink factor fills the picture too: every atom reaches
// the largest radius (the skin lies in the centres' hull grown by it), not r/√s (4.5 r at
// s = 0.05: span 0.771 of the picture, against 0.917 now; 10 r at s = 0.01).
TEST(TrajectoryCli, WideSkinFramesFillThePicture) {
  const fs::path dir = freshDirectory("wide_skin");
  const Result r = runTool("trajectory " + kPsf + " " + kDcd + " --surface mss --shrink 0.05 --frames 0:98:48 --size 48x48 "
                           "--quiet --exr " + (dir / "%02d.exr").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const Coverage c = coverageOf(dir);
  EXPECT_EQ(c.frames, 3);
  EXPECT_TRUE(c.clipped.empty()) << "clipped: " << ::testing::PrintToString(c.clipped);
  EXPECT_GE(c.span, 0.85);
  std::printf("[ framing  ] skin s = 0.05, every frame: span %.3f\n", c.span);
  fs::remove_all(dir);
}

TEST(TrajectoryCli, ResumeRendersOnlyWhatIsMissing) {
  const fs::path dir = freshDirectory("resume");
  const std::string cmd = "trajectory " + kPsf + " " + kDcd + " --frames 0:6 --size 24x24 --quiet -o " +
                          (dir / "%02d.png").string() + " --timings " + (dir / "t.csv").string();
  ASSERT_EQ(runTool(cmd).status, 0);
  const std::string kept = bytesOf(dir / "02.png");  // the same command: the same bytes
  fs::remove(dir / "01.png");
  fs::remove(dir / "04.png");
  const Result r = runTool(cmd + " --resume");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("2 to render, 4 done already"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(dir / "01.png") && fs::exists(dir / "04.png"));
  EXPECT_EQ(bytesOf(dir / "02.png"), kept);
  // The timings keep the first run's rows and add this run's (--resume appends, issue 18).
  std::ifstream csv(dir / "t.csv");
  std::string header, row;
  std::getline(csv, header);
  EXPECT_EQ(header, "frame,time_ps,read_ms,build_ms,scene_ms,render_ms,encode_ms,write_ms,moved_atoms,recomputed_atoms,"
                    "patches");
  std::multiset<int> rows;
  while (std::getline(csv, row)) rows.insert(std::stoi(row));
  EXPECT_EQ(rows, (std::multiset<int>{0, 1, 1, 2, 3, 4, 4, 5}));
  // No half-written files are left behind.
  for (const auto& f : fs::directory_iterator(dir)) EXPECT_EQ(f.path().filename().string().find(".partial"), std::string::npos);
  fs::remove_all(dir);
}

// What a command wrote to stdout, without the notes it gave on stderr (runTool captures both).
std::string withoutNotes(const std::string& output) {
  std::istringstream in(output);
  std::string out;
  for (std::string line; std::getline(in, line);)
    if (line.rfind("surftrace: note:", 0) != 0) out += line + "\n";
  return out;
}

TEST(TrajectoryCli, AreasOverTimeOneRowPerFrame) {
  const Result r = runTool("area " + kPsf + " " + kDcd + " --frames 0:98:24 --format csv");
  ASSERT_EQ(r.status, 0) << r.output;
  std::istringstream in(withoutNotes(r.output));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "frame,time_ps,sas,ses,ses_convex,ses_toroidal,ses_concave,ses_volume");
  int rows = 0;
  while (std::getline(in, line)) {
    double v[8];
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5],
                          &v[6], &v[7]),
              8)
        << line;
    EXPECT_EQ(v[0], 24.0 * rows);
    // The SES by kind adds up, and lies between the SAS (an upper bound) and nothing.
    EXPECT_NEAR(v[4] + v[5] + v[6], v[3], 1e-5 * v[3]);
    EXPECT_GT(v[3], 0.0);
    EXPECT_LT(v[3], v[2]);
    // Each row (a builder updated frame after frame) equals that frame alone (a fresh build).
    const Result alone = runTool("area " + kPsf + " " + kDcd + " --format csv --frames " + std::to_string(24 * rows));
    ASSERT_EQ(alone.status, 0) << alone.output;
    const std::string single = withoutNotes(alone.output);
    EXPECT_EQ(single.substr(single.find('\n') + 1), line + "\n");
    ++rows;
  }
  EXPECT_EQ(rows, 5);
}

TEST(TrajectoryCli, BadInputIsAClearError) {
  const std::string sample = kData + "/trajectories/sampletrajectory/sampletrajectory.dcd";
  // Output names in a folder of the test's own, though no frame is written.
  const std::string x = (::surftrace::test::testTempDir() / "x").string();
  Result r = runTool("trajectory " + kPsf + " " + sample + " -o " + x + "/%d.png");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("115 atoms per frame"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("3341"), std::string::npos) << r.output;
  r = runTool("trajectory " + kPsf + " " + kDcd + " -o " + x + "/frame.png");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("no conversion for the frame number"), std::string::npos) << r.output;
  r = runTool("trajectory " + kPsf + " " + kDcd + " -o " + x + "/%d_%d.png");
  EXPECT_NE(r.output.find("more than one conversion"), std::string::npos) << r.output;
  r = runTool("trajectory " + kPsf + " " + kDcd + " -o " + x + "/%s.png");
  EXPECT_NE(r.output.find("'%s' is not %d"), std::string::npos) << r.output;
  r = runTool("trajectory " + kPsf + " " + kDcd + " -o " + x + "/%d.png --frames 100:");
  EXPECT_NE(r.output.find("frame 100 does not exist: the trajectory holds frames 0 to 97"), std::string::npos) << r.output;
  r = runTool("trajectory " + kPsf + " " + kDcd + " -o " + x + "/%d.png --frames 0:10:0");
  EXPECT_NE(r.output.find("the step must be at least 1"), std::string::npos) << r.output;
  r = runTool("trajectory " + kPsf + " " + kDcd + " -o " + x + "/%d.png --shard 4/4");
  EXPECT_NE(r.output.find("expected i/n with 0 <= i < n"), std::string::npos) << r.output;
  r = runTool("trajectory " + kPsf + " " + kDcd + " -o " + x + "/%d.png --flexible 'resid 900-999'");
  EXPECT_NE(r.output.find("selects no atom (the molecule has residues 1 to 214)"), std::string::npos) << r.output;
  // An empty selection selects no atom either (it used to move every atom, with no note).
  for (const char* empty : {"''", "' '"}) {
    r = runTool("trajectory " + kPsf + " " + kDcd + " -o " + x + "/%d.png --flexible " + empty);
    EXPECT_EQ(r.status, 1) << empty;
    EXPECT_NE(r.output.find("--flexible " + std::string(empty) + " (atoms of " + kPsf + "): the atom selection is empty; "
                            "leave --flexible out to move every atom"),
              std::string::npos)
        << r.output;
  }
  r = runTool("trajectory " + kPsf + " " + kDcd + " -o " + x + "/%d.png --flexible 'residue 9'");
  EXPECT_NE(r.output.find("unknown keyword 'residue'"), std::string::npos) << r.output;
  r = runTool("trajectory " + kPsf + " " + kDcd + " -o " + x + "/%d.png --flexible 'resname ALA adn name CA'");
  EXPECT_NE(r.output.find("at word 4 'name': needs 'and' or 'or' before it"), std::string::npos) << r.output;
  r = runTool("trajectory " + kPsf + " " + kDcd + " -o " + x + "/%d.png --flexible 'atom 3000-3400'");
  EXPECT_NE(r.output.find("atom 3000-3400: the topology has 3341 atoms"), std::string::npos) << r.output;
  r = runTool("trajectory " + kPsf + " " + kDcd);
  EXPECT_NE(r.output.find("nothing to write"), std::string::npos) << r.output;
  r = runTool("render " + kPsf + " -o " + x + ".png");
  EXPECT_NE(r.output.find("a PSF is a topology without coordinates"), std::string::npos) << r.output;
  r = runTool("render " + kDcd + " -o " + x + ".png");
  EXPECT_NE(r.output.find("is a trajectory (.dcd)"), std::string::npos) << r.output;
  const std::string cmd = std::string("SLURM_ARRAY_TASK_ID=x SLURM_ARRAY_TASK_COUNT=4 ") + SURFTRACE_TOOL +
                          " trajectory " + kPsf + " " + kDcd + " -o " + x + "/%d.png 2>&1 | grep -q \"SLURM_ARRAY_TASK_ID='x'\"";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
}

}  // namespace
}  // namespace surftrace::tools::test
