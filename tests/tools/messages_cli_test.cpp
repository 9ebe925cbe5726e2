// Messages that say what went wrong: a file that asks for more memory than there is, an image
// cut short, numbers a reader can read. Each names the file or the value and the reason.
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "run_tool.hpp"
#include "temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using surftrace::tools::test::Result;

std::string data(const std::string& file) { return std::string(SURFTRACE_TEST_DATA) + "/" + file; }

Result shell(const std::string& script) {
  return surftrace::tools::test::runShell("bash -c 'surftrace() { \"" SURFTRACE_TOOL "\" \"$@\"; }; " + script +
                                          "' 2>&1");
}

fs::path folder(const std::string& name) {
  return ::surftrace::test::freshTempDir(name);
}

// A grey PFM whose header says width x height and whose pixels are `bytes` zero bytes.
fs::path pfm(const fs::path& path, int width, int height, std::size_t bytes) {
  std::ofstream out(path, std::ios::binary);
  out << "Pf\n" << width << " " << height << "\n-1.0\n" << std::string(bytes, '\0');
  return path;
}

std::string referenceExr(const fs::path& dir) {
  const std::string exr = (dir / "ref.exr").string();
  const Result r = shell("surftrace render " + data("structures/1crn.pdb") + " --size 32x32 --quiet --exr " + exr);
  EXPECT_EQ(r.status, 0) << r.output;
  return exr;
}

// An image whose header asks for more memory than the process may have (a memory limit below
// its 30000x30000 floats, 3.4 GiB) is an error naming the file and what did not fit, not
// "std::bad_alloc" alone.
TEST(Messages, OutOfMemoryNamesTheFile) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space: a memory limit stops it from starting";
#else
  const fs::path dir = folder("memory");
  const std::string exr = referenceExr(dir);
  const fs::path big = pfm(dir / "big.pfm", 30000, 30000, 64);
  const Result r = shell("ulimit -v 3000000; surftrace compare " + big.string() + " " + exr);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find(big.string() + ": not enough memory to hold the image"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("error: std::bad_alloc"), std::string::npos) << r.output;
#endif
}

// A PFM cut short: OpenImageIO gives no reason, the message gives one (and the sizes).
TEST(Messages, AnImageCutShortSaysSo) {
  const fs::path dir = folder("truncated");
  const std::string exr = referenceExr(dir);
  const fs::path cut = pfm(dir / "d_trunc.pfm", 32, 32, 1000);  // 4096 bytes of pixels promised
  const Result r = shell("surftrace compare " + cut.string() + " " + exr);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(std::regex_search(r.output, std::regex("d_trunc\\.pfm: [a-z]"))) << "no reason after the file name\n"
                                                                               << r.output;
  EXPECT_NE(r.output.find("cut short"), std::string::npos) << r.output;
}

// A camera too far away: near and far in a few digits (%.6g), not std::to_string's thirty,
// and why they collapse.
TEST(Messages, FarCamerasNumbersAreShort) {
  const fs::path dir = folder("far");
  const Result r = shell("surftrace render " + data("structures/1crn.pdb") + " --size 16x16 --eye 1e30,0,0 -o " +
                         (dir / "x.png").string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_FALSE(std::regex_search(r.output, std::regex("[0-9]{12,}"))) << r.output;
  EXPECT_NE(r.output.find("near 1e+30"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bring the eye closer"), std::string::npos) << r.output;
}

}  // namespace
