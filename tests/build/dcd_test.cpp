// Tests of the DCD reader against MDAnalysis (tests/oracles/mda_frames.py), an independent
// implementation: every frame of every file must give the same atoms, positions (the same
// float32 values), unit cell and time. Broken files are made here from good ones.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "build/io/error.hpp"
#include "build/io/trajectory.hpp"
#include "oracles/python_oracle.hpp"
#include "temp_dir.hpp"

namespace surftrace::build {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using Bytes = std::string;

fs::path data(const std::string& relative) { return fs::path(SURFTRACE_TEST_DATA) / relative; }

Bytes readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void writeBytes(const fs::path& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

// A fresh directory for one test's files.
fs::path tempDir() { return ::surftrace::test::freshTempDir("files"); }

// ---------------------------------------------------------------------------------------------
// The file's records, found by the test itself (Fortran unformatted: marker, payload, marker),
// to know where to cut or corrupt a file without trusting the reader under test.

struct Layout {
  std::size_t markerBytes = 4;
  bool big = false;
  struct Record {
    std::size_t at, length;  // offset of the leading marker; payload length
  };
  std::vector<Record> records;

  std::int64_t value(const Bytes& b, std::size_t at, std::size_t width) const {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < width; ++i)
      v |= std::uint64_t{static_cast<unsigned char>(b[at + (big ? width - 1 - i : i)])} << (8 * i);
    return width == 4 ? std::int64_t{static_cast<std::int32_t>(v)} : static_cast<std::int64_t>(v);
  }
  std::int32_t icntrl(const Bytes& b, int i) const {
    const std::size_t at = markerBytes + 4 + 4 * static_cast<std::size_t>(i);
    return static_cast<std::int32_t>(value(b, at, 4));
  }
  // Records before the first frame: CORD, titles, NATOM, and the free-atom list with NAMNF.
  std::size_t headerRecords(const Bytes& b) const { return icntrl(b, 8) > 0 ? 4 : 3; }
  std::size_t headerBytes(const Bytes& b) const {
    const Record& r = records[headerRecords(b) - 1];
    return r.at + 2 * markerBytes + r.length;
  }
};

Layout layoutOf(const Bytes& b) {
  Layout layout;
  layout.markerBytes = b.compare(8, 4, "CORD") == 0 ? 8 : 4;
  layout.big = layout.value(b, 0, layout.markerBytes) != 84;
  for (std::size_t at = 0; at + layout.markerBytes <= b.size();) {
    const auto length = static_cast<std::size_t>(layout.value(b, at, layout.markerBytes));
    if (at + 2 * layout.markerBytes + length > b.size()) break;
    layout.records.push_back({at, length});
    at += 2 * layout.markerBytes + length;
  }
  return layout;
}

void put32(Bytes& b, std::size_t at, std::uint32_t v, bool big) {
  for (std::size_t i = 0; i < 4; ++i)
    b[at + (big ? 3 - i : i)] = static_cast<char>((v >> (8 * i)) & 0xffu);
}

bool hasFourthDimension(const Bytes& b, const Layout& layout) {
  return layout.icntrl(b, 19) != 0 && layout.icntrl(b, 11) == 1;
}

// The file as MDAnalysis 2.4 reads it correctly. It takes the first 4 bytes as the marker, so
// 64-bit files get 32-bit markers. Its DCDReader reports all-zero positions for CHARMM 4D files
// (DCDFile reads an (N, 4) array of x, y, z, w; Timestep.positions copies it into its (N, 3)
// array with PyArray_CopyInto, which fails on the shape, unchecked), so the 4th coordinate
// records are dropped and the 4D flag cleared. Payloads stay untouched.
Bytes forMDAnalysis(const Bytes& b) {
  const Layout layout = layoutOf(b);
  const bool fourD = hasFourthDimension(b, layout);
  const std::size_t header = layout.headerRecords(b);
  const std::size_t perFrame = (layout.icntrl(b, 10) != 0 ? 1 : 0) + 4;
  Bytes out;
  for (std::size_t i = 0; i < layout.records.size(); ++i) {
    const auto& r = layout.records[i];
    if (fourD && i >= header && (i - header) % perFrame == perFrame - 1) continue;
    Bytes marker(4, '\0');
    put32(marker, 0, static_cast<std::uint32_t>(r.length), layout.big);
    Bytes payload = b.substr(r.at + layout.markerBytes, r.length);
    if (i == 0 && fourD) put32(payload, 4 + 4 * 11, 0, layout.big);
    out += marker;
    out += payload;
    out += marker;
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// The oracle

struct OracleFrame {
  double time = 0;
  bool hasCell = false;
  std::array<double, 6> cell{};
  std::vector<float> xyz;
};
struct Oracle {
  std::int64_t atoms = 0;
  std::vector<OracleFrame> frames;
};

template <typename T>
T little(const Bytes& b, std::size_t at) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i)
    v |= std::uint64_t{static_cast<unsigned char>(b[at + i])} << (8 * i);
  if constexpr (sizeof(T) == 4)
    return std::bit_cast<T>(static_cast<std::uint32_t>(v));
  else
    return std::bit_cast<T>(v);
}

// Runs mda_frames.py on `trajectory` (through forMDAnalysis where that matters) under the
// oracle Python the build chose (tests/oracles/python_oracle.hpp). Exit status 3 means MDAnalysis
// is missing: a failure that says what to install, never a skip.
::testing::AssertionResult runOracle(const fs::path& trajectory, const fs::path& scratch,
                                     Oracle& oracle) {
  fs::path input = trajectory;
  const Bytes bytes = readBytes(trajectory);
  const Layout layout = layoutOf(bytes);
  if (layout.markerBytes == 8 || hasFourthDimension(bytes, layout)) {
    input = scratch / (trajectory.stem().string() + ".for_mda.dcd");
    writeBytes(input, forMDAnalysis(bytes));
  }
  const fs::path dump = scratch / (trajectory.stem().string() + ".mda.bin");
  fs::remove(dump);
  const test::OracleRun run =
      test::runOracleScript("mda_frames.py", {input.string(), dump.string(), "DCD"}, scratch);
  if (run.exitCode == 3)
    return ::testing::AssertionFailure()
           << "MDAnalysis, the oracle of this test, cannot be imported:\n" << run.describe()
           << "\nInstall python3-mdanalysis (apt-get install python3-mdanalysis).";
  if (!run.ok()) return ::testing::AssertionFailure() << run.describe();
  const Bytes b = readBytes(dump);
  if (b.size() < 16) return ::testing::AssertionFailure() << "short oracle dump " << dump;
  oracle.atoms = little<std::int64_t>(b, 0);
  const auto frames = little<std::int64_t>(b, 8);
  const auto atoms = static_cast<std::size_t>(oracle.atoms);
  const std::size_t frameBytes = 8 + 8 + 48 + 12 * atoms;
  if (b.size() != 16 + static_cast<std::size_t>(frames) * frameBytes)
    return ::testing::AssertionFailure() << "oracle dump " << dump << " has " << b.size()
                                         << " bytes, not 16 + " << frames << " frames";
  oracle.frames.resize(static_cast<std::size_t>(frames));
  for (std::size_t k = 0; k < oracle.frames.size(); ++k) {
    const std::size_t at = 16 + k * frameBytes;
    OracleFrame& f = oracle.frames[k];
    f.time = little<double>(b, at);
    f.hasCell = little<std::int64_t>(b, at + 8) != 0;
    for (std::size_t i = 0; i < 6; ++i) f.cell[i] = little<double>(b, at + 16 + 8 * i);
    f.xyz.resize(3 * atoms);
    for (std::size_t i = 0; i < 3 * atoms; ++i) f.xyz[i] = little<float>(b, at + 64 + 4 * i);
  }
  return ::testing::AssertionSuccess();
}

// ---------------------------------------------------------------------------------------------
// Comparison

struct Worst {
  double position = 0;  // |ours - MDAnalysis| over all coordinates, Å
  double cellRelative = 0;
  double time = 0;  // ps
  std::size_t frames = 0;
};

// Frames 0..count-1 of `source` against MDAnalysis: positions bit-equal to its float32 values,
// the cell within 1e-5 relative (MDAnalysis keeps it in float32), the time within 1e-12.
// Not the time of big-endian files: MDAnalysis 2.4.2 (Debian) takes their CHARMM DELTA without
// swapping its bytes (-1.04e-37 for mrmd_h2so4-32bit-be.dcd, whose DELTA is 0.0020455); the
// little-endian copy of that file is compared instead (MarkerWidthsAndByteOrdersAgree).
void expectMatches(FrameSource& source, const Oracle& oracle, std::size_t count,
                   const std::string& label, Worst& worst, bool compareTime = true) {
  ASSERT_EQ(source.atomCount(), static_cast<std::size_t>(oracle.atoms)) << label;
  ASSERT_LE(count, oracle.frames.size()) << label;
  Frame frame;
  for (std::size_t k = 0; k < count; ++k) {
    ASSERT_NO_THROW(source.read(k, frame)) << label << " frame " << k + 1;
    const OracleFrame& want = oracle.frames[k];
    ASSERT_EQ(frame.positions.size(), source.atomCount()) << label;
    std::size_t unequal = 0;
    for (std::size_t i = 0; i < frame.positions.size(); ++i) {
      for (int a = 0; a < 3; ++a) {
        const double ours = frame.positions[i][a];
        const float theirs = want.xyz[3 * i + static_cast<std::size_t>(a)];
        worst.position = std::max(worst.position, std::abs(ours - double{theirs}));
        if (ours != double{theirs} && unequal++ < 3)
          ADD_FAILURE() << label << " frame " << k + 1 << " atom " << i + 1 << " axis " << a
                        << ": " << ours << " vs MDAnalysis " << theirs;
      }
    }
    EXPECT_EQ(unequal, 0u) << label << " frame " << k + 1 << ": unequal coordinates";
    ASSERT_EQ(frame.cell.has_value(), want.hasCell) << label << " frame " << k + 1;
    if (frame.cell) {
      for (std::size_t i = 0; i < 6; ++i) {
        const double rel = std::abs((*frame.cell)[i] - want.cell[i]) / std::abs(want.cell[i]);
        worst.cellRelative = std::max(worst.cellRelative, rel);
        EXPECT_LE(rel, 1e-5) << label << " frame " << k + 1 << " cell[" << i
                             << "]: " << (*frame.cell)[i] << " vs MDAnalysis " << want.cell[i];
      }
    }
    if (compareTime) {
      worst.time = std::max(worst.time, std::abs(frame.time - want.time));
      EXPECT_NEAR(frame.time, want.time, 1e-12 * std::max(1.0, std::abs(want.time)))
          << label << " frame " << k + 1;
    }
    ++worst.frames;
  }
}

void expectSameFrame(const Frame& a, const Frame& b, const std::string& label) {
  ASSERT_EQ(a.positions.size(), b.positions.size()) << label;
  for (std::size_t i = 0; i < a.positions.size(); ++i)
    ASSERT_EQ(a.positions[i], b.positions[i]) << label << " atom " << i + 1;
  EXPECT_EQ(a.cell, b.cell) << label;
  EXPECT_EQ(a.time, b.time) << label;
  EXPECT_EQ(a.step, b.step) << label;
}

// Random access: a fresh reader taking the frames last to first gives what in-order reading gave.
void expectReverseOrderSame(const fs::path& path, const std::string& label) {
  const auto forward = openDcd(path);
  std::vector<Frame> frames(forward->frameCount());
  for (std::size_t k = 0; k < frames.size(); ++k) forward->read(k, frames[k]);
  const auto backward = openDcd(path);
  Frame frame;
  for (std::size_t k = frames.size(); k-- > 0;) {
    backward->read(k, frame);
    expectSameFrame(frame, frames[k],
                    label + " frame " + std::to_string(k + 1) + " read backwards");
  }
}

void compareWithMDAnalysis(const fs::path& path, const fs::path& scratch, Worst& worst) {
  const std::string label = path.filename().string();
  Oracle oracle;
  ASSERT_TRUE(runOracle(path, scratch, oracle)) << label;
  std::unique_ptr<FrameSource> source;
  ASSERT_NO_THROW(source = openDcd(path)) << label;
  EXPECT_EQ(source->frameCount(), oracle.frames.size()) << label;
  const Bytes bytes = readBytes(path);
  const Layout layout = layoutOf(bytes);
  expectMatches(*source, oracle, std::min(source->frameCount(), oracle.frames.size()), label, worst,
                !layout.big);

  // The MD step of each frame, from the header as this test reads it.
  Frame frame;
  for (std::size_t k = 0; k < source->frameCount(); ++k) {
    source->read(k, frame);
    const long long istart = layout.icntrl(bytes, 1), nsavc = layout.icntrl(bytes, 2);
    EXPECT_EQ(frame.step, istart + static_cast<long long>(k) * nsavc)
        << label << " frame " << k + 1;
  }
  expectReverseOrderSame(path, label);
}

// ---------------------------------------------------------------------------------------------

class DcdAgainstMDAnalysis : public ::testing::TestWithParam<const char*> {};

TEST_P(DcdAgainstMDAnalysis, EveryFrameMatches) {
  const fs::path scratch = tempDir();
  Worst worst;
  compareWithMDAnalysis(data(GetParam()), scratch, worst);
  std::cout << "[ dcd      ] " << GetParam() << ": " << worst.frames << " frames, worst |dpos| "
            << worst.position << " A, cell rel " << worst.cellRelative << ", |dt| " << worst.time
            << " ps\n";
  fs::remove_all(scratch);
}

INSTANTIATE_TEST_SUITE_P(
    Files, DcdAgainstMDAnalysis,
    ::testing::Values("formats/dcd/4d-dynamic.dcd", "formats/dcd/fixed-atoms.dcd",
                      "formats/dcd/mrmd_h2so4-32bit-be.dcd", "formats/dcd/mrmd_h2so4-64bit-be.dcd",
                      "formats/dcd/mrmd_h2so4-64bit-le.dcd", "formats/dcd/nopbc.dcd",
                      "formats/dcd/triclinic-namd.dcd", "formats/dcd/triclinic-octane-cos.dcd",
                      "formats/dcd/triclinic-octane-direct.dcd",
                      "formats/dcd/triclinic-octane-vectors.dcd", "trajectories/watdyn/watdyn.dcd",
                      "trajectories/sampletrajectory/sampletrajectory.dcd"),
    [](const ::testing::TestParamInfo<const char*>& param) {
      std::string name = fs::path(param.param).stem().string();
      for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return name;
    });

// The three byte orders and marker widths of one trajectory hold the same frames.
TEST(Dcd, MarkerWidthsAndByteOrdersAgree) {
  const auto reference = openDcd(data("formats/dcd/mrmd_h2so4-32bit-be.dcd"));
  for (const char* name :
       {"formats/dcd/mrmd_h2so4-64bit-be.dcd", "formats/dcd/mrmd_h2so4-64bit-le.dcd"}) {
    const auto other = openDcd(data(name));
    ASSERT_EQ(other->frameCount(), reference->frameCount()) << name;
    ASSERT_EQ(other->frameCount(), 50u) << name;  // tests/data/MANIFEST.md
    Frame a, b;
    for (std::size_t k = 0; k < reference->frameCount(); ++k) {
      reference->read(k, a);
      other->read(k, b);
      expectSameFrame(a, b, std::string(name) + " frame " + std::to_string(k + 1));
    }
  }
}

// Every DCD of the shared data set (adk_dims.dcd, 2cas.dcd, withpbc.dcd, water.dcd, tip125, ...),
// when the checkout has it next to the repository.
TEST(Dcd, SharedDataMatchesMDAnalysis) {
  const fs::path root = fs::path(SURFTRACE_SOURCE_DIR) / ".." / "shared" / "data";
  if (!fs::is_directory(root)) GTEST_SKIP() << root << " does not exist (no shared data set here)";
  const fs::path scratch = tempDir();
  std::size_t files = 0;
  Worst worst;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".dcd") continue;
    SCOPED_TRACE(entry.path().string());
    compareWithMDAnalysis(entry.path(), scratch, worst);
    ++files;
    if (entry.path().filename() == "adk_dims.dcd") {
      const auto adk = openDcd(entry.path());
      EXPECT_EQ(adk->frameCount(), 98u);  // MANIFEST: header NSET 500, 98 frames in the file
      EXPECT_THAT(adk->notes(), ::testing::Contains("header says 500 frames, the file holds 98"));
    }
  }
  std::cout << "[ dcd      ] shared data: " << files << " files, " << worst.frames
            << " frames, worst |dpos| " << worst.position << " A, cell rel " << worst.cellRelative
            << ", |dt| " << worst.time << " ps\n";
  EXPECT_GT(files, 0u) << "no .dcd under " << root;
  fs::remove_all(scratch);
}

TEST(Dcd, HeaderFrameCountThatDisagreesIsNoted) {
  const fs::path dir = tempDir();
  Bytes bytes = readBytes(data("trajectories/sampletrajectory/sampletrajectory.dcd"));
  const Layout layout = layoutOf(bytes);
  put32(bytes, layout.markerBytes + 4, 500, layout.big);  // NSET = icntrl[0]
  writeBytes(dir / "nset500.dcd", bytes);
  const auto source = openDcd(dir / "nset500.dcd");
  EXPECT_EQ(source->frameCount(), 10u);
  EXPECT_THAT(source->notes(), ::testing::ElementsAre("header says 500 frames, the file holds 10"));
  EXPECT_TRUE(openDcd(data("trajectories/sampletrajectory/sampletrajectory.dcd"))->notes().empty());
  fs::remove_all(dir);
}

TEST(Dcd, TruncatedLastFrameIsLeftOut) {
  const fs::path dir = tempDir();
  for (const char* name : {"trajectories/watdyn/watdyn.dcd", "formats/dcd/fixed-atoms.dcd",
                           "formats/dcd/4d-dynamic.dcd", "formats/dcd/mrmd_h2so4-32bit-be.dcd"}) {
    SCOPED_TRACE(name);
    const Bytes good = readBytes(data(name));
    const auto full = openDcd(data(name));
    const std::size_t n = full->frameCount();
    // The last frame's size, from the records this test finds (each frame has the same count).
    const Layout layout = layoutOf(good);
    const std::size_t perFrame = (layout.records.size() - layout.headerRecords(good)) / n;
    const std::size_t lastStart = layout.records[layout.records.size() - perFrame].at;
    const std::size_t lastBytes = good.size() - lastStart;
    for (const std::size_t kept : {std::size_t{0}, std::size_t{1}, lastBytes / 2, lastBytes - 1}) {
      const fs::path cut =
          dir / ("cut_" + std::to_string(kept) + "_" + fs::path(name).filename().string());
      writeBytes(cut, good.substr(0, lastStart + kept));
      const auto source = openDcd(cut);
      EXPECT_EQ(source->frameCount(), n - 1) << "kept " << kept;
      if (kept > 0) {
        EXPECT_THAT(source->notes(),
                    ::testing::Contains("frame " + std::to_string(n - 1) + " is truncated (" +
                                        std::to_string(kept) + " of " + std::to_string(lastBytes) +
                                        " bytes) and left out"));
      }
      Frame frame;
      EXPECT_THROW(source->read(n - 1, frame), InputError);
      if (kept != lastBytes / 2) continue;
      // MDAnalysis on the good file and on the cut one: the frames before the cut agree.
      Oracle whole, truncated;
      ASSERT_TRUE(runOracle(data(name), dir, whole));
      ASSERT_TRUE(runOracle(cut, dir, truncated));
      EXPECT_EQ(truncated.frames.size(), n - 1);
      Worst worst;
      expectMatches(*source, whole, n - 1, cut.filename().string(), worst, !layout.big);
      expectMatches(*source, truncated, n - 1, cut.filename().string(), worst, !layout.big);
    }
  }
  fs::remove_all(dir);
}

TEST(Dcd, FileCutInsideTheHeaderIsAnInputError) {
  const fs::path dir = tempDir();
  for (const char* name : {"trajectories/watdyn/watdyn.dcd", "formats/dcd/fixed-atoms.dcd",
                           "formats/dcd/mrmd_h2so4-64bit-be.dcd"}) {
    const Bytes good = readBytes(data(name));
    const std::size_t header = layoutOf(good).headerBytes(good);
    const fs::path cut = dir / fs::path(name).filename();
    for (std::size_t size = 0; size < header; ++size) {
      writeBytes(cut, good.substr(0, size));
      try {
        openDcd(cut);
        ADD_FAILURE() << name << " cut to " << size << " bytes opened";
      } catch (const InputError& e) {
        EXPECT_EQ(e.path(), cut.string());
        EXPECT_THAT(e.what(), HasSubstr(cut.string())) << size;
      }
    }
    // The whole header and no frame: a trajectory of no frames, and notes that say so.
    writeBytes(cut, good.substr(0, header));
    const auto empty = openDcd(cut);
    EXPECT_EQ(empty->frameCount(), 0u) << name;
    EXPECT_FALSE(empty->notes().empty()) << name;
  }
  fs::remove_all(dir);
}

TEST(Dcd, CorruptRecordMarkerIsAnInputError) {
  const fs::path dir = tempDir();
  const fs::path path = data("trajectories/watdyn/watdyn.dcd");
  const Bytes good = readBytes(path);
  const Layout layout = layoutOf(good);
  const std::size_t header = layout.headerRecords(good);
  const auto reference = openDcd(path);
  const std::size_t perFrame = (layout.records.size() - header) / reference->frameCount();
  ASSERT_EQ(perFrame, 4u);  // cell, x, y, z

  // Frame 3's y record: its leading marker, then (separately) its trailing one.
  const Layout::Record& y = layout.records[header + 2 * perFrame + 2];
  ASSERT_EQ(y.length, 60u);  // 15 atoms
  for (const std::size_t at : {y.at, y.at + 4 + y.length}) {
    Bytes bad = good;
    put32(bad, at, 61, layout.big);
    const fs::path file = dir / "bad_marker.dcd";
    writeBytes(file, bad);
    const auto source = openDcd(file);
    ASSERT_EQ(source->frameCount(), reference->frameCount());
    Frame frame, want;
    try {
      source->read(2, frame);
      ADD_FAILURE() << "corrupt marker at byte " << at << " read";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(file.string()));
      EXPECT_THAT(e.what(), HasSubstr("frame 2:"));  // read(2): frames from 0
      EXPECT_THAT(e.what(), HasSubstr("expected a record marker of 60"));
      EXPECT_THAT(e.what(), HasSubstr("at byte " + std::to_string(at) + ", found 61"));
    }
    for (const std::size_t k : {std::size_t{1}, std::size_t{3}}) {  // neighbours still read
      source->read(k, frame);
      reference->read(k, want);
      expectSameFrame(frame, want, "frame " + std::to_string(k) + " after the failure");
    }
  }

  // Header records: the title record's trailing marker, and a title length past the end.
  const Layout::Record& title = layout.records[1];
  for (const auto& [at, value] : {std::pair{title.at + 4 + title.length, std::uint32_t{165}},
                                  std::pair{title.at, std::uint32_t{0x7ffffff0}}}) {
    Bytes bad = good;
    put32(bad, at, value, layout.big);
    const fs::path file = dir / "bad_title.dcd";
    writeBytes(file, bad);
    try {
      openDcd(file);
      ADD_FAILURE() << "corrupt title marker at byte " << at << " opened";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(file.string()));
      EXPECT_THAT(e.what(), HasSubstr("title record at byte " + std::to_string(title.at)));
    }
  }

  // An absurd atom count (2^31 - 1) must not allocate: no frame fits, and a note says so.
  Bytes bad = good;
  put32(bad, layout.records[2].at + 4, 0x7fffffff, layout.big);
  writeBytes(dir / "huge_natom.dcd", bad);
  const auto huge = openDcd(dir / "huge_natom.dcd");
  EXPECT_EQ(huge->frameCount(), 0u);
  EXPECT_THAT(huge->notes(), ::testing::Contains(HasSubstr("frame 0 is truncated")));
  Frame none;
  EXPECT_THROW(huge->read(0, none), InputError);

  // Not a DCD at all.
  writeBytes(dir / "text.dcd", "CORD is not enough\n");
  EXPECT_THROW(openDcd(dir / "text.dcd"), InputError);
  EXPECT_THROW(openDcd(dir / "does_not_exist.dcd"), InputError);
  fs::remove_all(dir);
}

TEST(Dcd, NonFiniteCoordinateNamesFrameAndAtom) {
  const fs::path dir = tempDir();
  struct Case {
    const char* name;
    std::size_t frame, atom, axis;  // 1-based frame and atom; 0..2 axis
    std::uint32_t bits;             // float32 bits written in the file's byte order
  };
  // fixed-atoms.dcd: frame 5 stores the free atoms only; the 2nd of them is patched.
  for (const Case& c : {Case{"trajectories/watdyn/watdyn.dcd", 4, 7, 1, 0x7fc00000u},
                        Case{"formats/dcd/mrmd_h2so4-32bit-be.dcd", 2, 3, 2, 0x7f800000u},
                        Case{"formats/dcd/fixed-atoms.dcd", 5, 0, 0, 0xff800000u},
                        Case{"formats/dcd/fixed-atoms.dcd", 1, 12, 2, 0x7fc00000u}}) {
    SCOPED_TRACE(c.name);
    Bytes bad = readBytes(data(c.name));
    const Layout layout = layoutOf(bad);
    const std::size_t header = layout.headerRecords(bad);
    const bool fixed = header == 4;
    const std::size_t perFrame = layout.icntrl(bad, 10) != 0 ? 4 : 3;
    // The frame's records: [cell,] x, y, z.
    const Layout::Record& r =
        layout.records[header + (c.frame - 1) * perFrame + (perFrame - 3) + c.axis];
    std::size_t slot = c.atom - 1;
    std::size_t atom = c.atom;
    if (fixed && c.frame > 1) {  // the file's 2nd free atom
      slot = 1;
      atom = static_cast<std::size_t>(layout.value(bad, layout.records[3].at + 4 + 4, 4));
    }
    put32(bad, r.at + layout.markerBytes + 4 * slot, c.bits, layout.big);
    const fs::path file = dir / ("nonfinite_" + fs::path(c.name).filename().string());
    writeBytes(file, bad);
    const auto source = openDcd(file);
    Frame frame;
    try {
      source->read(c.frame - 1, frame);
      ADD_FAILURE() << "non-finite coordinate read";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(file.string()));
      EXPECT_THAT(e.what(), HasSubstr("frame " + std::to_string(c.frame - 1) + ", atom " +  // from 0
                                      std::to_string(atom) + ": non-finite " + "xyz"[c.axis]));
    }
    if (c.frame > 1) {
      EXPECT_NO_THROW(source->read(0, frame));
    }
  }
  fs::remove_all(dir);
}

TEST(Dcd, IndexOutOfRangeIsAnInputError) {
  const fs::path path = data("trajectories/watdyn/watdyn.dcd");
  const auto source = openDcd(path);
  ASSERT_EQ(source->frameCount(), 10u);  // tests/data/MANIFEST.md
  EXPECT_EQ(source->atomCount(), 15u);
  Frame frame;
  for (const std::size_t k :
       {std::size_t{10}, std::size_t{11}, std::numeric_limits<std::size_t>::max()}) {
    try {
      source->read(k, frame);
      ADD_FAILURE() << "frame index " << k << " read";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(path.string()));
      EXPECT_THAT(e.what(), HasSubstr("does not exist: the file holds frames 0 to 9"));
    }
  }
  EXPECT_NO_THROW(source->read(9, frame));
}

// A 4D flag on a file of 3-record frames is an error that names the flag, not 7 frames of
// scrambled coordinates (issue 18): told by the size where the frames do not fit 4 records,
// and by the atoms' jump from frame 0 to frame 1 where they do.
TEST(Dcd, FourthDimensionFlagOnA3DFileIsAnError) {
  const fs::path dir = tempDir();
  for (const char* name : {"trajectories/adk_dims/adk_dims.dcd", "trajectories/watdyn/watdyn.dcd",
                           "formats/dcd/triclinic-namd.dcd", "formats/dcd/mrmd_h2so4-64bit-le.dcd"}) {
    SCOPED_TRACE(name);
    const Bytes good = readBytes(data(name));
    const Layout layout = layoutOf(good);
    ASSERT_FALSE(hasFourthDimension(good, layout));
    const std::size_t header = layout.headerRecords(good);
    const std::size_t perFrame = layout.icntrl(good, 10) != 0 && layout.icntrl(good, 19) != 0 ? 4 : 3;
    const std::size_t frames = (layout.records.size() - header) / perFrame;
    // Every whole count of frames: some fit 4 records a frame by size, some do not.
    for (const std::size_t kept : {frames, frames - frames % 4, std::size_t{4}, std::size_t{2}}) {
      if (kept < 2 || kept > frames) continue;
      Bytes bad = good.substr(0, layout.records[header + kept * perFrame - 1].at + 2 * layout.markerBytes +
                                     layout.records[header + kept * perFrame - 1].length);
      put32(bad, layout.markerBytes + 4 + 4 * 19, 24, layout.big);  // a CHARMM file...
      put32(bad, layout.markerBytes + 4 + 4 * 11, 1, layout.big);   // ...of 4D dynamics
      const fs::path file = dir / ("flag4d_" + std::to_string(kept) + "_" + fs::path(name).filename().string());
      writeBytes(file, bad);
      try {
        const auto source = openDcd(file);
        Frame frame;
        for (std::size_t k = 0; k < source->frameCount(); ++k) source->read(k, frame);
        ADD_FAILURE() << kept << " frames: a 3D file flagged 4D was read (" << source->frameCount() << " frames)";
      } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr(file.string()));
        EXPECT_THAT(e.what(), HasSubstr("4D flag (icntrl[11] = 1")) << kept << " frames";
      }
    }
  }
  // A real CHARMM 4D file still reads.
  const auto real = openDcd(data("formats/dcd/4d-dynamic.dcd"));
  Frame frame;
  for (std::size_t k = 0; k < real->frameCount(); ++k) EXPECT_NO_THROW(real->read(k, frame));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace surftrace::build
