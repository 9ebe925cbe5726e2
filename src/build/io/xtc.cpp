// GROMACS XTC trajectories: an index of frame offsets built at open, and a decoder of the
// compressed coordinates that yields the same floats as xdrfile.
//
// Why our own decoder and not GROMACS: Debian's libgromacs-dev (2022.5) was weighed.
// libgromacs7 is 70 MB installed and pulls in OpenMPI, FFTW, hwloc, LAPACK and muparser; its
// installed header gromacs/fileio/trxio.h offers only sequential read_first_frame /
// read_next_frame (no seek to a frame offset) and needs a gmx_output_env_t. The format is
// small and published (xdrfile's xdr3dfcoord, Frans van Hoesel's algorithm), so this file
// decodes it, written from the description, with every field checked: a corrupt or hostile
// file gives an InputError, never undefined behaviour or an allocation the file cannot back.
//
// Frame layout (XDR: big-endian 32-bit ints and IEEE floats):
//   int magic (1995), int natoms, int step, float time (ps), float box[3][3] (nm, rows a b c),
//   int natoms again; then natoms <= 9: float xyz[natoms][3] (nm), uncompressed; else
//   float precision, int minint[3], int maxint[3], int smallidx, int byteCount,
//   byteCount bytes of bit-packed integers, zero-padded to a multiple of 4.
// The packed stream is read most significant bit first. Each "big" atom is its integer
// coordinates minus minint, either as one mixed-radix number of sizeofints(sizes) bits
// (sizes = maxint - minint + 1, when all fit in 24 bits) or as three plain fields. Then
// one flag bit; if set, 5 bits give run + (is_smaller + 1) with run a multiple of 3 (the
// run length persists while the flag is 0). A run of run/3 "small" atoms follows, each
// a mixed-radix number of smallidx bits in base magicints[smallidx], relative to the atom
// before it; the first small atom and the big one are swapped (water: H O H is written
// O H H). smallidx then moves by is_smaller (-1, 0, +1).
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/geometric.hpp>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "build/core/assert.hpp"
#include "build/io/binary_reader.hpp"
#include "build/io/trajectory.hpp"

namespace surftrace::build {

namespace {

constexpr std::int32_t kXtcMagic = 1995;
// GROMACS 2023 writes this magic (and a 64-bit byte count) for systems of more than
// 298 million atoms; we do not read that variant.
constexpr std::int32_t kXtcLargeMagic = 2023;

constexpr std::uint64_t kCoordinatesAt = 56;  // after magic, natoms, step, time, box, natoms
constexpr float kMinPrecision = 1.0f, kMaxPrecision = 1e9f;  // see decodeCompressed
constexpr std::uint64_t kBlockAt = 92;        // after precision, minint, maxint, smallidx, count
constexpr std::int64_t kMaxUncompressedAtoms = 9;
// Bits of one atom at most: three 32-bit fields, the run flag and 5 run bits. A byte count
// above this bound for the frame's atoms is corruption, not a long frame.
constexpr std::uint64_t kMaxBitsPerAtom = 3 * 32 + 1 + 5;
// Bits of one atom at least: one bit of coordinates and the run flag (small atoms take more).
constexpr std::uint64_t kMinBitsPerAtom = 2;
// The reader looks 8 bytes ahead of the bit it is at; the frame buffer has this many zero
// bytes after its end so the look-ahead never leaves it.
constexpr std::size_t kLookAhead = 8;

// xdrfile's table of bases for the small atoms: about 2^(i/3), with the odd values (5060,
// 524287, 8388607) of the original, which the bit counts of written files depend on.
constexpr std::array<std::uint32_t, 73> kMagicInts = {
    0,        0,        0,       0,       0,       0,       0,       0,       0,       8,
    10,       12,       16,      20,      25,      32,      40,      50,      64,      80,
    101,      128,      161,     203,     256,     322,     406,     512,     645,     812,
    1024,     1290,     1625,    2048,    2580,    3250,    4096,    5060,    6501,    8192,
    10321,    13003,    16384,   20642,   26007,   32768,   41285,   52015,   65536,   82570,
    104031,   131072,   165140,  208063,  262144,  330280,  416127,  524287,  660561,  832255,
    1048576,  1321122,  1664510, 2097152, 2642245, 3329021, 4194304, 5284491, 6658042, 8388607,
    10568983, 13316085, 16777216};
constexpr std::int64_t kFirstSmallIdx = 9;  // the first non-zero entry
constexpr std::int64_t kLastSmallIdx = static_cast<std::int64_t>(kMagicInts.size()) - 1;
// Above this the three sizes are too large to pack as one mixed-radix number.
constexpr std::uint64_t kMaxPackedSize = 0xffffff;

using binary::bytesText;

// XDR: big-endian 32-bit ints and IEEE floats.
constexpr binary::ByteOrder kXdr{.big = true};
std::int32_t xdrInt(const unsigned char* p) { return kXdr.i32(p); }
float xdrFloat(const unsigned char* p) { return kXdr.f32(p); }

std::string floatText(float x) {
  std::array<char, 32> text{};
  const auto end = std::to_chars(text.data(), text.data() + text.size(), x).ptr;
  return std::string(text.data(), end);
}

// Number of bits of n (0 for 0): what sizeofint and sizeofints compute.
unsigned bitLength(std::uint64_t n) { return static_cast<unsigned>(std::bit_width(n)); }

// Bit length of s0 * s1 * s2 (each < 2^24, so the product < 2^72) without overflow.
unsigned productBitLength(std::uint64_t s0, std::uint64_t s1, std::uint64_t s2) {
  const std::uint64_t p = s0 * s1;                          // < 2^48
  const std::uint64_t low = (p & 0xffffffffu) * s2;         // < 2^56
  const std::uint64_t high = (p >> 32) * s2 + (low >> 32);  // the product >> 32, < 2^41
  return high == 0 ? bitLength(low) : 32 + bitLength(high);
}

// Something wrong inside one compressed block; XtcSource::read adds file, frame and offset.
struct BlockError {
  std::string message;
};

// The packed stream, most significant bit first, bounded by the block's byte count.
class BitReader {
 public:
  // `data` must stay readable for kLookAhead bytes past `bytes`.
  BitReader(const unsigned char* data, std::uint64_t bytes) : data_(data), endBit_(8 * bytes) {}

  // The next n bits (1 <= n <= kMaxTake) as an unsigned number.
  static constexpr unsigned kMaxTake = 57;
  std::uint64_t take(unsigned n, const char* what) {
    SURFTRACE_ASSERT(n >= 1 && n <= kMaxTake);
    if (n > endBit_ - bit_) overrun(n, what);
    std::uint64_t window = 0;
    std::memcpy(&window, data_ + (bit_ >> 3), sizeof window);
    if constexpr (std::endian::native == std::endian::little) window = __builtin_bswap64(window);
    const auto shift = static_cast<unsigned>(bit_ & 7);
    bit_ += n;
    // shift + n <= 64, so the window holds all n bits.
    return (window << shift) >> (64 - n);
  }

  // Three integers packed as one mixed-radix number of `bits` bits (<= 72), digits in bases
  // sizes[0..2] (each 1..2^24), most significant first. The bits come as bytes, least
  // significant byte first, the last one holding the leftover bits.
  void takeInts(unsigned bits, const std::array<std::uint64_t, 3>& sizes,
                std::array<std::uint64_t, 3>& out, const char* what) {
    std::uint64_t low = 0;                           // bytes 0..7 of the number
    std::uint64_t high = 0;                          // byte 8
    const unsigned fullBytes = (bits - 1) / 8;       // 8-bit chunks before the last one
    const unsigned lastBits = bits - 8 * fullBytes;  // 1..8
    if (bits <= kMaxTake) {
      // One read; the chunks, first one most significant in w, reversed into place.
      const std::uint64_t w = take(bits, what);
      if (fullBytes > 0) low = __builtin_bswap64(w >> lastBits) >> (64 - 8 * fullBytes);
      low |= (w & ((1u << lastBits) - 1)) << (8 * fullBytes);
    } else {
      for (unsigned byte = 0; byte < fullBytes; ++byte) low |= take(8, what) << (8 * byte);
      const std::uint64_t last = take(lastBits, what);
      if (fullBytes < 8)
        low |= last << (8 * fullBytes);
      else
        high = last;  // bits 65..72
    }
    for (std::size_t i = 2; i > 0; --i) out[i] = divide(high, low, sizes[i]);
    if (high != 0 || low >= sizes[0]) outOfRange(what);
    out[0] = low;
  }

 private:
  // Out of line, so that the hot paths stay small enough to inline.
  [[noreturn]] [[gnu::noinline]] void overrun(unsigned n, const char* what) const {
    throw BlockError{std::string("reading ") + what + " needs " + std::to_string(n) +
                     " bits at bit " + std::to_string(bit_) + ", past the end of the block (" +
                     std::to_string(endBit_) + " bits)"};
  }
  [[noreturn]] [[gnu::noinline]] void outOfRange(const char* what) const {
    throw BlockError{std::string(what) + ": packed number beyond its range (at bit " +
                     std::to_string(bit_) + ")"};
  }

  // (high:low) /= d in place, returns the remainder; high < 2^8, 0 < d <= 2^24. Long division
  // in 32-bit limbs keeps every partial dividend below d * 2^32 < 2^56.
  static std::uint64_t divide(std::uint64_t& high, std::uint64_t& low, std::uint64_t d) {
    if (high == 0 && low <= 0xffffffffu) {
      // Most numbers (small atoms, compact boxes) fit 32 bits, and 32-bit division is faster.
      const auto l = static_cast<std::uint32_t>(low);
      const auto d32 = static_cast<std::uint32_t>(d);
      low = l / d32;
      return l % d32;
    }
    if (high == 0) {
      const std::uint64_t r = low % d;
      low /= d;
      return r;
    }
    std::uint64_t r = high % d;
    high /= d;
    std::uint64_t cur = (r << 32) | (low >> 32);
    const std::uint64_t q1 = cur / d;
    r = cur % d;
    cur = (r << 32) | (low & 0xffffffffu);
    const std::uint64_t q0 = cur / d;
    low = (q1 << 32) | q0;
    return cur % d;
  }

  const unsigned char* data_;
  std::uint64_t endBit_;
  std::uint64_t bit_ = 0;
};

// The compressed coordinates of one frame as xdrfile's integers, then as its floats (nm):
// (float)integer * (1.0f / precision), evaluated in float. Positions come out in Å.
void decodeCompressed(const unsigned char* frameBytes, std::uint64_t blockBytes,
                      std::vector<glm::dvec3>& positions) {
  const auto natoms = static_cast<std::int64_t>(positions.size());
  const float precision = xdrFloat(frameBytes + kCoordinatesAt);
  if (!(std::isfinite(precision) && precision > 0.0f))
    throw BlockError{"precision " + floatText(precision) + " is not a positive number"};
  // GROMACS writes 1000 (coordinates to 0.001 nm) unless told otherwise. Below 1 every
  // coordinate is rounded to more than a nanometre; above 1e9 no coordinate beyond ±2 nm fits
  // the 32-bit integers: neither comes from a simulation of molecules.
  if (precision < kMinPrecision || precision > kMaxPrecision)
    throw BlockError{"precision " + floatText(precision) + " (coordinates in units of 1/precision nm) is outside " +
                     floatText(kMinPrecision) + ".." + floatText(kMaxPrecision) +
                     ": not a value a simulation writes; the file is damaged"};
  std::array<std::int64_t, 3> minint{};
  std::array<std::int64_t, 3> maxint{};
  std::array<std::uint64_t, 3> sizes{};
  for (std::size_t d = 0; d < 3; ++d) {
    minint[d] = xdrInt(frameBytes + kCoordinatesAt + 4 + 4 * d);
    maxint[d] = xdrInt(frameBytes + kCoordinatesAt + 16 + 4 * d);
    if (maxint[d] < minint[d])
      throw BlockError{"integer bounds " + std::to_string(minint[d]) + " > " +
                       std::to_string(maxint[d]) + " in dimension " + std::to_string(d + 1)};
    sizes[d] = static_cast<std::uint64_t>(maxint[d] - minint[d]) + 1;
    // xdrfile holds the size in 32 bits; no writer reaches 2^32 (|x| <= INT_MAX - 2).
    if (sizes[d] > 0xffffffffu)
      throw BlockError{"integer range of dimension " + std::to_string(d + 1) +
                       " overflows 32 bits"};
  }
  std::int64_t smallIdx = xdrInt(frameBytes + kCoordinatesAt + 28);
  if (smallIdx < kFirstSmallIdx || smallIdx > kLastSmallIdx)
    throw BlockError{"smallidx " + std::to_string(smallIdx) + " is outside " +
                     std::to_string(kFirstSmallIdx) + ".." + std::to_string(kLastSmallIdx)};

  // All coordinates lie in [minint, maxint] (checked below), so one product bounds them all.
  const float invPrecision = 1.0f / precision;
  const std::int64_t largest =
      std::max({-minint[0], -minint[1], -minint[2], maxint[0], maxint[1], maxint[2]});
  if (!std::isfinite(static_cast<float>(largest) * invPrecision))
    throw BlockError{"precision " + floatText(precision) +
                     " makes the coordinates overflow a float"};

  const bool threeFields = std::max({sizes[0], sizes[1], sizes[2]}) > kMaxPackedSize;
  const std::array<unsigned, 3> fieldBits = {bitLength(sizes[0]), bitLength(sizes[1]),
                                             bitLength(sizes[2])};
  const unsigned packedBits = threeFields ? 0 : productBitLength(sizes[0], sizes[1], sizes[2]);

  auto magic = [](std::int64_t idx) {
    return static_cast<std::int64_t>(kMagicInts[static_cast<std::size_t>(idx)]);
  };
  std::int64_t smaller = magic(std::max(kFirstSmallIdx, smallIdx - 1)) / 2;
  std::int64_t smallNum = magic(smallIdx) / 2;

  BitReader bits(frameBytes + kBlockAt, blockBytes);
  std::array<std::uint64_t, 3> raw{};
  std::array<std::int64_t, 3> big{};
  std::array<std::int64_t, 3> prev{};
  std::array<std::int64_t, 3> cur{};
  std::int64_t atom = 0;
  std::int64_t run = 0;
  auto emit = [&](const std::array<std::int64_t, 3>& c) {
    // double(float) * 10 is exact: float's 24-bit significand times 10 fits a double.
    positions[static_cast<std::size_t>(atom++)] =
        glm::dvec3(static_cast<double>(static_cast<float>(c[0]) * invPrecision),
                   static_cast<double>(static_cast<float>(c[1]) * invPrecision),
                   static_cast<double>(static_cast<float>(c[2]) * invPrecision)) *
        10.0;
  };
  auto atomText = [&] { return "atom " + std::to_string(atom + 1); };
  while (atom < natoms) {
    if (threeFields) {
      for (std::size_t d = 0; d < 3; ++d) {
        raw[d] = bits.take(fieldBits[d], "a coordinate");
        if (raw[d] >= sizes[d])
          throw BlockError{atomText() + ": coordinate beyond the frame's integer bounds"};
      }
    } else {
      bits.takeInts(packedBits, sizes, raw, "a coordinate");
    }
    for (std::size_t d = 0; d < 3; ++d) big[d] = minint[d] + static_cast<std::int64_t>(raw[d]);
    prev = big;

    std::int64_t isSmaller = 0;
    if (bits.take(1, "the run flag") == 1) {
      const auto code = static_cast<std::int64_t>(bits.take(5, "the run length"));
      isSmaller = code % 3;
      run = code - isSmaller;
      --isSmaller;
    }
    if (run > 0) {
      if (run / 3 >= natoms - atom)
        throw BlockError{atomText() + " starts a run of " + std::to_string(run / 3 + 1) +
                         " atoms, past the frame's " + std::to_string(natoms) + " atoms"};
      if (smallIdx < kFirstSmallIdx)
        throw BlockError{atomText() + " starts a run with smallidx " + std::to_string(smallIdx) +
                         " (base 0)"};
      const auto base = static_cast<std::uint64_t>(magic(smallIdx));
      const std::array<std::uint64_t, 3> smallSizes = {base, base, base};
      for (std::int64_t k = 0; k < run; k += 3) {
        bits.takeInts(static_cast<unsigned>(smallIdx), smallSizes, raw, "a small coordinate");
        for (std::size_t d = 0; d < 3; ++d) {
          cur[d] = prev[d] + static_cast<std::int64_t>(raw[d]) - smallNum;
          if (cur[d] < minint[d] || cur[d] > maxint[d])
            throw BlockError{atomText() + ": coordinate beyond the frame's integer bounds"};
        }
        if (k == 0) {
          // The writer swapped the first two atoms of a run (water's O and first H).
          emit(cur);
          emit(big);
        } else {
          emit(cur);
        }
        prev = cur;
      }
    } else {
      emit(big);
    }

    smallIdx += isSmaller;
    // Below FIRSTIDX the base is 0: allowed while no run uses it (checked there).
    if (smallIdx < 0 || smallIdx > kLastSmallIdx) {
      if (atom >= natoms) break;  // never used again: xdrfile would not look it up either
      throw BlockError{"smallidx moves to " + std::to_string(smallIdx) + " after atom " +
                       std::to_string(atom)};
    }
    if (isSmaller < 0) {
      smallNum = smaller;
      smaller = smallIdx > kFirstSmallIdx ? magic(smallIdx - 1) / 2 : 0;
    } else if (isSmaller > 0) {
      smaller = smallNum;
      smallNum = magic(smallIdx) / 2;
    }
  }
}

// Unit cell a, b, c (Å), alpha, beta, gamma (degrees) from the box rows (nm), as
// MDAnalysis's triclinic_box: none when an edge is zero or an angle is not in (0, 180).
std::optional<std::array<double, 6>> cellFromBox(const std::array<float, 9>& box) {
  const glm::dvec3 a = glm::dvec3(box[0], box[1], box[2]) * 10.0;
  const glm::dvec3 b = glm::dvec3(box[3], box[4], box[5]) * 10.0;
  const glm::dvec3 c = glm::dvec3(box[6], box[7], box[8]) * 10.0;
  const double la = glm::length(a);
  const double lb = glm::length(b);
  const double lc = glm::length(c);
  if (!(la > 0.0 && lb > 0.0 && lc > 0.0)) return std::nullopt;
  auto angle = [](const glm::dvec3& u, const glm::dvec3& v, double lu, double lv) {
    return std::acos(std::clamp(glm::dot(u, v) / (lu * lv), -1.0, 1.0)) * 180.0 / std::numbers::pi;
  };
  const double alpha = angle(b, c, lb, lc);
  const double beta = angle(a, c, la, lc);
  const double gamma = angle(a, b, la, lb);
  for (double g : {alpha, beta, gamma})
    if (!(g > 0.0 && g < 180.0)) return std::nullopt;
  return std::array<double, 6>{la, lb, lc, alpha, beta, gamma};
}

class XtcSource : public FrameSource {
 public:
  explicit XtcSource(const std::filesystem::path& path);
  std::size_t atomCount() const override { return atoms_; }
  std::size_t frameCount() const override { return offsets_.size() - 1; }
  void read(std::size_t index, Frame& frame) override;

 private:
  [[noreturn]] void fail(std::size_t frame, std::uint64_t offset,
                         const std::string& message) const {
    file_.fail("frame " + std::to_string(frame) + " (byte " + std::to_string(offset) + "): " +
               message);
  }
  // Reads n bytes at `offset` into buffer_ (followed by kLookAhead zero bytes).
  void readBytes(std::size_t frame, std::uint64_t offset, std::uint64_t n);
  // Walks the frame headers, hopping over the compressed blocks, and fills offsets_.
  void scan();
  // Bytes of the frame at `offset` from its first fields (at most kBlockAt of them in
  // buffer_); nullopt when the file ends first. Throws on fields no writer produces.
  std::optional<std::uint64_t> frameBytes(std::size_t frame, std::uint64_t offset,
                                          std::uint64_t available);

  binary::Reader file_;
  std::size_t atoms_ = 0;
  std::vector<std::uint64_t> offsets_;  // frame k spans [offsets_[k], offsets_[k + 1])
  std::vector<unsigned char> buffer_;
};

XtcSource::XtcSource(const std::filesystem::path& path) : FrameSource(path.string()), file_(path) {
  if (const std::error_code ec = file_.measure())
    file_.fail("cannot read the file: " + ec.message());
  if (!file_.open()) file_.fail("cannot open the file");
  if (file_.size() == 0) file_.fail("empty file: no XTC frame");
  scan();
}

void XtcSource::readBytes(std::size_t frame, std::uint64_t offset, std::uint64_t n) {
  if (!file_.holds(offset, n))
    fail(frame, offset,
         "the file ends at byte " + std::to_string(file_.size()) + ", " + bytesText(n) +
             " expected (did the file change while open?)");
  if (!file_.read(offset, n, buffer_, kLookAhead))
    fail(frame, offset, "read error (did the file change while open?)");
}

std::optional<std::uint64_t> XtcSource::frameBytes(std::size_t frame, std::uint64_t offset,
                                                   std::uint64_t available) {
  const unsigned char* p = buffer_.data();
  if (available < 4) return std::nullopt;
  const std::int32_t magic = xdrInt(p);
  if (magic == kXtcLargeMagic)
    fail(frame, offset,
         "XTC magic number 2023 (GROMACS 2023 format for more than 298 million "
         "atoms) is not supported");
  if (magic != kXtcMagic)
    fail(frame, offset,
         "not an XTC frame: magic number " + std::to_string(magic) + ", expected 1995");
  if (available < 8) return std::nullopt;
  const std::int64_t natoms = xdrInt(p + 4);
  if (natoms < 0) fail(frame, offset, "negative atom count " + std::to_string(natoms));
  if (static_cast<std::uint64_t>(natoms) != atoms_)
    fail(frame, offset,
         std::to_string(natoms) + " atoms, but frame 0 has " + std::to_string(atoms_));
  if (available < kCoordinatesAt) return std::nullopt;
  const std::int64_t again = xdrInt(p + kCoordinatesAt - 4);
  if (again != natoms)
    fail(frame, offset,
         "the header says " + std::to_string(natoms) + " atoms, the coordinates " +
             std::to_string(again));
  const auto n = static_cast<std::uint64_t>(natoms);
  if (natoms <= kMaxUncompressedAtoms) return kCoordinatesAt + 12 * n;
  if (available < kBlockAt) return std::nullopt;
  const std::int64_t count = xdrInt(p + kBlockAt - 4);
  if (count < 0)
    fail(frame, offset, "the compressed block's size is negative (" + std::to_string(count) + " bytes)");
  if (static_cast<std::uint64_t>(count) > (kMaxBitsPerAtom * n + 7) / 8 ||
      kMinBitsPerAtom * n > 8 * static_cast<std::uint64_t>(count))
    fail(frame, offset,
         "a compressed block of " + bytesText(static_cast<std::uint64_t>(count)) + " cannot hold " +
             std::to_string(natoms) + " atoms");
  const auto padded = (static_cast<std::uint64_t>(count) + 3) / 4 * 4;
  return kBlockAt + padded;
}

void XtcSource::scan() {
  offsets_.assign(1, 0);
  while (offsets_.back() < file_.size()) {
    const std::size_t frame = offsets_.size() - 1;
    const std::uint64_t offset = offsets_.back();
    const std::uint64_t available = std::min(kBlockAt, file_.size() - offset);
    readBytes(frame, offset, available);
    if (frame == 0 && available >= 8)
      atoms_ = static_cast<std::size_t>(std::max(std::int32_t{0}, xdrInt(buffer_.data() + 4)));
    const std::optional<std::uint64_t> bytes = frameBytes(frame, offset, available);
    if (!bytes || *bytes > file_.size() - offset) {
      const std::string what = "the file ends " + bytesText(file_.size() - offset) + " into its " +
                               (bytes ? bytesText(*bytes) : std::string("header"));
      if (frame == 0) fail(frame, offset, "truncated: " + what);
      notes_.push_back("frame " + std::to_string(frame) + " (byte " + std::to_string(offset) +
                       ") is truncated (" + what + ") and left out");
      break;
    }
    offsets_.push_back(offset + *bytes);
  }
  buffer_.clear();
  buffer_.shrink_to_fit();
}

void XtcSource::read(std::size_t index, Frame& frame) {
  file_.checkFrameIndex(index, frameCount());
  const std::uint64_t offset = offsets_[index];
  const std::uint64_t size = offsets_[index + 1] - offset;
  readBytes(index, offset, size);
  // The file may have changed since the scan: check the header again.
  if (frameBytes(index, offset, size) != size)
    fail(index, offset, "the frame header changed since the file was opened");
  const unsigned char* p = buffer_.data();

  frame.step = xdrInt(p + 8);
  frame.time = static_cast<double>(xdrFloat(p + 12));
  std::array<float, 9> box{};
  for (std::size_t i = 0; i < 9; ++i) {
    box[i] = xdrFloat(p + 16 + 4 * i);
    if (!std::isfinite(box[i]))
      fail(index, offset, "non-finite box entry " + std::to_string(i + 1));
  }
  frame.cell = cellFromBox(box);

  frame.positions.resize(atoms_);
  if (static_cast<std::int64_t>(atoms_) <= kMaxUncompressedAtoms) {
    for (std::size_t i = 0; i < 3 * atoms_; ++i) {
      const float x = xdrFloat(p + kCoordinatesAt + 4 * i);
      if (!std::isfinite(x))
        fail(index, offset, "non-finite coordinate of atom " + std::to_string(i / 3 + 1));
      frame.positions[i / 3][static_cast<glm::length_t>(i % 3)] = static_cast<double>(x) * 10.0;
    }
    return;
  }
  try {
    decodeCompressed(p, static_cast<std::uint64_t>(xdrInt(p + kBlockAt - 4)), frame.positions);
  } catch (const BlockError& e) {
    fail(index, offset,
         "corrupt compressed coordinates (block at byte " + std::to_string(offset + kBlockAt) +
             "): " + e.message);
  }
}

}  // namespace

std::unique_ptr<FrameSource> openXtc(const std::filesystem::path& path) {
  return std::make_unique<XtcSource>(path);
}

}  // namespace surftrace::build
