// CHARMM/NAMD/X-PLOR DCD trajectories: Fortran unformatted records (32- or 64-bit markers,
// either byte order) read frame by frame at offsets computed from the header.
//
// Layout (after the molfile plugin's readdcd.h, which MDAnalysis also uses):
//   record 84 bytes:  "CORD", icntrl[20]  (NSET, ISTART, NSAVC, ..., NAMNF at [8], DELTA at [9],
//                     unit-cell flag [10], 4D flag [11], CHARMM version [19])
//   record:           NTITLE, NTITLE lines of 80 characters
//   record 4 bytes:   NATOM
//   record:           free-atom indices (1-based), only if NAMNF > 0
//   per frame:        [record 48 bytes: unit cell a, gamma, b, beta, alpha, c (CHARMM, flag)]
//                     records x, y, z (float32) [and a 4th (CHARMM 4D dynamics), skipped]
// With fixed atoms, frame 0 stores every atom and later frames only the free ones.
#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include "build/core/assert.hpp"
#include "build/io/binary_reader.hpp"
#include "build/io/trajectory.hpp"

namespace surftrace::build {

namespace {

namespace fs = std::filesystem;

using Bytes = std::vector<unsigned char>;
using binary::ByteOrder;
using binary::bytesText;

// MDAnalysis (coordinates/units.py) converts CHARMM's AKMA time unit to ps with the factor
// 1 / (1 / 4.888821e-2); written the same way so that frame times agree to the last bit.
constexpr double kPsPerAkma = 1.0 / (1.0 / 4.888821e-2);

constexpr std::uint64_t kCellRecordBytes = 48;  // six float64
constexpr char kAxisName[4] = {'x', 'y', 'z', 'w'};

// The unit cell as MDAnalysis 2.x reports it (DCDReader._frame_to_ts): the record holds
// (a, gamma, b, beta, alpha, c). CHARMM >= 25 and NAMD > 2.5 write the angles' cosines, NAMD 2.5
// degrees; recent CHARMM writes the symmetric box matrix (h11, h21, h22, h31, h32, h33), which
// is recognised only by values that cannot be a cell (negative, or an angle above 180). The
// tests compare with MDAnalysis, so the same order of guesses is kept even where a file's
// header would tell more (triclinic-octane-vectors.dcd holds a matrix but reads as cosines).
// A cell of zero lengths means no cell, as in MDAnalysis.
std::optional<std::array<double, 6>> cellFromRecord(const std::array<double, 6>& r) {
  std::array<double, 6> uc = {r[0], r[2], r[5], r[4], r[3], r[1]};
  const auto isCosine = [](double x) { return x >= -1.0 && x <= 1.0; };
  if (isCosine(uc[3]) && isCosine(uc[4]) && isCosine(uc[5])) {
    // 90 - asin(x) rather than acos(x): exactly 90 degrees for a zero cosine.
    for (std::size_t i = 3; i < 6; ++i)
      uc[i] = 90.0 - std::asin(uc[i]) * 90.0 / (std::numbers::pi / 2);
  } else if (uc[0] < 0 || uc[1] < 0 || uc[2] < 0 || uc[3] < 0 || uc[4] < 0 || uc[5] < 0 ||
             uc[3] > 180 || uc[4] > 180 || uc[5] > 180) {
    // MDAnalysis lib.mdamath.triclinic_box on the rows of the symmetric matrix.
    using V = std::array<double, 3>;
    const V e1 = {r[0], r[1], r[3]}, e2 = {r[1], r[2], r[4]}, e3 = {r[3], r[4], r[5]};
    const auto dot = [](const V& u, const V& v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
    const auto degrees = [](double c) { return std::acos(c) * 180.0 / std::numbers::pi; };
    const double l1 = std::sqrt(dot(e1, e1));
    const double l2 = std::sqrt(dot(e2, e2));
    const double l3 = std::sqrt(dot(e3, e3));
    uc = {l1, l2, l3, degrees(dot(e2, e3) / (l2 * l3)), degrees(dot(e1, e3) / (l1 * l3)),
          degrees(dot(e1, e2) / (l1 * l2))};
    // An invalid box (NaN included) becomes MDAnalysis's zero box: no cell.
    for (std::size_t i = 0; i < 6; ++i)
      if (!(uc[i] > 0) || (i >= 3 && !(uc[i] < 180))) return std::nullopt;
  }
  if (uc[0] == 0 && uc[1] == 0 && uc[2] == 0) return std::nullopt;
  return uc;
}

class DcdSource final : public FrameSource {
 public:
  explicit DcdSource(const fs::path& path);

  std::size_t atomCount() const override { return atomCount_; }
  std::size_t frameCount() const override { return frameCount_; }
  void read(std::size_t index, Frame& frame) override;

 private:
  // Reads `n` bytes at `offset` into `out`; the size is checked against the file first, so a
  // corrupt length never turns into a huge allocation.
  void readBytes(std::uint64_t offset, std::uint64_t n, Bytes& out, const std::string& what);
  std::int64_t marker(const unsigned char* p) const {
    return markerBytes_ == 4 ? std::int64_t{order_.i32(p)}
                             : std::bit_cast<std::int64_t>(order_.u64(p));
  }
  // One whole header record at `offset` whose length is not known in advance: checks its two
  // markers and returns the payload in `out`; `offset` moves past the record.
  void readRecord(std::uint64_t& offset, Bytes& out, const std::string& what);
  [[noreturn]] void fail(const std::string& message) const { file_.fail(message); }
  void decodeFrame(std::size_t index, Frame& frame);
  void checkFourthDimension();

  binary::Reader file_;
  ByteOrder order_;
  std::uint64_t markerBytes_ = 4;

  std::size_t atomCount_ = 0;
  std::size_t frameCount_ = 0;
  std::int32_t istart_ = 0;
  std::int32_t nsavc_ = 0;
  double delta_ = 0.0;  // AKMA time units (float32 in CHARMM files, float64 in X-PLOR ones)
  bool hasCell_ = false;
  int axes_ = 3;  // coordinate records per frame: 4 with CHARMM 4D dynamics
  std::vector<std::uint32_t> freeAtoms_;  // 0-based; empty without fixed atoms

  std::uint64_t headerBytes_ = 0;
  std::uint64_t firstFrameBytes_ = 0;  // every atom
  std::uint64_t frameBytes_ = 0;       // the free atoms only, with fixed atoms

  std::vector<glm::dvec3> firstPositions_;  // frame 0 (read when first needed), with fixed atoms
  Bytes buffer_;
};

DcdSource::DcdSource(const fs::path& path) : FrameSource(path.string()), file_(path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) fail("is a directory, not a file");
  if (!file_.open()) fail(std::string("cannot open: ") + std::strerror(errno));
  if ((ec = file_.measure())) fail("cannot read its size: " + ec.message());

  // The first record holds 84 bytes; its marker tells the byte order and the marker width.
  Bytes head;
  readBytes(0, std::min<std::uint64_t>(file_.size(), 12), head, "the first record");
  bool found = false;
  for (const std::uint64_t width : {4u, 8u}) {
    for (const bool big : {false, true}) {
      const ByteOrder order{big};
      if (found || head.size() < width + 4 || std::memcmp(head.data() + width, "CORD", 4) != 0)
        continue;
      const std::uint64_t value = width == 4 ? order.u32(head.data()) : order.u64(head.data());
      if (value == 84) {
        order_ = order;
        markerBytes_ = width;
        found = true;
      }
    }
  }
  if (!found && file_.size() < 12)
    fail("the file ends at byte " + std::to_string(file_.size()) +
         ", inside the first record (a DCD file starts with a record of 84 bytes)");
  if (!found)
    fail("not a DCD file: expected a first record of 84 bytes starting with \"CORD\" at byte 0 "
         "(a 32- or 64-bit record marker, either byte order)");

  std::uint64_t offset = 0;
  Bytes record;
  readRecord(offset, record, "the header record (CORD and icntrl)");
  SURFTRACE_ASSERT(record.size() == 84);  // the marker was found to be 84 above
  const auto icntrl = [&](int i) { return order_.i32(record.data() + 4 + 4 * i); };
  const std::int32_t nset = icntrl(0);
  istart_ = icntrl(1);
  nsavc_ = icntrl(2);
  const std::int32_t fixedCount = icntrl(8);
  const bool charmm = icntrl(19) != 0;
  // X-PLOR stores DELTA as a float64 over icntrl[9..10]; CHARMM a float32 in icntrl[9] and
  // uses icntrl[10] and [11] as flags (readdcd.h tests them only for CHARMM files).
  delta_ = charmm ? double{order_.f32(record.data() + 40)} : order_.f64(record.data() + 40);
  hasCell_ = charmm && icntrl(10) != 0;
  axes_ = charmm && icntrl(11) == 1 ? 4 : 3;

  readRecord(offset, record, "the title record");

  const std::uint64_t natomAt = offset;
  readRecord(offset, record, "the atom count record");
  if (record.size() != 4)
    fail("the atom count record at byte " + std::to_string(natomAt) + " holds " +
         bytesText(record.size()) + ", expected 4");
  const std::int32_t natom = order_.i32(record.data());
  if (natom <= 0) fail("the header gives " + std::to_string(natom) + " atoms");
  atomCount_ = static_cast<std::size_t>(natom);

  if (fixedCount < 0 || fixedCount > natom)
    fail("the header gives " + std::to_string(fixedCount) + " fixed atoms of " +
         std::to_string(natom));
  if (fixedCount > 0) {
    const std::size_t freeCount = atomCount_ - static_cast<std::size_t>(fixedCount);
    const std::uint64_t listAt = offset;
    readRecord(offset, record, "the free-atom index record");
    if (record.size() != 4 * freeCount)
      fail("the free-atom index record at byte " + std::to_string(listAt) + " holds " +
           bytesText(record.size()) + ", expected " + bytesText(4 * freeCount) + " (" +
           std::to_string(freeCount) + " free atoms = " + std::to_string(natom) + " atoms - " +
           std::to_string(fixedCount) + " fixed)");
    freeAtoms_.resize(freeCount);
    for (std::size_t i = 0; i < freeCount; ++i) {
      const std::int32_t atom = order_.i32(record.data() + 4 * i);
      if (atom < 1 || atom > natom)
        fail("free atom " + std::to_string(i + 1) + " of the index record at byte " +
             std::to_string(listAt) + " is atom " + std::to_string(atom) + ", not in 1.." +
             std::to_string(natom));
      freeAtoms_[i] = static_cast<std::uint32_t>(atom - 1);
    }
  }
  headerBytes_ = offset;

  const std::uint64_t cellBytes = hasCell_ ? kCellRecordBytes + 2 * markerBytes_ : 0;
  const auto frameBytes = [&](std::uint64_t atoms) {
    return cellBytes + static_cast<std::uint64_t>(axes_) * (4 * atoms + 2 * markerBytes_);
  };
  firstFrameBytes_ = frameBytes(atomCount_);
  frameBytes_ = fixedCount > 0 ? frameBytes(freeAtoms_.size()) : firstFrameBytes_;

  // The frame count comes from the file size: writers that stop early leave NSET too large
  // (adk_dims.dcd says 500 and holds 98), and a crash leaves a partial last frame.
  const std::uint64_t body = file_.size() - headerBytes_;
  std::uint64_t rest = body;
  std::uint64_t expected = firstFrameBytes_;
  if (body >= firstFrameBytes_) {
    const std::uint64_t later = (body - firstFrameBytes_) / frameBytes_;
    frameCount_ = static_cast<std::size_t>(1 + later);
    rest = body - firstFrameBytes_ - later * frameBytes_;
    expected = frameBytes_;
  }
  if (rest > 0)
    notes_.push_back("frame " + std::to_string(frameCount_) + " is truncated (" +
                     std::to_string(rest) + " of " + bytesText(expected) + ") and left out");
  if (nset < 0 || static_cast<std::uint64_t>(nset) != frameCount_)
    notes_.push_back("header says " + std::to_string(nset) + " frames, the file holds " +
                     std::to_string(frameCount_));
  if (axes_ == 4 && freeAtoms_.empty()) checkFourthDimension();

}

// A 4D flag (icntrl[11] = 1) on a file of ordinary 3-record frames pairs each frame's x, y, z
// with records of the next frame: every record has the same length, so no marker is out of
// place and the coordinates come out scrambled. Two facts tell the layouts apart: the file
// must hold whole frames of the claimed layout, and in a real trajectory an atom moves little
// from one frame to the next, so frame 1's x record continues frame 0's x record under the
// right layout and not under the wrong one.
void DcdSource::checkFourthDimension() {
  const std::uint64_t cellBytes = hasCell_ ? kCellRecordBytes + 2 * markerBytes_ : 0;
  const std::uint64_t recordBytes = 4 * atomCount_ + 2 * markerBytes_;
  const std::uint64_t frame3 = cellBytes + 3 * recordBytes, frame4 = cellBytes + 4 * recordBytes;
  const std::uint64_t body = file_.size() - headerBytes_;
  const std::string wrongFlag =
      "the header's 4D flag (icntrl[11] = 1, CHARMM 4D dynamics) says each frame holds 4 "
      "coordinate records, but ";
  const std::string remedy =
      "; the flag is wrong: rewrite the header with icntrl[11] = 0 (e.g. with MDAnalysis or "
      "catdcd)";
  // x of frame 0, and of frame 1 under each layout (the payload after its leading marker).
  const std::uint64_t x0 = headerBytes_ + cellBytes + markerBytes_;
  const std::uint64_t x1three = x0 + frame3, x1four = x0 + frame4;
  if (x1four + 4 * atomCount_ + markerBytes_ > file_.size()) {
    // One frame or less under the 4D layout: only the size can speak.
    if (body % frame4 != 0 && body % frame3 == 0)
      fail(wrongFlag + "the file holds " + std::to_string(body / frame3) +
           " whole frames of 3 records and no whole number of 4-record frames" + remedy);
    return;
  }
  Bytes first, three, four, mark;
  const auto coordinates = [&](std::uint64_t at, Bytes& out) {
    readBytes(at - markerBytes_, markerBytes_, mark, "a coordinate record");
    if (marker(mark.data()) != static_cast<std::int64_t>(4 * atomCount_)) return false;
    readBytes(at, 4 * atomCount_, out, "a coordinate record");
    return true;
  };
  if (!coordinates(x0, first)) return;  // decodeFrame names the bad marker
  if (!coordinates(x1four, four)) {
    if (coordinates(x1three, three))
      fail(wrongFlag + "frame 1 does not start where 4 records a frame put it (byte " +
           std::to_string(x1four - markerBytes_) + "), while 3 records a frame fit" + remedy);
    return;
  }
  if (!coordinates(x1three, three)) return;
  const auto rms = [&](const Bytes& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < atomCount_; ++i) {
      const double d = double{order_.f32(b.data() + 4 * i)} - double{order_.f32(first.data() + 4 * i)};
      if (std::isfinite(d)) sum += d * d;
    }
    return std::sqrt(sum / static_cast<double>(atomCount_));
  };
  const double stepThree = rms(three), stepFour = rms(four);
  if (10.0 * stepThree < stepFour)
    fail(wrongFlag + "read so, atoms jump by " + std::to_string(stepFour) +
         " Å (rms) from frame 0 to frame 1, and by " + std::to_string(stepThree) +
         " Å when read with 3 records a frame" + remedy);
}

void DcdSource::readBytes(std::uint64_t offset, std::uint64_t n, Bytes& out,
                          const std::string& what) {
  if (!file_.holds(offset, n))
    fail("the file ends at byte " + std::to_string(file_.size()) + ", inside " + what + " (" +
         bytesText(n) + " expected from byte " + std::to_string(offset) + ")");
  if (!file_.read(offset, n, out))
    fail("read error at byte " + std::to_string(offset) + " in " + what +
         " (did the file change while open?)");
}

void DcdSource::readRecord(std::uint64_t& offset, Bytes& out, const std::string& what) {
  Bytes m;
  readBytes(offset, markerBytes_, m, what);
  const std::int64_t length = marker(m.data());
  const std::uint64_t payloadAt = offset + markerBytes_;
  if (length < 0 || static_cast<std::uint64_t>(length) > file_.size() - payloadAt)
    fail(what + " at byte " + std::to_string(offset) + " has a record marker of " +
         std::to_string(length) + ", but only " + bytesText(file_.size() - payloadAt) +
         " follow it");
  const auto n = static_cast<std::uint64_t>(length);
  readBytes(payloadAt, n, out, what);
  const std::uint64_t endAt = payloadAt + n;
  readBytes(endAt, markerBytes_, m, what);
  if (marker(m.data()) != length)
    fail(what + " at byte " + std::to_string(offset) + " starts with a record marker of " +
         std::to_string(length) + " but ends with " + std::to_string(marker(m.data())) +
         " at byte " + std::to_string(endAt));
  offset = endAt + markerBytes_;
}

void DcdSource::read(std::size_t index, Frame& frame) {
  file_.checkFrameIndex(index, frameCount_);
  if (index > 0 && !freeAtoms_.empty() && firstPositions_.empty()) {
    // Later frames store only the free atoms; the fixed ones keep their frame-0 positions.
    Frame first;
    decodeFrame(0, first);
    firstPositions_ = std::move(first.positions);
  }
  decodeFrame(index, frame);
}

void DcdSource::decodeFrame(std::size_t index, Frame& frame) {
  const bool full = index == 0 || freeAtoms_.empty();
  const std::uint64_t start =
      index == 0 ? headerBytes_ : headerBytes_ + firstFrameBytes_ + (index - 1) * frameBytes_;
  const std::string frameName = "frame " + std::to_string(index);  // from 0, as --frames
  readBytes(start, full ? firstFrameBytes_ : frameBytes_, buffer_, frameName);

  // Checks one record's two markers against the payload it must have.
  std::uint64_t at = 0;
  const auto record = [&](std::uint64_t payload, const std::string& what) {
    for (const std::uint64_t markerAt : {at, at + markerBytes_ + payload}) {
      const std::int64_t found = marker(buffer_.data() + markerAt);
      if (found < 0 || static_cast<std::uint64_t>(found) != payload)
        fail(frameName + ": expected a record marker of " + std::to_string(payload) + " (" +
             what + ") at byte " + std::to_string(start + markerAt) + ", found " +
             std::to_string(found));
    }
    const unsigned char* data = buffer_.data() + at + markerBytes_;
    at += payload + 2 * markerBytes_;
    return data;
  };

  frame.cell.reset();
  if (hasCell_) {
    const unsigned char* p = record(kCellRecordBytes, "the unit cell, 6 float64");
    std::array<double, 6> raw{};
    for (std::size_t i = 0; i < 6; ++i) {
      raw[i] = order_.f64(p + 8 * i);
      if (!std::isfinite(raw[i]))
        fail(frameName + ": the unit cell holds a non-finite value (" + std::to_string(raw[i]) +
             ")");
    }
    frame.cell = cellFromRecord(raw);
  }

  if (full) {
    frame.positions.resize(atomCount_);
  } else {
    frame.positions = firstPositions_;
  }
  const std::size_t stored = full ? atomCount_ : freeAtoms_.size();
  for (int axis = 0; axis < axes_; ++axis) {
    const std::string what = std::string(1, kAxisName[axis]) + " coordinates of " +
                             std::to_string(stored) + (stored == 1 ? " atom" : " atoms");
    const unsigned char* p = record(4 * stored, what);
    if (axis == 3) continue;  // CHARMM 4D dynamics: the 4th coordinate is not a position
    for (std::size_t i = 0; i < stored; ++i) {
      const double v = order_.f32(p + 4 * i);
      const std::size_t atom = full ? i : freeAtoms_[i];
      if (!std::isfinite(v))
        fail(frameName + ", atom " + std::to_string(atom + 1) + ": non-finite " +
             kAxisName[axis] + " coordinate (" + std::to_string(v) + ")");
      frame.positions[atom][axis] = v;
    }
  }

  frame.step = static_cast<long long>(istart_) + static_cast<long long>(index) * nsavc_;
  // MDAnalysis: dt = delta * nsavc (ps) and time = (frame + istart / nsavc) * dt; the same
  // arithmetic keeps the times identical. Without NSAVC (MDAnalysis then divides by zero),
  // step * delta.
  const double deltaPs = delta_ * kPsPerAkma;
  frame.time = nsavc_ != 0 ? (static_cast<double>(index) + static_cast<double>(istart_) / nsavc_) *
                                 (deltaPs * nsavc_)
                           : static_cast<double>(frame.step) * deltaPs;
}

}  // namespace

std::unique_ptr<FrameSource> openDcd(const std::filesystem::path& path) {
  return std::make_unique<DcdSource>(path);
}

}  // namespace surftrace::build
