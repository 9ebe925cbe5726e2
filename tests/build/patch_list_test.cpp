// Patch-list container invariants and .stp file round trips, truncation and corruption.
#include "build/patch_list.hpp"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include <zlib.h>

#include <gtest/gtest.h>

namespace surftrace::build {
namespace {

std::string tempPath(const std::string& name) {
  return (std::filesystem::path(testing::TempDir()) / name).string();
}

std::vector<unsigned char> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void spit(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// A patch list with every array filled with random, distinct values.
PatchList randomPatchList(std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  std::uniform_int_distribution<std::uint32_t> atom(0, 99);
  auto v3 = [&] { return glm::dvec3(u(rng), u(rng), u(rng)); };
  PatchList p;
  p.params.surface = SurfaceKind::Ses;
  p.params.probeRadius = 1.4 + 1e-3 * seed;
  p.params.radiiSet = "table:/some/radii.txt";
  p.params.inputCrc32 = 0xdeadbeefu ^ seed;
  p.params.atomCount = 100;
  p.componentCount = 2;
  const int nConvex = 5 + static_cast<int>(seed % 7), nTori = 3 + static_cast<int>(seed % 5), nConcave = 4;
  for (int k = 0; k < nConvex; ++k) {
    p.convex.center.push_back(v3());
    p.convex.radius.push_back(u(rng));
    p.convex.atom.push_back(atom(rng));
    p.convex.component.push_back(k % 2);
    p.convex.area.push_back(u(rng));
    p.convex.vectorArea.push_back(v3());
  }
  for (int k = 0; k < nTori; ++k) {
    p.tori.center.push_back(v3());
    p.tori.axis.push_back(v3());
    p.tori.e1.push_back(v3());
    p.tori.bigRadius.push_back(u(rng));
    p.tori.thetaI.push_back(u(rng));
    p.tori.thetaJ.push_back(u(rng));
    p.tori.phiExtent.push_back(u(rng));
    p.tori.atomI.push_back(atom(rng));
    p.tori.atomJ.push_back(atom(rng));
    p.tori.component.push_back(0);
  }
  for (int k = 0; k < nConcave; ++k) {
    p.concave.probe.push_back(v3());
    p.concave.dirI.push_back(v3());
    p.concave.dirJ.push_back(v3());
    p.concave.dirK.push_back(v3());
    p.concave.atomI.push_back(atom(rng));
    p.concave.atomJ.push_back(atom(rng));
    p.concave.atomK.push_back(atom(rng));
    p.concave.clipBegin.push_back(static_cast<std::uint32_t>(p.clipPlanes.size()));
    p.concave.clipCount.push_back(static_cast<std::uint32_t>(k));
    for (int c = 0; c < k; ++c) p.clipPlanes.emplace_back(v3(), u(rng));
    p.concave.component.push_back(1);
  }
  p.mss.kind.push_back(static_cast<std::uint32_t>(MssKind::Edge));
  p.mss.center.push_back(v3());
  p.mss.axis.push_back(v3());
  p.mss.radialCoeff.push_back(u(rng));
  p.mss.axialCoeff.push_back(u(rng));
  p.mss.constant.push_back(u(rng));
  p.mss.boundRadius.push_back(u(rng));
  p.mss.atoms.push_back(glm::uvec4(1, 2, ~0u, ~0u));
  p.mss.cellBegin.push_back(0);
  p.mss.cellCount.push_back(2);
  p.cellPlanes.emplace_back(v3(), 1.0);
  p.cellPlanes.emplace_back(v3(), -1.0);
  return p;
}

// Bitwise equality of two doubles (a round trip must not even flip a NaN payload or -0).
template <class T> bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void expectIdentical(const PatchList& a, const PatchList& b) {
  EXPECT_EQ(a.params.surface, b.params.surface);
  EXPECT_EQ(a.params.probeRadius, b.params.probeRadius);
  EXPECT_EQ(a.params.shrinkFactor, b.params.shrinkFactor);
  EXPECT_EQ(a.params.radiiSet, b.params.radiiSet);
  EXPECT_EQ(a.params.inputCrc32, b.params.inputCrc32);
  EXPECT_EQ(a.params.atomCount, b.params.atomCount);
  EXPECT_EQ(a.componentCount, b.componentCount);
  EXPECT_TRUE(sameBits(a.convex.center, b.convex.center));
  EXPECT_TRUE(sameBits(a.convex.area, b.convex.area));
  EXPECT_TRUE(sameBits(a.tori.e1, b.tori.e1));
  EXPECT_TRUE(sameBits(a.tori.phiExtent, b.tori.phiExtent));
  EXPECT_TRUE(sameBits(a.tori.atomJ, b.tori.atomJ));
  EXPECT_TRUE(sameBits(a.concave.dirK, b.concave.dirK));
  EXPECT_TRUE(sameBits(a.concave.clipCount, b.concave.clipCount));
  EXPECT_TRUE(sameBits(a.clipPlanes, b.clipPlanes));
  EXPECT_TRUE(sameBits(a.mss.atoms, b.mss.atoms));
  EXPECT_TRUE(sameBits(a.mss.boundRadius, b.mss.boundRadius));
  EXPECT_TRUE(sameBits(a.cellPlanes, b.cellPlanes));
}

TEST(PatchListFile, RoundTripIsBitExact) {
  for (std::uint32_t seed = 0; seed < 20; ++seed) {
    const PatchList p = randomPatchList(seed);
    const std::string path = tempPath("roundtrip.stp");
    writePatchList(path, p);
    const PatchList q = readPatchList(path);
    SCOPED_TRACE("seed " + std::to_string(seed));
    expectIdentical(p, q);
  }
}

TEST(PatchListFile, EmptyListRoundTrips) {
  PatchList p;
  p.params.atomCount = 0;
  const std::string path = tempPath("empty.stp");
  writePatchList(path, p);
  EXPECT_EQ(readPatchList(path).patchCount(), 0u);
}

TEST(PatchListFile, EveryTruncationIsAClearError) {
  const std::string path = tempPath("full.stp");
  writePatchList(path, randomPatchList(3));
  const auto bytes = slurp(path);
  const std::string cut = tempPath("cut.stp");
  for (std::size_t n = 0; n < bytes.size(); n += 1 + n / 16) {
    spit(cut, {bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n)});
    try {
      readPatchList(cut);
      ADD_FAILURE() << "a file cut to " << n << " of " << bytes.size() << " bytes was accepted";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(cut), std::string::npos) << what;
      EXPECT_TRUE(what.find("truncated") != std::string::npos || what.find("bad magic") != std::string::npos)
          << "cut at " << n << ": " << what;
    }
  }
}

TEST(PatchListFile, AnyFlippedBodyByteFailsTheChecksum) {
  const std::string path = tempPath("flip.stp");
  writePatchList(path, randomPatchList(5));
  const auto bytes = slurp(path);
  std::mt19937 rng(1);
  for (int trial = 0; trial < 50; ++trial) {
    auto damaged = bytes;
    const std::size_t at = 24 + rng() % (bytes.size() - 24 - 4);  // inside the body
    damaged[at] ^= static_cast<unsigned char>(1u << (rng() % 8));
    spit(path, damaged);
    try {
      readPatchList(path);
      ADD_FAILURE() << "flipped byte " << at << " was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
    }
  }
}

TEST(PatchListFile, NewerVersionIsRejectedByName) {
  const std::string path = tempPath("newer.stp");
  writePatchList(path, randomPatchList(1));
  auto bytes = slurp(path);
  const std::uint32_t newer = kPatchFileVersion + 1;
  std::memcpy(bytes.data() + 8, &newer, 4);
  spit(path, bytes);
  try {
    readPatchList(path);
    FAIL() << "newer version accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("newer"), std::string::npos) << e.what();
  }
}

TEST(PatchListFile, ForeignFileIsNotAPatchList) {
  const std::string path = tempPath("foreign.stp");
  spit(path, {'A', 'T', 'O', 'M', ' ', ' ', '1', '\n', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_THROW(readPatchList(path), std::runtime_error);
  EXPECT_THROW(readPatchList(tempPath("does-not-exist.stp")), std::runtime_error);
}

TEST(PatchListFile, BigEndianFileReadsTheSame) {
  // Build the big-endian image of a file by hand: swap every scalar field in place.
  // The layout walk below is independent of the reader: header, then the body fields.
  PatchList p = randomPatchList(7);
  const std::string path = tempPath("le.stp");
  writePatchList(path, p);
  auto le = slurp(path);
  auto be = le;
  auto swapAt = [&](std::size_t at, std::size_t width) { std::reverse(be.begin() + at, be.begin() + at + width); };
  std::size_t at = 8;
  swapAt(at, 4); at += 4;  // version
  swapAt(at, 4); at += 4;  // endianness tag
  std::uint64_t bodySize;
  std::memcpy(&bodySize, le.data() + at, 8);
  swapAt(at, 8); at += 8;
  const std::size_t bodyStart = at;
  auto u32At = [&](std::size_t o) { std::uint32_t v; std::memcpy(&v, le.data() + o, 4); return v; };
  auto u64At = [&](std::size_t o) { std::uint64_t v; std::memcpy(&v, le.data() + o, 8); return v; };
  swapAt(at, 4); at += 4;  // surface
  swapAt(at, 8); at += 8;  // probe
  swapAt(at, 8); at += 8;  // shrink
  { const auto n = u32At(at); swapAt(at, 4); at += 4 + n; }  // radii set
  swapAt(at, 4); at += 4;  // crc
  swapAt(at, 4); at += 4;  // atoms
  swapAt(at, 4); at += 4;  // components
  const auto arrays = u32At(at); swapAt(at, 4); at += 4;
  for (std::uint32_t a = 0; a < arrays; ++a) {
    const auto n = u32At(at); swapAt(at, 4); at += 4 + n;
    const auto scalar = u32At(at); swapAt(at, 4); at += 4;
    const auto comps = u32At(at); swapAt(at, 4); at += 4;
    const auto count = u64At(at); swapAt(at, 8); at += 8;
    const std::size_t width = scalar == 1 ? 8 : 4;
    for (std::uint64_t k = 0; k < count * comps; ++k) { swapAt(at, width); at += width; }
  }
  ASSERT_EQ(at, bodyStart + bodySize);
  // The checksum is over the bytes as stored, written in the file's byte order.
  const auto crc = static_cast<std::uint32_t>(crc32(0L, be.data() + bodyStart, static_cast<uInt>(bodySize)));
  std::memcpy(be.data() + at, &crc, 4);
  swapAt(at, 4);
  const std::string bePath = tempPath("be.stp");
  spit(bePath, be);
  expectIdentical(p, readPatchList(bePath));
}

TEST(PatchListValidate, MismatchedLengthsAreRejected) {
  PatchList p = randomPatchList(2);
  p.tori.thetaJ.pop_back();
  EXPECT_THROW(p.validate(), std::runtime_error);
  EXPECT_THROW(writePatchList(tempPath("bad.stp"), p), std::runtime_error);
}

TEST(PatchListValidate, ClipRangePastTheEndIsRejected) {
  PatchList p = randomPatchList(2);
  p.concave.clipCount.back() += 1;
  EXPECT_THROW(p.validate(), std::runtime_error);
}

TEST(PatchListValidate, AtomOutOfRangeAndNonFiniteAreRejected) {
  PatchList p = randomPatchList(2);
  p.tori.atomI[0] = p.params.atomCount;
  EXPECT_THROW(p.validate(), std::runtime_error);
  PatchList q = randomPatchList(2);
  q.convex.radius[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(q.validate(), std::runtime_error);
  EXPECT_NO_THROW(randomPatchList(2).validate());
}

}  // namespace
}  // namespace surftrace::build
