// `cmake --install BUILD --prefix P` puts `surftrace` in P/bin and the program it hands the image
// commands to in P/libexec/surftrace, where `surftrace` finds it from its own location: the
// installed tree renders as the build tree does, moved as a whole too, and through a symbolic
// link on PATH. The oracle is the build tree's own program, run on the same command line.
#include <filesystem>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>

#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools::test {
namespace {

namespace fs = std::filesystem;

const std::string kCrambin = std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb";

fs::path freshDirectory(const std::string& name) {
  return ::surftrace::test::freshTempDir(name);
}

// 'path', for a shell. (Built with +=: GCC 12 warns, wrongly, of an overlapping copy in
// "literal" + std::string&&, -Wrestrict.)
std::string quoted(const fs::path& path) {
  std::string text = "'";
  text += path.string();
  text += "'";
  return text;
}

// `program render 1crn.pdb` at 64x48 with `engine`, to out.png and out.exr in `dir`.
Result renderWith(const std::string& program, const fs::path& dir, const std::string& engine) {
  std::string line = "cd ";
  line += quoted(dir);
  line += " && " + program + " render " + kCrambin + " --size 64x48 --quiet --engine " + engine +
          " -o out.png --exr out.exr 2>&1";
  return runShell(line);
}

// The PNG's size and pixels (8-bit RGB as `render` writes it).
struct Png {
  int width = 0, height = 0, channels = 0;
  std::vector<unsigned char> pixels;
};
Png readPng(const fs::path& path) {
  Png png;
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return png;
  png.width = in->spec().width;
  png.height = in->spec().height;
  png.channels = in->spec().nchannels;
  png.pixels.resize(static_cast<std::size_t>(png.width) * png.height * png.channels);
  if (!in->read_image(0, 0, 0, png.channels, OIIO::TypeDesc::UINT8, png.pixels.data())) png.pixels.clear();
  return png;
}

// The installed program's images against the build tree's: the PNG's pixels and every EXR
// buffer bit for bit (the metadata differs: it records the command line, the program's path).
void expectSameRender(const fs::path& installed, const fs::path& built, const std::string& what) {
  const Png a = readPng(installed / "out.png"), b = readPng(built / "out.png");
  EXPECT_EQ(a.width, 64) << what;
  EXPECT_EQ(a.height, 48) << what;
  EXPECT_EQ(a.channels, 3) << what;
  ASSERT_FALSE(a.pixels.empty()) << what << ": " << installed / "out.png" << " does not read";
  EXPECT_TRUE(a.pixels == b.pixels) << what << ": the PNGs differ";
  // Not a blank picture: the surface covers part of it, the white background the rest.
  std::size_t background = 0;
  for (std::size_t p = 0; p < a.pixels.size(); p += 3)
    background += a.pixels[p] == 255 && a.pixels[p + 1] == 255 && a.pixels[p + 2] == 255;
  EXPECT_GT(background, 0u) << what;
  EXPECT_LT(background, a.pixels.size() / 3) << what;
  const view::FrameBuffers x = view::readExr((installed / "out.exr").string());
  const view::FrameBuffers y = view::readExr((built / "out.exr").string());
  EXPECT_TRUE(x.rgba == y.rgba && x.depth == y.depth && x.normal == y.normal && x.kind == y.kind &&
              x.patchId == y.patchId)
      << what << ": the EXR buffers differ";
}

TEST(Install, InstalledProgramsRenderFromTheirPrefix) {
  const fs::path dir = freshDirectory("prefix");
  const fs::path prefix = dir / "prefix";
  std::string installLine = "'" SURFTRACE_CMAKE_COMMAND "' --install '" SURFTRACE_BINARY_DIR "' --prefix ";
  installLine += quoted(prefix);
  installLine += " 2>&1";
  const Result install = runShell(installLine);
  ASSERT_EQ(install.status, 0) << install.output;
  // The layout: the command users type on PATH, the program it runs out of the way.
  EXPECT_TRUE(fs::is_regular_file(prefix / "bin" / "surftrace")) << install.output;
  EXPECT_TRUE(fs::is_regular_file(prefix / "libexec" / "surftrace" / "surftrace_images")) << install.output;
  EXPECT_FALSE(fs::exists(prefix / "bin" / "surftrace_images")) << install.output;

  // Both engines: the GL shaders are compiled into the program, nothing is read at run time.
  for (const std::string engine : {"embree", "gl"}) {
    const fs::path built = dir / ("built_" + engine), work = dir / ("installed_" + engine);
    fs::create_directories(built);
    fs::create_directories(work);
    const Result tree = renderWith(quoted(SURFTRACE_TOOL), built, engine);
    ASSERT_EQ(tree.status, 0) << tree.output;
    const Result r = renderWith(quoted(prefix / "bin" / "surftrace"), work, engine);
    ASSERT_EQ(r.status, 0) << r.output;
    expectSameRender(work, built, "installed, engine " + engine);
  }

  // Moved as a whole, and called through a symbolic link in a folder on PATH.
  const fs::path moved = dir / "moved";
  fs::rename(prefix, moved);
  const fs::path onPath = dir / "path";
  fs::create_directories(onPath);
  fs::create_symlink(moved / "bin" / "surftrace", onPath / "surftrace");
  const fs::path work = dir / "linked";
  fs::create_directories(work);
  std::string linkedProgram = "PATH=";
  linkedProgram += quoted(onPath);
  linkedProgram += ":\"$PATH\" surftrace";
  const Result linked = renderWith(linkedProgram, work, "embree");
  ASSERT_EQ(linked.status, 0) << linked.output;
  expectSameRender(work, dir / "built_embree", "moved, through a link on PATH");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace surftrace::tools::test
