// The XTC reader against MDAnalysis, an independent decoder (tests/oracles/mda_frames.py), on
// real trajectories and on files the tests damage on purpose.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "build/io/error.hpp"
#include "build/io/trajectory.hpp"
#include "oracles/python_oracle.hpp"

namespace surftrace::build {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

static_assert(std::endian::native == std::endian::little, "the oracle dump is little-endian");

const char* const kTestFiles[] = {
    "formats/xtc/cell_shapes.xtc",
    "formats/xtc/large_diff.xtc",
    "trajectories/sampletrajectory/sampletrajectory.xtc",
    "trajectories/cobrotoxin/cobrotoxin.xtc",
};

fs::path data(const std::string& relative) { return fs::path(SURFTRACE_TEST_DATA) / relative; }

using Bytes = std::vector<unsigned char>;

Bytes readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeBytes(const fs::path& path, const Bytes& bytes, std::size_t count) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(count));
}
void writeBytes(const fs::path& path, const Bytes& bytes) { writeBytes(path, bytes, bytes.size()); }

std::uint32_t be32(const Bytes& b, std::size_t at) {
  return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) |
         (std::uint32_t{b[at + 2]} << 8) | std::uint32_t{b[at + 3]};
}
void putBe32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (std::size_t i = 0; i < 4; ++i) b[at + i] = static_cast<unsigned char>(v >> (24 - 8 * i));
}

// What the test needs from each frame header, found by a walk of its own (not the reader's):
// where the frame and its compressed block are, its precision (0: stored uncompressed), step.
struct HeaderInfo {
  std::size_t offset = 0;
  std::size_t blockAt = 0;  // 0 when uncompressed
  std::size_t blockBytes = 0;
  double precision = 0.0;
  std::int32_t step = 0;
};

std::vector<HeaderInfo> walkHeaders(const Bytes& b) {
  std::vector<HeaderInfo> frames;
  std::size_t at = 0;
  while (at + 56 <= b.size()) {
    HeaderInfo h;
    h.offset = at;
    h.step = static_cast<std::int32_t>(be32(b, at + 8));
    const std::uint32_t natoms = be32(b, at + 4);
    std::size_t size = 56 + 12 * std::size_t{natoms};
    if (natoms > 9) {
      if (at + 92 > b.size()) break;
      h.precision = static_cast<double>(std::bit_cast<float>(be32(b, at + 56)));
      h.blockAt = at + 92;
      h.blockBytes = be32(b, at + 88);
      size = 92 + (h.blockBytes + 3) / 4 * 4;
    }
    if (at + size > b.size()) break;
    frames.push_back(h);
    at += size;
  }
  return frames;
}

// A folder of its own under the system's temporary folder, removed afterwards.
class Scratch {
 public:
  Scratch() {
    std::string name = (fs::temp_directory_path() / "surftrace_xtc_XXXXXX").string();
    if (mkdtemp(name.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = name;
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

struct OracleFrame {
  double time = 0.0;
  bool hasCell = false;
  std::array<double, 6> cell{};
  std::vector<float> xyz;  // Å, as MDAnalysis holds them (float32)
};

struct Oracle {
  std::int64_t atoms = 0;
  std::vector<OracleFrame> frames;
};

// Runs the oracle on a copy of `trajectory` in `scratch` (MDAnalysis writes an offsets cache
// beside the file it reads; it must not land in the source tree).
bool runOracle(const fs::path& trajectory, const fs::path& scratch, Oracle& oracle) {
  const fs::path copy = scratch / trajectory.filename();
  fs::copy_file(trajectory, copy, fs::copy_options::overwrite_existing);
  const fs::path out = scratch / (trajectory.filename().string() + ".frames");
  const test::OracleRun run =
      test::runOracleScript("mda_frames.py", {copy.string(), out.string()}, scratch);
  if (run.exitCode == 3) {
    ADD_FAILURE() << "MDAnalysis, the oracle of these tests, cannot be imported: install "
                     "python3-mdanalysis (apt-get install python3-mdanalysis).\n"
                  << run.describe();
    return false;
  }
  if (!run.ok()) {
    ADD_FAILURE() << run.describe();
    return false;
  }

  const Bytes dump = readBytes(out);
  std::size_t at = 0;
  auto take = [&](void* dst, std::size_t n) {
    if (at + n > dump.size()) return false;
    std::memcpy(dst, dump.data() + at, n);
    at += n;
    return true;
  };
  std::int64_t frames = 0;
  bool complete = take(&oracle.atoms, 8) && take(&frames, 8) && oracle.atoms >= 0 && frames >= 0;
  if (complete) oracle.frames.resize(static_cast<std::size_t>(frames));
  for (std::size_t k = 0; complete && k < oracle.frames.size(); ++k) {
    OracleFrame& f = oracle.frames[k];
    std::int64_t hasCell = 0;
    f.xyz.resize(static_cast<std::size_t>(oracle.atoms) * 3);
    complete = take(&f.time, 8) && take(&hasCell, 8) && take(f.cell.data(), 48) &&
               take(f.xyz.data(), f.xyz.size() * 4);
    f.hasCell = hasCell != 0;
  }
  if (!complete || at != dump.size()) {
    ADD_FAILURE() << "oracle dump " << out << " does not match its header";
    return false;
  }
  return true;
}

// The worst disagreement with the oracle over the frames compared.
struct Agreement {
  std::size_t frames = 0;
  std::size_t coordinates = 0;
  std::size_t notIdentical = 0;   // our double, rounded to float32, differs from MDAnalysis's
  double worstAbs = 0.0;          // Å
  double worstRel = 0.0;          // |Δ| / |x|
  double worstOfTolerance = 0.0;  // |Δ| / tolerance
  void merge(const Agreement& o) {
    frames += o.frames;
    coordinates += o.coordinates;
    notIdentical += o.notIdentical;
    worstAbs = std::max(worstAbs, o.worstAbs);
    worstRel = std::max(worstRel, o.worstRel);
    worstOfTolerance = std::max(worstOfTolerance, o.worstOfTolerance);
  }
};

std::ostream& operator<<(std::ostream& os, const Agreement& a) {
  return os << a.frames << " frames, " << a.coordinates << " coordinates; worst |diff| "
            << a.worstAbs << " A (relative " << a.worstRel << ", " << a.worstOfTolerance
            << " of the tolerance); " << a.notIdentical << " not identical as float32";
}

// Frame `k` of `source` against the oracle's: time, step (from the header walk), cell, and
// every coordinate within half the file's precision (5 / precision Å) plus the float32
// rounding of MDAnalysis's nm -> Å conversion.
void compareFrame(FrameSource& source, std::size_t k, const OracleFrame& want,
                  const HeaderInfo& header, Agreement& agreement) {
  SCOPED_TRACE(source.path() + " frame " + std::to_string(k));
  Frame got;
  ASSERT_NO_THROW(source.read(k, got));
  ASSERT_EQ(got.positions.size() * 3, want.xyz.size());
  EXPECT_EQ(got.time, want.time);
  EXPECT_EQ(got.step, header.step);
  ASSERT_EQ(got.cell.has_value(), want.hasCell);
  if (got.cell) {
    for (std::size_t i = 0; i < 3; ++i)
      EXPECT_NEAR((*got.cell)[i], want.cell[i], 1e-6 * want.cell[i]) << "edge " << i;
    for (std::size_t i = 3; i < 6; ++i)
      EXPECT_NEAR((*got.cell)[i], want.cell[i], 1e-3) << "angle " << i;
  }
  const double half = header.precision > 0.0 ? 5.0 / header.precision : 0.0;
  int reported = 0;
  for (std::size_t i = 0; i < want.xyz.size(); ++i) {
    const double x = got.positions[i / 3][static_cast<glm::length_t>(i % 3)];
    const double w = static_cast<double>(want.xyz[i]);
    const double diff = std::abs(x - w);
    const double tolerance = half + std::abs(w) * 0x1p-24 + 1e-30;
    agreement.worstAbs = std::max(agreement.worstAbs, diff);
    if (w != 0.0) agreement.worstRel = std::max(agreement.worstRel, diff / std::abs(w));
    agreement.worstOfTolerance = std::max(agreement.worstOfTolerance, diff / tolerance);
    if (static_cast<float>(x) != want.xyz[i]) ++agreement.notIdentical;
    if (diff > tolerance && reported++ < 5)
      ADD_FAILURE() << "atom " << i / 3 + 1 << " axis " << i % 3 << ": " << x << " vs MDAnalysis "
                    << w << " (tolerance " << tolerance << ")";
  }
  agreement.coordinates += want.xyz.size();
  ++agreement.frames;
}

// Every frame of `path` against MDAnalysis.
Agreement compareWithOracle(const fs::path& path) {
  Agreement agreement;
  Scratch scratch;
  Oracle oracle;
  if (!runOracle(path, scratch.path(), oracle)) return agreement;
  const std::vector<HeaderInfo> headers = walkHeaders(readBytes(path));
  std::unique_ptr<FrameSource> source;
  try {
    source = openXtc(path);
  } catch (const InputError& e) {
    ADD_FAILURE() << e.what();
    return agreement;
  }
  EXPECT_EQ(static_cast<std::int64_t>(source->atomCount()), oracle.atoms) << path;
  EXPECT_EQ(source->frameCount(), oracle.frames.size()) << path;
  EXPECT_EQ(source->frameCount(), headers.size()) << path;
  EXPECT_TRUE(source->notes().empty()) << path << ": " << source->notes().front();
  const std::size_t n = std::min({source->frameCount(), oracle.frames.size(), headers.size()});
  for (std::size_t k = 0; k < n; ++k)
    compareFrame(*source, k, oracle.frames[k], headers[k], agreement);
  // Same integers and the same float arithmetic as xdrfile: our Å, rounded to float32, are
  // MDAnalysis's (both are the correctly rounded product of the same float nm and 10).
  EXPECT_EQ(agreement.notIdentical, 0u) << path;
  std::cout << "[ xtc      ] " << path.filename().string() << ": " << oracle.atoms << " atoms, "
            << agreement << "\n";
  return agreement;
}

TEST(XtcReader, MatchesMdanalysisOnTestData) {
  Agreement all;
  for (const char* file : kTestFiles) {
    SCOPED_TRACE(file);
    all.merge(compareWithOracle(data(file)));
  }
  std::cout << "[ xtc      ] all test data: " << all << "\n";
  EXPECT_GT(all.frames, 0u);
}

TEST(XtcReader, MatchesMdanalysisOnSharedData) {
  const fs::path shared = fs::path(SURFTRACE_SOURCE_DIR "/../shared/data");
  if (!fs::is_directory(shared)) GTEST_SKIP() << shared << " does not exist (the shared data set)";
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(shared))
    if (entry.is_regular_file() && entry.path().extension() == ".xtc")
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty()) << "no .xtc under " << shared;
  Agreement all;
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.string());
    all.merge(compareWithOracle(file));
  }
  std::cout << "[ xtc      ] " << files.size() << " shared files: " << all << "\n";
}

// Opening `bytes` written to a file must throw an InputError naming the file and containing
// every string of `expected`.
void expectOpenError(const fs::path& path, const Bytes& bytes, std::size_t count,
                     const std::vector<std::string>& expected) {
  writeBytes(path, bytes, count);
  try {
    auto source = openXtc(path);
    ADD_FAILURE() << "no error; " << source->frameCount() << " frames";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path.string()));
    for (const std::string& s : expected) EXPECT_THAT(e.what(), HasSubstr(s));
  }
}

// Reading frame `k` of `bytes` must throw an InputError containing `expected`.
void expectReadError(const fs::path& path, const Bytes& bytes, std::size_t k,
                     const std::vector<std::string>& expected) {
  writeBytes(path, bytes);
  std::unique_ptr<FrameSource> source;
  ASSERT_NO_THROW(source = openXtc(path));
  Frame frame;
  try {
    source->read(k, frame);
    ADD_FAILURE() << "no error reading frame " << k;
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path.string()));
    for (const std::string& s : expected) EXPECT_THAT(e.what(), HasSubstr(s));
  }
  // The other frames stay readable.
  for (std::size_t j = 0; j < source->frameCount(); ++j)
    if (j != k) {
      EXPECT_NO_THROW(source->read(j, frame)) << "frame " << j;
    }
}

// Frames written by hand, to reach what the real files do not: coordinates stored uncompressed
// (9 atoms or fewer) and compressed ones whose three integer ranges need a 72-bit mixed-radix
// number, or three separate fields (a range above 2^24). Only "big" atoms, no runs: the packing
// follows the format description, and MDAnalysis checks that we both read it the same way.
__extension__ using Uint128 = unsigned __int128;

class BitWriter {
 public:
  // The low `bits` bits of v, most significant first.
  void put(Uint128 v, unsigned bits) {
    for (unsigned i = bits; i-- > 0;) {
      if (bit_ % 8 == 0) bytes_.push_back(0);
      if (((v >> i) & 1) != 0) bytes_.back() |= static_cast<unsigned char>(0x80u >> (bit_ % 8));
      ++bit_;
    }
  }
  const Bytes& bytes() const { return bytes_; }

 private:
  Bytes bytes_;
  std::size_t bit_ = 0;
};

void appendBe32(Bytes& b, std::uint32_t v) {
  for (int i = 3; i >= 0; --i) b.push_back(static_cast<unsigned char>(v >> (8 * i)));
}
void appendFloat(Bytes& b, float f) { appendBe32(b, std::bit_cast<std::uint32_t>(f)); }

void appendHeader(Bytes& b, std::uint32_t natoms, std::int32_t step, float time,
                  const std::array<float, 9>& box) {
  appendBe32(b, 1995);
  appendBe32(b, natoms);
  appendBe32(b, static_cast<std::uint32_t>(step));
  appendFloat(b, time);
  for (float x : box) appendFloat(b, x);
  appendBe32(b, natoms);
}

// Compressed frame of big atoms only: integer coordinates `ints` in [minint, minint + size).
// One big atom: its integers above minint, as one mixed-radix number or three fields.
void putBigAtom(BitWriter& w, const std::array<std::uint32_t, 3>& sizes,
                const std::array<Uint128, 3>& v) {
  if (*std::max_element(sizes.begin(), sizes.end()) > 0xffffffu) {
    for (std::size_t d = 0; d < 3; ++d)
      w.put(v[d], static_cast<unsigned>(std::bit_width(sizes[d])));
    return;
  }
  const Uint128 product = Uint128{sizes[0]} * sizes[1] * sizes[2];
  unsigned packedBits = 0;
  while ((product >> packedBits) != 0) ++packedBits;
  // One number, most significant digit first; its bytes go least significant first, the last
  // one with the leftover bits.
  const Uint128 n = (v[0] * sizes[1] + v[1]) * sizes[2] + v[2];
  for (unsigned done = 0; done < packedBits; done += 8)
    w.put(n >> done, std::min(8u, packedBits - done));
}

// A compressed frame whose packed stream is `w`.
void appendBlock(Bytes& b, std::uint32_t natoms, std::int32_t step, float time,
                 const std::array<float, 9>& box, float precision,
                 const std::array<std::int32_t, 3>& minint,
                 const std::array<std::uint32_t, 3>& sizes, std::int32_t smallIdx,
                 const BitWriter& w) {
  appendHeader(b, natoms, step, time, box);
  appendFloat(b, precision);
  for (std::size_t d = 0; d < 3; ++d) appendBe32(b, static_cast<std::uint32_t>(minint[d]));
  for (std::size_t d = 0; d < 3; ++d)
    appendBe32(b, static_cast<std::uint32_t>(static_cast<std::int64_t>(minint[d]) + sizes[d] - 1));
  appendBe32(b, static_cast<std::uint32_t>(smallIdx));
  appendBe32(b, static_cast<std::uint32_t>(w.bytes().size()));
  b.insert(b.end(), w.bytes().begin(), w.bytes().end());
  while (b.size() % 4 != 0) b.push_back(0);
}

// Compressed frame of big atoms only: integer coordinates `ints` in [minint, minint + size).
void appendCompressed(Bytes& b, std::int32_t step, float time, const std::array<float, 9>& box,
                      float precision, const std::array<std::int32_t, 3>& minint,
                      const std::array<std::uint32_t, 3>& sizes,
                      const std::vector<std::array<std::int32_t, 3>>& ints) {
  BitWriter w;
  for (const auto& c : ints) {
    std::array<Uint128, 3> v{};
    for (std::size_t d = 0; d < 3; ++d)
      v[d] = static_cast<Uint128>(static_cast<std::int64_t>(c[d]) - minint[d]);
    putBigAtom(w, sizes, v);
    w.put(0, 1);  // no run
  }
  appendBlock(b, static_cast<std::uint32_t>(ints.size()), step, time, box, precision, minint, sizes,
              9, w);  // smallidx 9: unused without runs
}

// Packed streams that go wrong on purpose, each an InputError naming what is wrong.
TEST(XtcReader, CraftedBlocksAreInputErrors) {
  Scratch scratch;
  const fs::path path = scratch.path() / "crafted.xtc";
  const std::array<float, 9> box = {3.f, 0.f, 0.f, 0.f, 3.f, 0.f, 0.f, 0.f, 3.f};
  const std::array<std::int32_t, 3> minint = {0, 0, 0};
  const std::array<std::uint32_t, 3> sizes = {1000, 1000, 1000};
  const std::array<Uint128, 3> origin = {0, 0, 0};
  // Big atom, then the run flag and the 5-bit code run + is_smaller + 1.
  auto atom = [&](BitWriter& w, int code) {
    putBigAtom(w, sizes, origin);
    if (code < 0) {
      w.put(0, 1);
    } else {
      w.put(1, 1);
      w.put(static_cast<Uint128>(code), 5);
    }
  };
  auto check = [&](std::int32_t smallIdx, const BitWriter& w, const std::string& expected) {
    Bytes b;
    appendBlock(b, 10, 0, 0.f, box, 1000.f, minint, sizes, smallIdx, w);
    SCOPED_TRACE(expected);
    expectReadError(path, b, 0, {"frame 0 (byte 0)", "block at byte 92", expected});
  };
  {
    BitWriter w;  // a run of 10 small atoms after the first of 10
    atom(w, 30);
    check(9, w, "starts a run of 11 atoms, past the frame's 10 atoms");
  }
  {
    BitWriter w;  // smallidx 9 - 1 = 8, whose base is 0, then a run
    atom(w, 0);
    atom(w, 4);
    check(9, w, "atom 2 starts a run with smallidx 8 (base 0)");
  }
  {
    BitWriter w;  // smallidx 72 + 1: past the table
    atom(w, 2);
    check(72, w, "smallidx moves to 73");
  }
  {
    BitWriter w;  // 3 atoms of 10
    for (int i = 0; i < 3; ++i) atom(w, -1);
    check(9, w, "past the end of the block");
  }
  // And a NaN among uncompressed coordinates.
  Bytes b;
  appendHeader(b, 3, 0, 0.f, box);
  for (int i = 0; i < 9; ++i) appendFloat(b, i == 4 ? std::nanf("") : 1.f);
  expectReadError(path, b, 0, {"frame 0 (byte 0)", "non-finite coordinate of atom 2"});
}

TEST(XtcReader, HandWrittenFramesMatchMdanalysis) {
  Scratch scratch;
  std::mt19937 rng(7);
  const std::array<float, 9> cubic = {5.f, 0.f, 0.f, 0.f, 5.f, 0.f, 0.f, 0.f, 5.f};
  const std::array<float, 9> triclinic = {4.f, 0.f, 0.f, 1.f, 3.5f, 0.f, -0.5f, 1.2f, 3.f};

  // Uncompressed: 5 atoms, a triclinic box, then no box.
  Bytes small;
  std::vector<std::vector<float>> smallXyz;
  for (int k = 0; k < 3; ++k) {
    appendHeader(small, 5, 100 * k, 0.5f * static_cast<float>(k),
                 k == 2 ? std::array<float, 9>{} : triclinic);
    smallXyz.emplace_back();
    for (int i = 0; i < 15; ++i) {
      smallXyz.back().push_back(std::uniform_real_distribution<float>(-50.f, 50.f)(rng));
      appendFloat(small, smallXyz.back().back());
    }
  }
  const fs::path smallPath = scratch.path() / "uncompressed.xtc";
  writeBytes(smallPath, small);

  // 40 big atoms: a 72-bit packed number, three separate fields (24, 25, 10 bits), a 61-bit
  // and an 8-bit packed number.
  Bytes wide;
  constexpr std::size_t kWideFrames = 4;
  const std::array<std::array<std::uint32_t, 3>, kWideFrames> sizes = {
      {{0xffffff, 0xffffff, 0xffffff},
       {0xffffff, 0x1000001, 1000},
       {1u << 20, 1u << 20, 1u << 20},
       {5, 6, 7}}};
  const std::array<std::int32_t, 3> minint = {-8000000, -4000, 1};
  const std::array<float, kWideFrames> precision = {1000.f, 100.f, 1000.f, 10.f};
  std::vector<std::vector<std::array<std::int32_t, 3>>> wideInts(kWideFrames);
  for (std::size_t k = 0; k < kWideFrames; ++k) {
    for (int i = 0; i < 40; ++i) {
      std::array<std::int32_t, 3> c{};
      for (std::size_t d = 0; d < 3; ++d) {
        const std::uint32_t top = sizes[k][d] - 1;
        // The extremes first, then anywhere in range.
        const std::uint32_t v = i == 0 ? 0
                                : i == 1
                                    ? top
                                    : std::uniform_int_distribution<std::uint32_t>(0, top)(rng);
        c[d] = static_cast<std::int32_t>(minint[d] + static_cast<std::int64_t>(v));
      }
      wideInts[k].push_back(c);
    }
    appendCompressed(wide, static_cast<std::int32_t>(k) + 1, 2.0f * static_cast<float>(k),
                     k % 2 == 0 ? cubic : triclinic, precision[k], minint, sizes[k], wideInts[k]);
  }
  const fs::path widePath = scratch.path() / "wide_ranges.xtc";
  writeBytes(widePath, wide);

  for (const fs::path& path : {smallPath, widePath}) {
    SCOPED_TRACE(path.filename().string());
    const Agreement agreement = compareWithOracle(path);
    EXPECT_GT(agreement.frames, 0u);
  }
  // And against the values the test wrote, through xdrfile's float arithmetic.
  auto source = openXtc(smallPath);
  Frame frame;
  for (std::size_t k = 0; k < 3; ++k) {
    source->read(k, frame);
    for (std::size_t i = 0; i < 15; ++i)
      EXPECT_EQ(frame.positions[i / 3][static_cast<glm::length_t>(i % 3)],
                static_cast<double>(smallXyz[k][i]) * 10.0);
    EXPECT_EQ(frame.cell.has_value(), k != 2);
  }
  source = openXtc(widePath);
  ASSERT_EQ(source->frameCount(), kWideFrames);
  for (std::size_t k = 0; k < kWideFrames; ++k) {
    source->read(k, frame);
    EXPECT_EQ(frame.step, static_cast<long long>(k) + 1);
    const float inv = 1.0f / precision[k];
    for (std::size_t i = 0; i < 40; ++i)
      for (std::size_t d = 0; d < 3; ++d)
        EXPECT_EQ(frame.positions[i][static_cast<glm::length_t>(d)],
                  static_cast<double>(static_cast<float>(wideInts[k][i][d]) * inv) * 10.0)
            << "frame " << k << " atom " << i + 1;
  }
}

void expectSameFrame(const Frame& a, const Frame& b) {
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(a.cell, b.cell);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i)
    if (a.positions[i] != b.positions[i]) {
      ADD_FAILURE() << "atom " << i + 1 << " differs";
      return;
    }
}

TEST(XtcReader, ReverseOrderEqualsForwardOrder) {
  for (const char* file : kTestFiles) {
    SCOPED_TRACE(file);
    auto source = openXtc(data(file));
    std::vector<Frame> forward(source->frameCount());
    for (std::size_t k = 0; k < forward.size(); ++k) source->read(k, forward[k]);
    Frame reused;  // one Frame for all reads: its memory is reused
    for (std::size_t k = forward.size(); k-- > 0;) {
      source->read(k, reused);
      SCOPED_TRACE("frame " + std::to_string(k));
      expectSameFrame(reused, forward[k]);
    }
  }
}

TEST(XtcReader, TruncatedLastFrameIsLeftOutWithNote) {
  const fs::path original = data("trajectories/cobrotoxin/cobrotoxin.xtc");
  const Bytes bytes = readBytes(original);
  const std::vector<HeaderInfo> headers = walkHeaders(bytes);
  ASSERT_EQ(headers.size(), 3u);
  Scratch scratch;
  Oracle oracle;
  ASSERT_TRUE(runOracle(original, scratch.path(), oracle));
  const std::size_t last = headers.back().offset;
  const std::size_t cuts[] = {
      last + 2,        last + 30, last + 60, last + 91, last + 92 + headers.back().blockBytes / 2,
      bytes.size() - 1};
  for (std::size_t cut : cuts) {
    SCOPED_TRACE("cut at byte " + std::to_string(cut));
    const fs::path path = scratch.path() / "truncated.xtc";
    writeBytes(path, bytes, cut);
    std::unique_ptr<FrameSource> source;
    ASSERT_NO_THROW(source = openXtc(path));
    EXPECT_EQ(source->frameCount(), 2u);
    ASSERT_EQ(source->notes().size(), 1u);
    EXPECT_THAT(source->notes()[0], HasSubstr("frame 2 (byte"));  // frames from 0
    EXPECT_THAT(source->notes()[0], HasSubstr("truncated"));
    Agreement agreement;
    for (std::size_t k = 0; k < 2; ++k)
      compareFrame(*source, k, oracle.frames[k], headers[k], agreement);
    EXPECT_EQ(agreement.frames, 2u);
    Frame frame;
    EXPECT_THROW(source->read(2, frame), InputError);
  }
}

TEST(XtcReader, CutInsideFirstFrameIsInputError) {
  const Bytes bytes = readBytes(data("trajectories/cobrotoxin/cobrotoxin.xtc"));
  const std::vector<HeaderInfo> headers = walkHeaders(bytes);
  Scratch scratch;
  const fs::path path = scratch.path() / "cut.xtc";
  for (std::size_t cut : {std::size_t{0}, std::size_t{2}, std::size_t{20}, std::size_t{55},
                          std::size_t{60}, std::size_t{91}, 92 + headers[0].blockBytes / 2}) {
    SCOPED_TRACE("cut at byte " + std::to_string(cut));
    expectOpenError(path, bytes, cut, {cut == 0 ? "empty" : "frame 0 (byte 0)"});
  }
}

TEST(XtcReader, WrongMagicIsInputError) {
  const Bytes original = readBytes(data("trajectories/sampletrajectory/sampletrajectory.xtc"));
  const std::vector<HeaderInfo> headers = walkHeaders(original);
  ASSERT_GE(headers.size(), 3u);
  Scratch scratch;
  const fs::path path = scratch.path() / "magic.xtc";
  Bytes bytes = original;
  putBe32(bytes, 0, 1996);
  expectOpenError(path, bytes, bytes.size(), {"frame 0 (byte 0)", "magic number 1996"});
  bytes = original;
  putBe32(bytes, headers[2].offset, 0x12345678);
  expectOpenError(path, bytes, bytes.size(),
                  {"frame 2 (byte " + std::to_string(headers[2].offset) + ")", "magic"});
  bytes = original;
  putBe32(bytes, 0, 2023);
  expectOpenError(path, bytes, bytes.size(), {"2023", "not supported"});
}

TEST(XtcReader, ImpossibleHeaderFieldsAreInputErrors) {
  const Bytes original = readBytes(data("trajectories/sampletrajectory/sampletrajectory.xtc"));
  const std::vector<HeaderInfo> headers = walkHeaders(original);
  ASSERT_GE(headers.size(), 2u);
  Scratch scratch;
  const fs::path path = scratch.path() / "fields.xtc";
  const std::size_t f2 = headers[1].offset;
  const std::string frame1 = "frame 1 (byte " + std::to_string(f2) + ")";  // the second frame
  auto with = [&](std::size_t at, std::uint32_t value) {
    Bytes b = original;
    putBe32(b, at, value);
    return b;
  };
  // Found while the file is opened.
  expectOpenError(path, with(f2 + 4, 114), original.size(),
                  {frame1, "114 atoms, but frame 0 has 115"});
  expectOpenError(path, with(f2 + 52, 116), original.size(), {frame1, "116"});
  expectOpenError(path, with(4, 0xfffffffb), original.size(),
                  {"frame 0 (byte 0)", "negative atom count"});
  expectOpenError(path, with(f2 + 88, 0x7fffffff), original.size(), {frame1, "compressed block"});
  expectOpenError(path, with(f2 + 88, 3), original.size(), {frame1, "cannot hold 115 atoms"});
  // A negative size says so (issue 18: "a block of 18446744073709551612 bytes").
  expectOpenError(path, with(f2 + 88, 0xfffffffc), original.size(), {frame1, "negative (-4 bytes)"});
  // Found when the frame is read.
  expectReadError(path, with(f2 + 84, 100), 1, {frame1, "smallidx 100"});
  expectReadError(path, with(f2 + 84, 3), 1, {frame1, "smallidx 3"});
  expectReadError(path, with(f2 + 84, 0x80000000), 1, {frame1, "smallidx"});
  expectReadError(path, with(f2 + 56, 0), 1, {frame1, "precision"});
  expectReadError(path, with(f2 + 56, 0x7fc00000), 1, {frame1, "precision"});  // NaN
  expectReadError(path, with(f2 + 56, 0x00000001), 1, {frame1, "precision"});  // 1e-45
  // Finite and positive, but no simulation writes it (issue 18: taken as is before).
  expectReadError(path, with(f2 + 56, std::bit_cast<std::uint32_t>(1e30f)), 1, {frame1, "precision 1e+30", "damaged"});
  expectReadError(path, with(f2 + 56, std::bit_cast<std::uint32_t>(1e-30f)), 1, {frame1, "precision 1e-30", "damaged"});
  expectReadError(path, with(f2 + 56, std::bit_cast<std::uint32_t>(0.5f)), 1, {frame1, "precision 0.5"});
  expectReadError(path, with(f2 + 60, 0x7fffffff), 1,
                  {frame1, "integer bounds"});  // minint > maxint
  expectReadError(path, with(f2 + 16, 0x7f800000), 1, {frame1, "non-finite box"});
  {
    Bytes b = with(f2 + 60, 0x80000000);  // minint INT_MIN, maxint INT_MAX: 2^32 values
    putBe32(b, f2 + 72, 0x7fffffff);
    expectReadError(path, b, 1, {frame1, "overflows 32 bits"});
  }
}

TEST(XtcReader, IndexOutOfRangeIsInputError) {
  auto source = openXtc(data("trajectories/sampletrajectory/sampletrajectory.xtc"));
  ASSERT_EQ(source->frameCount(), 10u);
  Frame frame;
  try {
    source->read(10, frame);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("frame 10 does not exist: the file holds frames 0 to 9"));
  }
  EXPECT_THROW(source->read(static_cast<std::size_t>(-1), frame), InputError);
  EXPECT_NO_THROW(source->read(9, frame));
  EXPECT_EQ(frame.positions.size(), 115u);
}

// Messages number frames from 0, as the other readers, `--frames` and the output file names do:
// the second frame of a file is frame 1 whether it is read, indexed or missing.
TEST(XtcReader, MessagesNumberFramesFromZero) {
  const Bytes original = readBytes(data("trajectories/sampletrajectory/sampletrajectory.xtc"));
  const std::vector<HeaderInfo> headers = walkHeaders(original);
  ASSERT_GE(headers.size(), 3u);
  Scratch scratch;
  const fs::path path = scratch.path() / "numbers.xtc";
  Bytes bytes = original;
  putBe32(bytes, headers[1].offset + 56, 0);  // the second frame's precision
  expectReadError(path, bytes, 1, {"frame 1 (byte " + std::to_string(headers[1].offset) + ")"});
  writeBytes(path, original, headers[2].offset + 10);  // the third frame cut inside its header
  auto source = openXtc(path);
  ASSERT_EQ(source->frameCount(), 2u);
  ASSERT_EQ(source->notes().size(), 1u);
  EXPECT_THAT(source->notes()[0], HasSubstr("frame 2 (byte " + std::to_string(headers[2].offset) + ")"));
  Frame frame;
  try {
    source->read(2, frame);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("frame 2 does not exist: the file holds frames 0 to 1"));
  }
}

// Flipped bytes inside compressed blocks (and sometimes in the fields before one) must give
// an InputError or a frame of finite coordinates: never a crash, a sanitizer report or another
// exception. The other frames of the file still read as before.
TEST(XtcReader, CorruptCompressedBytesGiveInputErrorOrAFrame) {
  std::uint32_t seed = 20240601;
  if (const char* s = std::getenv("SURFTRACE_FUZZ_SEED"))
    seed = static_cast<std::uint32_t>(std::stoul(s));
  constexpr int kTrials = 400;
  std::cout << "[ xtc      ] fuzz seed " << seed << " (SURFTRACE_FUZZ_SEED), " << kTrials
            << " trials\n";
  const char* const files[] = {"trajectories/sampletrajectory/sampletrajectory.xtc",
                               "trajectories/cobrotoxin/cobrotoxin.xtc",
                               "formats/xtc/large_diff.xtc"};
  struct Original {
    fs::path path;
    Bytes bytes;
    std::vector<HeaderInfo> headers;
    std::vector<Frame> frames;
  };
  std::vector<Original> originals;
  for (const char* file : files) {
    Original o{data(file), readBytes(data(file)), {}, {}};
    o.headers = walkHeaders(o.bytes);
    auto source = openXtc(o.path);
    o.frames.resize(source->frameCount());
    for (std::size_t k = 0; k < o.frames.size(); ++k) source->read(k, o.frames[k]);
    originals.push_back(std::move(o));
  }
  Scratch scratch;
  const fs::path path = scratch.path() / "fuzz.xtc";
  std::size_t openErrors = 0, readErrors = 0, decoded = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    std::mt19937 rng(seed + static_cast<std::uint32_t>(trial));  // one seed per trial
    SCOPED_TRACE("trial " + std::to_string(trial) + " seed " +
                 std::to_string(seed + static_cast<std::uint32_t>(trial)));
    const Original& o = originals[static_cast<std::size_t>(trial) % originals.size()];
    const std::size_t k = std::uniform_int_distribution<std::size_t>(0, o.headers.size() - 1)(rng);
    const HeaderInfo& h = o.headers[k];
    Bytes bytes = o.bytes;
    const bool fields = rng() % 4 == 0;  // precision, minint, maxint, smallidx
    const std::size_t from = fields ? h.offset + 56 : h.blockAt + h.blockBytes / 4;
    const std::size_t to = fields ? h.offset + 88 : h.blockAt + 3 * h.blockBytes / 4;
    const int flips = 1 + static_cast<int>(rng() % 4);
    for (int i = 0; i < flips; ++i) {
      const std::size_t at = std::uniform_int_distribution<std::size_t>(from, to - 1)(rng);
      bytes[at] ^= static_cast<unsigned char>(1 + rng() % 255);
    }
    writeBytes(path, bytes);
    std::unique_ptr<FrameSource> source;
    try {
      source = openXtc(path);
    } catch (const InputError&) {
      ++openErrors;
      continue;
    }
    ASSERT_EQ(source->frameCount(), o.frames.size());
    Frame frame;
    try {
      source->read(k, frame);
      ++decoded;
      ASSERT_EQ(frame.positions.size(), o.frames[k].positions.size());
      for (const glm::dvec3& p : frame.positions)
        ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    } catch (const InputError& e) {
      ++readErrors;
      EXPECT_THAT(e.what(), HasSubstr("frame " + std::to_string(k) + " (byte "));
    }
    const std::size_t other = (k + 1) % o.frames.size();
    if (other != k) {
      source->read(other, frame);
      expectSameFrame(frame, o.frames[other]);
    }
  }
  std::cout << "[ xtc      ] fuzz: " << openErrors << " open errors, " << readErrors
            << " read errors, " << decoded << " frames decoded\n";
  EXPECT_GT(readErrors, 0u);
}

}  // namespace
}  // namespace surftrace::build
