// Patch-list container invariants and .stp file round trips, truncation and corruption.
#include "build/patch_list.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <numbers>
#include <random>
#include <regex>
#include <set>

#include <glm/geometric.hpp>
#include <zlib.h>

#include <gtest/gtest.h>

#include "build/io/molecule.hpp"
#include "build/io/stp_file.hpp"
#include "build/surface.hpp"
#include "patch_compare.hpp"
#include "temp_dir.hpp"

namespace surftrace::build {
namespace {

std::string tempPath(const std::string& name) {
  return (::surftrace::test::testTempDir() / name).string();
}

std::vector<unsigned char> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void spit(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// A valid SES patch list with every array filled with random, distinct values.
PatchList randomPatchList(std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1e3, 1e3), unit(0.0, 1.0);
  std::uniform_int_distribution<std::uint32_t> atom(0, 99);
  auto v3 = [&] { return glm::dvec3(u(rng), u(rng), u(rng)); };
  auto direction = [&] { return glm::normalize(v3()); };
  PatchList p;
  p.params.surface = SurfaceKind::Ses;
  p.params.probeRadius = 1.4 + 1e-3 * seed;
  p.params.radiiSet = "table:/some/radii.txt";
  p.params.inputCrc32 = 0xdeadbeefu ^ seed;
  p.params.atomCount = 100;
  p.componentCount = 2;
  const int nConvex = 5 + static_cast<int>(seed % 7), nTori = 3 + static_cast<int>(seed % 5), nConcave = 4;
  for (int k = 0; k < nConvex; ++k) {
    const double r = 1.0 + unit(rng);
    p.convex.center.push_back(v3());
    p.convex.radius.push_back(r);
    p.convex.atom.push_back(atom(rng));
    p.convex.component.push_back(k % 2);
    p.convex.area.push_back(4.0 * std::numbers::pi * r * r * unit(rng));
    p.convex.vectorArea.push_back(std::numbers::pi * unit(rng) * direction());
  }
  for (int k = 0; k < nTori; ++k) {
    const glm::dvec3 axis = direction();
    const std::uint32_t i = atom(rng) % 99;
    p.tori.center.push_back(v3());
    p.tori.axis.push_back(axis);
    p.tori.e1.push_back(glm::normalize(glm::cross(axis, v3())));
    p.tori.bigRadius.push_back(3.0 * unit(rng));
    p.tori.thetaI.push_back(-0.5 * std::numbers::pi * unit(rng));
    p.tori.thetaJ.push_back(0.5 * std::numbers::pi * unit(rng));
    p.tori.phiExtent.push_back(2.0 * std::numbers::pi * (1.0 - unit(rng)));
    p.tori.atomI.push_back(i);
    p.tori.atomJ.push_back(i + 1 + atom(rng) % (99 - i));
    p.tori.component.push_back(0);
  }
  for (int k = 0; k < nConcave; ++k) {
    p.concave.probe.push_back(v3());
    p.concave.dirI.push_back(direction());
    p.concave.dirJ.push_back(direction());
    p.concave.dirK.push_back(direction());
    const std::uint32_t i = atom(rng) % 98;
    p.concave.atomI.push_back(i);
    p.concave.atomJ.push_back(i + 1);
    p.concave.atomK.push_back(i + 2);
    p.concave.clipBegin.push_back(static_cast<std::uint32_t>(p.clipPlanes.size()));
    p.concave.clipCount.push_back(static_cast<std::uint32_t>(k));
    for (int c = 0; c < k; ++c) p.clipPlanes.emplace_back(direction(), u(rng));
    p.concave.component.push_back(1);
  }
  return p;
}

// A valid MSS patch list: one patch of each kind, with its cell planes.
PatchList randomMssList(std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1e3, 1e3), unit(0.0, 1.0);
  auto v3 = [&] { return glm::dvec3(u(rng), u(rng), u(rng)); };
  PatchList p;
  p.params.surface = SurfaceKind::Mss;
  p.params.shrinkFactor = 0.1 + 0.8 * unit(rng);
  p.params.inputCrc32 = 0xfeedu ^ seed;
  p.params.atomCount = 100;
  const double s = p.params.shrinkFactor;
  const glm::uvec4 simplex[4] = {{7, ~0u, ~0u, ~0u}, {1, 2, ~0u, ~0u}, {3, 5, 8, ~0u}, {10, 20, 30, 40}};
  for (std::uint32_t kind = 0; kind < 4; ++kind) {
    p.mss.kind.push_back(kind);
    p.mss.center.push_back(v3());
    p.mss.axis.push_back(kind == 0 || kind == 3 ? glm::dvec3(0, 0, 1) : glm::normalize(v3()));
    p.mss.radialCoeff.push_back(kind <= 1 ? 1.0 - s : -s);
    p.mss.axialCoeff.push_back(kind == 1 ? -1.0 : kind == 2 ? 1.0 : 0.0);
    p.mss.constant.push_back(u(rng));
    p.mss.boundRadius.push_back(5.0 * unit(rng));
    p.mss.atoms.push_back(simplex[kind]);
    p.mss.cellBegin.push_back(static_cast<std::uint32_t>(p.cellPlanes.size()));
    p.mss.cellCount.push_back(kind);
    for (std::uint32_t c = 0; c < kind; ++c) {
      p.cellPlanes.emplace_back(glm::normalize(v3()), u(rng));
      p.cellPlaneAtom.push_back(c == 0 ? ~0u : 50u + c);  // unknown, or an atom whose plane it is not
    }
  }
  return p;
}

// Bitwise equality of two doubles (a round trip must not even flip a NaN payload or -0).
template <class T> bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  // (An empty vector's data() may be null, which memcmp must not be given even for 0 bytes.)
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
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
    const PatchList p = seed % 2 == 0 ? randomPatchList(seed) : randomMssList(seed);
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

// The fuzzer's .stp seeds load: a seed the loader refuses (an older version, say) stops every
// mutation of it at the header, and the fuzzer never reaches the arrays.
TEST(PatchListFile, FuzzSeedsLoad) {
  const std::filesystem::path seeds = std::filesystem::path(SURFTRACE_TEST_DATA) / ".." / "fuzz" / "seeds" / "stp";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(seeds)) {
    EXPECT_NO_THROW(readPatchList(entry.path().string()))
        << entry.path() << ": rebuild it as tests/fuzz/README.md says";
    ++count;
  }
  EXPECT_GE(count, 5);
}

// The lists `surftrace build` writes for the test molecules pass every check, and write back
// bit for bit: SES with and without cavities, the skin at s = 0.3 and 0.5, vdW and SAS spheres.
TEST(PatchListValidate, RealListsLoadAndRoundTrip) {
  for (const char* file : {"structures/1crn.pdb", "paper/1vis.pdb.gz", "paper/1grm.pdb.gz"}) {
    const Molecule m = readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file);
    const SurfaceRequest requests[] = {{SurfaceKind::Ses, 1.4, 0.5, false}, {SurfaceKind::Ses, 1.4, 0.5, true},
                                       {SurfaceKind::Ses, 3.0, 0.5, false}, {SurfaceKind::Mss, 1.4, 0.3, false},
                                       {SurfaceKind::Mss, 1.4, 0.5, false}, {SurfaceKind::Mss, 1.4, 1.0, false},
                                       {SurfaceKind::Sas, 1.4, 0.5, false}};
    for (const SurfaceRequest& r : requests) {
      const std::string what = std::string(file) + " " + surfaceKindName(r.surface) + " rp " +
                               std::to_string(r.probeRadius) + " s " + std::to_string(r.shrinkFactor);
      const PatchList p = buildSurface(m, r);
      ASSERT_GT(p.patchCount(), 0u) << what;
      // With the atoms, as `surftrace build` writes it: the skin is stored by reference.
      const PatchListAtoms atoms{m.centers, m.radii};
      const std::string path = tempPath("real.stp"), again = tempPath("real-again.stp");
      ASSERT_NO_THROW(writePatchList(path, p, atoms)) << what;
      PatchList q;
      ASSERT_NO_THROW(q = readPatchList(path)) << what;
      test::expectSamePatchLists(q, p, what);
      writePatchList(again, q, atoms);
      EXPECT_EQ(slurp(path), slurp(again)) << what;
    }
  }
}

// Rewrites element `index` of array `name` ("tori.axis") of a file from writePatchList, or the
// bytes at `offset` when name is empty, and recomputes the checksum: damage the CRC cannot see,
// as in a file that something other than surftrace wrote.
template <class T>
void overwrite(const std::string& path, const std::string& name, std::size_t index, const T& value,
               std::size_t offset = 0) {
  auto bytes = slurp(path);
  constexpr std::size_t kHeader = 24;
  if (!name.empty()) {
    // The array's entry: u32 name length, the name, u32 type, u32 width, u64 count, the data.
    std::vector<unsigned char> key(4);
    const auto length = static_cast<std::uint32_t>(name.size());
    std::memcpy(key.data(), &length, 4);
    key.insert(key.end(), name.begin(), name.end());
    const auto at = std::search(bytes.begin() + kHeader, bytes.end(), key.begin(), key.end());
    ASSERT_NE(at, bytes.end()) << name;
    offset = static_cast<std::size_t>(at - bytes.begin()) + key.size() + 4 + 4 + 8 + index * sizeof(T);
  }
  ASSERT_LE(offset + sizeof(T), bytes.size() - 4) << name;
  std::memcpy(bytes.data() + offset, &value, sizeof(T));
  const std::size_t bodySize = bytes.size() - kHeader - 4;
  const auto crc = static_cast<std::uint32_t>(crc32(0L, bytes.data() + kHeader, static_cast<uInt>(bodySize)));
  std::memcpy(bytes.data() + kHeader + bodySize, &crc, 4);
  spit(path, bytes);
}

// Loading fails, with an error that names the file and the field and says the file is damaged.
void expectRejected(const std::string& path, const std::string& field, const std::string& value) {
  try {
    readPatchList(path);
    ADD_FAILURE() << field << " = " << value << " was accepted";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path + ": corrupt patch list: "), std::string::npos) << what;
    EXPECT_NE(what.find(field + " = " + value), std::string::npos) << what;
    EXPECT_NE(what.find("damaged"), std::string::npos) << what;
  }
}

const Molecule& crambin() {
  static const Molecule m = readMolecule(std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb");
  return m;
}

// An atom count beyond what the file can speak of (kMaxAtomsPerByte for each byte of its
// body), forged behind a valid checksum, is refused at once, naming the file, the field and
// the value: `info`, `area` and `render` sized per-atom arrays by it (10^8 in a 160 KB file
// allocated gigabytes). The count the bound allows reads; one more does not. The writer
// refuses such a list in the same words rather than write a file no reader takes.
TEST(PatchListFile, AnAtomCountTheFileCannotHoldIsRefused) {
  const PatchList p = buildSurface(crambin(), {SurfaceKind::Ses, 1.4});
  const std::string path = tempPath("forged-count.stp");
  writePatchList(path, p);
  const std::size_t body = std::filesystem::file_size(path) - 24 - 4;  // header, checksum
  // The body: u32 surface kind, f64 probe radius, f64 shrink factor, the radii set (u32 length
  // and its bytes), u32 input checksum, then the u32 atom count.
  const std::size_t at = 24 + 4 + 8 + 8 + 4 + p.params.radiiSet.size() + 4;
  const std::uint64_t most = kMaxAtomsPerByte * body;
  ASSERT_LT(most, 16777215u) << "crambin's list is larger than this test assumes";
  for (const std::uint32_t forged : {16777215u, 10000000u, 100000000u, 0xFFFFFFFFu, static_cast<std::uint32_t>(most + 1)}) {
    overwrite(path, "", 0, forged, at);
    expectRejected(path, "atom count", std::to_string(forged));
  }
  overwrite(path, "", 0, static_cast<std::uint32_t>(most), at);
  EXPECT_EQ(readPatchList(path).params.atomCount, most);

  PatchList many = p;
  many.params.atomCount = static_cast<std::uint32_t>(most + 1);
  std::filesystem::remove(tempPath("many.stp"));
  try {
    writePatchList(tempPath("many.stp"), many);
    ADD_FAILURE() << "a list of " << many.params.atomCount << " atoms in " << body << " bytes was written";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(tempPath("many.stp") + ": the list speaks of " + std::to_string(most + 1) + " atoms"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(tempPath("many.stp")));
}

// One field at a time made impossible in a real list, behind a valid checksum.
TEST(PatchListValidate, ImpossibleSesFieldsAreRejectedOnLoad) {
  const PatchList p = buildSurface(crambin(), {SurfaceKind::Ses, 1.4, 0.5, false});
  ASSERT_GE(p.componentCount, 2u);
  ASSERT_GT(p.clipPlanes.size(), 0u);
  const std::string good = tempPath("1crn-ses.stp"), bad = tempPath("1crn-ses-bad.stp");
  writePatchList(good, p);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    std::function<void()> damage;
    std::string field, value;
  };
  const Case cases[] = {
      {[&] { overwrite(bad, "convex.radius", 3, -1.5); }, "convex.radius[3]", "-1.5"},
      {[&] { overwrite(bad, "convex.radius", 3, 1e300); }, "convex.radius[3]", "1e+300"},
      {[&] { overwrite(bad, "convex.radius", 3, 0.0); }, "convex.radius[3]", "0"},
      {[&] { overwrite(bad, "convex.radius", 3, 1e-300); }, "convex.radius[3]", "1e-300"},
      {[&] { overwrite(bad, "convex.radius", 3, nan); }, "convex.radius[3]", "nan"},
      {[&] { overwrite(bad, "convex.area", 2, -1e9); }, "convex.area[2]", "-1000000000"},
      {[&] { overwrite(bad, "convex.area", 2, 1e9); }, "convex.area[2]", "1000000000"},
      {[&] { overwrite(bad, "convex.center", 1, glm::dvec3(0, 1e12, 0)); }, "convex.center[1]", "(0, 1000000000000, 0)"},
      {[&] { overwrite(bad, "convex.vectorArea", 4, glm::dvec3(0, 0, -4)); }, "convex.vectorArea[4]", "(0, 0, -4)"},
      {[&] { overwrite(bad, "convex.atom", 0, p.params.atomCount); }, "convex.atom[0]", std::to_string(p.params.atomCount)},
      {[&] { overwrite(bad, "convex.component", 6, 0xFFFFFFFFu); }, "convex.component[6]", "4294967295"},
      {[&] { overwrite(bad, "tori.axis", 17, glm::dvec3(0.0)); }, "tori.axis[17]", "(0, 0, 0)"},
      {[&] { overwrite(bad, "tori.e1", 5, p.tori.axis[5]); }, "tori.e1[5]", ""},
      {[&] { overwrite(bad, "tori.bigRadius", 9, -2.0); }, "tori.bigRadius[9]", "-2"},
      {[&] { overwrite(bad, "tori.thetaI", 2, -4.0); }, "tori.thetaI[2]", "-4"},
      {[&] { overwrite(bad, "tori.thetaJ", 2, -1.5); }, "tori.thetaJ[2]", "-1.5"},
      {[&] { overwrite(bad, "tori.phiExtent", 8, 7.0); }, "tori.phiExtent[8]", "7"},
      {[&] { overwrite(bad, "tori.phiExtent", 8, 0.0); }, "tori.phiExtent[8]", "0"},
      {[&] { overwrite(bad, "tori.atomJ", 3, p.tori.atomI[3]); }, "tori.atomJ[3]", std::to_string(p.tori.atomI[3])},
      {[&] { overwrite(bad, "tori.component", 5, 0xFFFFFFFFu); }, "tori.component[5]", "4294967295"},
      {[&] { overwrite(bad, "concave.atomK", 1, p.params.atomCount); }, "concave.atomK[1]", std::to_string(p.params.atomCount)},
      {[&] { overwrite(bad, "concave.atomK", 1, p.concave.atomI[1]); }, "concave.atomK[1]", std::to_string(p.concave.atomI[1])},
      {[&] { overwrite(bad, "concave.dirJ", 4, glm::dvec3(2, 0, 0)); }, "concave.dirJ[4]", "(2, 0, 0)"},
      {[&] { overwrite(bad, "concave.clipCount", 0, static_cast<std::uint32_t>(p.clipPlanes.size() + 1)); },
       "concave.clipCount[0]", std::to_string(p.clipPlanes.size() + 1)},
      {[&] { overwrite(bad, "concave.clipBegin", 0, 0xFFFFFFF0u); }, "concave.clipCount[0]", ""},
      {[&] { overwrite(bad, "concave.component", 7, p.componentCount); }, "concave.component[7]", std::to_string(p.componentCount)},
      {[&] { overwrite(bad, "clipPlanes.plane", 0, glm::dvec4(0, 0, 0, 1)); }, "clipPlanes.plane[0]", "(0, 0, 0, 1)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.field + " = " + c.value);
    std::filesystem::copy_file(good, bad, std::filesystem::copy_options::overwrite_existing);
    c.damage();
    expectRejected(bad, c.field, c.value);
  }
  // The parameters, at their place in the body: u32 surface, f64 probe, f64 shrink, the radii
  // set (u32 length + text), u32 input CRC, u32 atom count, u32 component count.
  const std::size_t probe = 24 + 4, shrink = probe + 8, components = shrink + 8 + 4 + p.params.radiiSet.size() + 8;
  for (double rp : {-1.0, 0.0, 1e300, nan}) {
    std::filesystem::copy_file(good, bad, std::filesystem::copy_options::overwrite_existing);
    overwrite(bad, "", 0, rp, probe);
    expectRejected(bad, "params.probeRadius", "");
  }
  for (double s : {0.0, 1.5, nan}) {
    std::filesystem::copy_file(good, bad, std::filesystem::copy_options::overwrite_existing);
    overwrite(bad, "", 0, s, shrink);
    expectRejected(bad, "params.shrinkFactor", "");
  }
  std::filesystem::copy_file(good, bad, std::filesystem::copy_options::overwrite_existing);
  overwrite(bad, "", 0, 0xFFFFFFFFu, components);
  expectRejected(bad, "componentCount", "4294967295");
  // One component more than the patches carry: `area` would report an empty cavity.
  std::filesystem::copy_file(good, bad, std::filesystem::copy_options::overwrite_existing);
  overwrite(bad, "", 0, p.componentCount + 1, components);
  expectRejected(bad, "componentCount", std::to_string(p.componentCount + 1) + ", but no patch is of component " +
                                            std::to_string(p.componentCount));
}

TEST(PatchListValidate, ImpossibleMssFieldsAreRejectedOnLoad) {
  const PatchList p = buildSurface(crambin(), {SurfaceKind::Mss, 1.4, 0.5, false});
  const auto [edges, edgesEnd] = mssKindRange(p.mss, MssKind::Edge);
  ASSERT_LT(edges, edgesEnd);
  ASSERT_GT(p.mss.cellCount[edges], 0u);
  // A version-2 file, which stores every field (version 3 derives them: see below).
  const std::string good = tempPath("1crn-mss.stp"), bad = tempPath("1crn-mss-bad.stp");
  spit(good, encodePatchList(p, {}, 2));
  const std::string e = std::to_string(edges);
  struct Case {
    std::function<void()> damage;
    std::string field, value;
  };
  const Case cases[] = {
      {[&] { overwrite(bad, "mss.kind", 0, 7u); }, "mss.kind[0]", "7"},
      {[&] { overwrite(bad, "mss.kind", edges - 1, 2u); }, "mss.kind[" + e + "]", "1"},
      {[&] { overwrite(bad, "mss.axis", edges, glm::dvec3(0.0)); }, "mss.axis[" + e + "]", "(0, 0, 0)"},
      {[&] { overwrite(bad, "mss.radialCoeff", edges, 0.0); }, "mss.radialCoeff[" + e + "]", "0"},
      {[&] { overwrite(bad, "mss.axialCoeff", edges, 1.0); }, "mss.axialCoeff[" + e + "]", "1"},
      {[&] { overwrite(bad, "mss.constant", 0, 1e30); }, "mss.constant[0]", "1e+30"},
      {[&] { overwrite(bad, "mss.boundRadius", 3, -1.0); }, "mss.boundRadius[3]", "-1"},
      {[&] { overwrite(bad, "mss.center", 3, glm::dvec3(-1e10, 0, 0)); }, "mss.center[3]", "(-10000000000, 0, 0)"},
      {[&] { overwrite(bad, "mss.atoms", 0, glm::uvec4(p.params.atomCount, ~0u, ~0u, ~0u)); }, "mss.atoms[0]", ""},
      {[&] { overwrite(bad, "mss.atoms", edges, glm::uvec4(5, 5, ~0u, ~0u)); }, "mss.atoms[" + e + "]", "(5, 5, "},
      {[&] { overwrite(bad, "mss.atoms", 0, glm::uvec4(0, 0, ~0u, ~0u)); }, "mss.atoms[0]", "(0, 0, "},
      {[&] { overwrite(bad, "mss.cellCount", edges, static_cast<std::uint32_t>(p.cellPlanes.size() + 1)); },
       "mss.cellCount[" + e + "]", std::to_string(p.cellPlanes.size() + 1)},
      {[&] { overwrite(bad, "cellPlanes.plane", 2, glm::dvec4(0, 0, 0.5, 0)); }, "cellPlanes.plane[2]", "(0, 0, 0.5, 0)"},
      {[&] { overwrite(bad, "cellPlanes.plane", 2, glm::dvec4(1, 0, 0, -1e20)); }, "cellPlanes.plane[2]", "(1, 0, 0, -1e+20)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.field + " = " + c.value);
    std::filesystem::copy_file(good, bad, std::filesystem::copy_options::overwrite_existing);
    c.damage();
    expectRejected(bad, c.field, c.value);
  }
  // An SES surface kind over the skin's arrays: the kinds do not mix.
  std::filesystem::copy_file(good, bad, std::filesystem::copy_options::overwrite_existing);
  overwrite(bad, "", 0, static_cast<std::uint32_t>(SurfaceKind::Ses), 24);
  try {
    readPatchList(bad);
    ADD_FAILURE() << "an SES list with MSS patches was accepted";
  } catch (const std::runtime_error& err) {
    EXPECT_NE(std::string(err.what()).find("mss has " + std::to_string(p.mss.size()) + " entries, but a ses list"),
              std::string::npos)
        << err.what();
  }
}

// validate() (run by writePatchList) names the field as the loader does.
TEST(PatchListValidate, WriteRefusesAnImpossibleList) {
  PatchList p = randomPatchList(4);
  p.tori.axis[1] = glm::dvec3(0.0);
  try {
    writePatchList(tempPath("never.stp"), p);
    FAIL() << "an impossible list was written";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("patch list: tori.axis[1] = (0, 0, 0) is not a unit vector"), std::string::npos)
        << e.what();
  }
}

// Version 3 derives the skin's quadrics and planes from the atoms with the builder's own
// functions: the lists of 1CRN, 1GRM and 1VIS come back bit for bit, array for array, in a
// file that stores no patch or plane whole (its size is that of the references alone) and is
// under a fifth of version 2's. Without the atoms every patch is stored whole, bit for bit too.
TEST(PatchListFile, SkinByReferenceRoundTripsBitExact) {
  for (const char* file : {"structures/1crn.pdb", "paper/1grm.pdb.gz", "paper/1vis.pdb.gz"}) {
    const Molecule m = readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file);
    for (const double s : {0.3, 0.5, 0.9}) {
      const std::string what = std::string(file) + " s " + std::to_string(s);
      const PatchList p = buildSurface(m, {SurfaceKind::Mss, 1.4, s, false});
      ASSERT_GT(p.mss.size(), 0u) << what;
      ASSERT_EQ(p.skinAtoms.size(), m.size()) << what;
      // A list without its atoms (not the builder's) is stored whole.
      PatchList bare = p;
      bare.skinAtoms = {};
      const std::vector<unsigned char> v3 = encodePatchList(p, {m.centers, m.radii}), own = encodePatchList(p);
      const std::vector<unsigned char> whole = encodePatchList(bare), v2 = encodePatchList(p, {}, 2);
      test::expectSamePatchLists(parsePatchList(v3, "v3.stp"), p, what + " by reference");
      test::expectSamePatchLists(parsePatchList(own, "own.stp"), p, what + " by reference to its own atoms");
      EXPECT_EQ(own, v3) << what;
      test::expectSamePatchLists(parsePatchList(whole, "whole.stp"), bare, what + " whole");
      // References only: the atoms (32 bytes), per patch its simplex and plane count (20), per
      // plane its atom (4), and the table's names and lengths.
      const std::size_t references = 32 * m.size() + 20 * p.mss.size() + 4 * p.cellPlanes.size();
      EXPECT_LE(v3.size(), references + 4096) << what;
      EXPECT_LT(5 * v3.size(), v2.size()) << what;
      // Version 2 holds everything but the atoms across the planes, which read as not known,
      // and the skin's atoms, which read as none.
      PatchList old = parsePatchList(v2, "v2.stp");
      EXPECT_EQ(old.cellPlaneAtom, std::vector<std::uint32_t>(p.cellPlanes.size(), ~0u)) << what;
      old.cellPlaneAtom = p.cellPlaneAtom;
      EXPECT_EQ(old.skinAtoms.size(), 0u) << what;
      old.skinAtoms = p.skinAtoms;
      test::expectSamePatchLists(old, p, what + " version 2");
    }
  }
}

// Files written by the version-2 writer before version 3 existed (tests/data/stp, MANIFEST.md)
// read as the lists built now from the same structures, every array bit for bit (the atoms
// across the planes, which version 2 did not store, read as not known).
TEST(PatchListFile, Version2FilesStillRead) {
  const std::string dir = std::string(SURFTRACE_TEST_DATA) + "/";
  const Molecule m = readMolecule(dir + "small/tiny.pdb");
  const struct {
    const char* file;
    SurfaceRequest request;
  } cases[] = {{"stp/tiny_ses_v2.stp", {SurfaceKind::Ses, 1.4, 0.5, false}},
               {"stp/tiny_mss_v2.stp", {SurfaceKind::Mss, 1.4, 0.5, false}}};
  for (const auto& c : cases) {
    const std::vector<unsigned char> bytes = slurp(dir + c.file);
    ASSERT_GT(bytes.size(), 12u) << c.file;
    std::uint32_t version;
    std::memcpy(&version, bytes.data() + 8, 4);
    EXPECT_EQ(version, 2u) << c.file;
    PatchList old = readPatchList(dir + c.file);
    PatchList now = buildSurface(m, c.request);
    ASSERT_GT(now.patchCount(), 0u) << c.file;
    EXPECT_EQ(old.cellPlaneAtom, std::vector<std::uint32_t>(now.cellPlanes.size(), ~0u)) << c.file;
    old.cellPlaneAtom = now.cellPlaneAtom;
    EXPECT_EQ(old.skinAtoms.size(), 0u) << c.file;
    old.skinAtoms = now.skinAtoms;
    test::expectSamePatchLists(old, now, c.file);
  }
  // Version 1 is refused with the file, its version and what to do.
  auto bytes = slurp(dir + cases[0].file);
  const std::uint32_t one = 1;
  std::memcpy(bytes.data() + 8, &one, 4);
  const std::string path = tempPath("v1.stp");
  spit(path, bytes);
  try {
    readPatchList(path);
    FAIL() << "version 1 accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": patch list version 1 was written by an older SurfTrace"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("rebuild it with `surftrace build`"), std::string::npos) << e.what();
  }
}

// A version-3 skin cut anywhere is a clear error, as an SES list is.
TEST(PatchListFile, EveryTruncationOfASkinIsAClearError) {
  const PatchList p = buildSurface(crambin(), {SurfaceKind::Mss, 1.4, 0.5, false});
  const auto bytes = encodePatchList(p, {crambin().centers, crambin().radii});
  const std::string cut = tempPath("cut-mss.stp");
  for (std::size_t n = 0; n < bytes.size(); n += 1 + n / 8) {
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

// The references of a version-3 skin damaged behind a valid checksum: each is an error that
// names the file and the entry, never a crash, an abort in the exact arithmetic or a wrong list.
TEST(PatchListValidate, DamagedSkinReferencesAreRejectedOnLoad) {
  const Molecule& m = crambin();
  const PatchList p = buildSurface(m, {SurfaceKind::Mss, 1.4, 0.5, false});
  const auto [edges, edgesEnd] = mssKindRange(p.mss, MssKind::Edge);
  const auto [faces, facesEnd] = mssKindRange(p.mss, MssKind::Face);
  const auto [tets, tetsEnd] = mssKindRange(p.mss, MssKind::Concave);
  ASSERT_LT(edges, edgesEnd);
  ASSERT_LT(faces, facesEnd);
  ASSERT_LT(tets, tetsEnd);
  ASSERT_GT(p.mss.cellCount[tets], 0u);
  const std::string good = tempPath("1crn-mss-v3.stp"), bad = tempPath("1crn-mss-v3-bad.stp");
  writePatchList(good, p, {m.centers, m.radii});
  // An atom that is not one of the first tetrahedron's: its plane is no face of that cell.
  const glm::uvec4 t = p.mss.atoms[tets];
  std::uint32_t stranger = 0;
  while (stranger == t[0] || stranger == t[1] || stranger == t[2] || stranger == t[3]) ++stranger;
  const std::uint32_t plane = p.mss.cellBegin[tets];
  const glm::uvec4 f = p.mss.atoms[faces];
  const std::string e = std::to_string(edges), tp = std::to_string(plane);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    std::function<void()> damage;
    std::string field, value;
  };
  const Case cases[] = {
      {[&] { overwrite(bad, "mss.atoms", edges, glm::uvec4(5, 5, ~0u, ~0u)); }, "mss.atoms[" + e + "]", "(5, 5, "},
      {[&] { overwrite(bad, "mss.atoms", 0, glm::uvec4(~0u, ~0u, ~0u, ~0u)); }, "mss.atoms[", ""},
      {[&] { overwrite(bad, "skin.center", 3, glm::dvec3(nan, 0, 0)); }, "skin.center[3]", "(nan, 0, 0)"},
      {[&] { overwrite(bad, "skin.center", 3, glm::dvec3(2e9, 0, 0)); }, "skin.center[3]", "(2000000000, 0, 0)"},
      {[&] { overwrite(bad, "skin.weight", 4, -1.0); }, "skin.weight[4]", "-1"},
      {[&] { overwrite(bad, "cellPlanes.atom", plane, stranger); }, "cellPlanes.atom[" + tp + "]",
       std::to_string(stranger) + " is not an atom across a face of mss patch " + std::to_string(tets)},
      {[&] { overwrite(bad, "cellPlanes.atom", plane, p.params.atomCount); }, "cellPlanes.atom[" + tp + "]",
       std::to_string(p.params.atomCount)},
      {[&] { overwrite(bad, "mss.cellCount", 0, 0xFFFFFFFFu); }, "mss.cellCount[0]", "4294967295 runs past"},
      // The face's third atom moved onto its first: a degenerate triangle, whose exact
      // orthocentre divides by zero. Some patch with that atom is refused first.
      {[&] { overwrite(bad, "skin.center", f[2], m.centers[f[0]]); }, "", ""},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.field + " = " + c.value);
    std::filesystem::copy_file(good, bad, std::filesystem::copy_options::overwrite_existing);
    c.damage();
    try {
      readPatchList(bad);
      ADD_FAILURE() << c.field << " = " << c.value << " was accepted";
    } catch (const std::runtime_error& err) {
      const std::string what = err.what();
      EXPECT_NE(what.find(bad + ": corrupt patch list: "), std::string::npos) << what;
      EXPECT_NE(what.find(c.field + (c.value.empty() ? "" : " = " + c.value)), std::string::npos) << what;
      EXPECT_NE(what.find("damaged"), std::string::npos) << what;
    }
  }
}

// Reading a .stp needs the list, its checks and the skin's geometry, never a builder: every
// header the reader's translation unit reaches (quoted includes, followed through src/) is
// outside build/ses/, build/mss/ but skin_geometry.hpp, and the builders' pipeline.
TEST(PatchListFile, TheReaderIncludesNoBuilder) {
  const std::filesystem::path src = std::filesystem::path(SURFTRACE_SOURCE_DIR) / "src";
  const std::regex include("^\\s*#\\s*include\\s+\"([^\"]+)\"");
  const std::regex builder("build/(ses/.*|mss/(?!skin_geometry\\.hpp$).*|surface\\.hpp|neighbour_grid\\.hpp|atom_culling\\.hpp)");
  std::set<std::string> seen;
  std::vector<std::string> todo{"build/io/stp_file.cpp"};
  while (!todo.empty()) {
    const std::string file = todo.back();
    todo.pop_back();
    if (!seen.insert(file).second) continue;
    std::ifstream in(src / file);
    ASSERT_TRUE(in) << (src / file) << " (reached from build/io/stp_file.cpp)";
    std::string line;
    std::smatch m;
    while (std::getline(in, line))
      if (std::regex_search(line, m, include)) {
        const std::string header = m[1];
        EXPECT_FALSE(std::regex_match(header, builder)) << file << " includes the builder header " << header;
        if (std::filesystem::exists(src / header)) todo.push_back(header);
      }
  }
  EXPECT_GT(seen.size(), 3u);
}

// The shrink factors served are s in [1e-3, 1] (the --shrink option's range), with s = 1 the
// vdW spheres: buildSurface, the patch list's checks and the .stp reader take exactly those.
TEST(ShrinkFactor, OneRangeForRequestBuilderAndFile) {
  const Molecule m = readMolecule(std::string(SURFTRACE_TEST_DATA) + "/small/tiny.pdb");
  for (double s : {-0.5, 0.0, 1e-200, 5e-4, 0.000999, 1e-3, 0.25, 0.5, 0.999, 1.0, 1.0000001, 1.5, HUGE_VAL,
                   std::nan("")}) {
    SCOPED_TRACE("s = " + testing::PrintToString(s));
    const bool served = s >= 0.001 && s <= 1.0;
    EXPECT_EQ(validShrinkFactor(s), served);
    EXPECT_EQ(skinBuiltWithCells(s), served && s < 1.0);
    PatchList list;
    try {
      list = buildSurface(m, {SurfaceKind::Mss, 1.4, s, false});
    } catch (const std::invalid_argument&) {
      EXPECT_FALSE(served) << "buildSurface refused a served shrink factor";
      continue;
    }
    ASSERT_TRUE(served) << "buildSurface built an MSS request the option refuses";
    EXPECT_EQ(list.params.surface, s == 1.0 ? SurfaceKind::Vdw : SurfaceKind::Mss);
    EXPECT_EQ(list.params.shrinkFactor, s);
    EXPECT_NO_THROW(parsePatchList(encodePatchList(list, {m.centers, m.radii}), "served.stp"));
  }
  // A skin list speaks of a factor below 1e-3 or at 1 only when damaged: the reader refuses it
  // as the builder does (an empty list: nothing else in it to refuse).
  for (double s : {5e-4, 1.0}) {
    PatchList skin;
    skin.params.surface = SurfaceKind::Mss;
    skin.params.shrinkFactor = s;
    try {
      skin.validate();
      ADD_FAILURE() << "an MSS list at s = " << s << " validates";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("params.shrinkFactor"), std::string::npos) << e.what();
    }
  }
}

// Framing a list file alone reaches as far as framing its structure: each convex sphere's
// reach is its atom's (SurfaceRequest::reach), for the SES (r + rp), SAS (spheres of r + rp) and
// vdW spheres (also the skin at s = 1).
TEST(SurfaceReach, ConvexSpheresReachAsFarAsTheirAtoms) {
  const Molecule m = readMolecule(std::string(SURFTRACE_TEST_DATA) + "/small/tiny.pdb");
  for (const SurfaceRequest& r : {SurfaceRequest{SurfaceKind::Ses, 1.4, 0.5, false},
                                  SurfaceRequest{SurfaceKind::Ses, 3.0, 0.5, false},
                                  SurfaceRequest{SurfaceKind::Sas, 1.4, 0.5, false},
                                  SurfaceRequest{SurfaceKind::Vdw, 1.4, 0.5, false},
                                  SurfaceRequest{SurfaceKind::Mss, 1.4, 1.0, false}}) {
    const PatchList list = buildSurface(m, r);
    SCOPED_TRACE(std::string(surfaceKindName(list.params.surface)) + " rp " + std::to_string(r.probeRadius));
    ASSERT_GT(list.convex.size(), 0u);
    const std::vector<double> fromList = SurfaceRequest::of(list.params).reachOfSpheres(list.convex.radius);
    const std::vector<double> fromAtoms = r.reach(m.radii);
    ASSERT_EQ(fromList.size(), list.convex.size());
    for (std::size_t k = 0; k < list.convex.size(); ++k) EXPECT_EQ(fromList[k], fromAtoms[list.convex.atom[k]]) << k;
  }
}

}  // namespace
}  // namespace surftrace::build
