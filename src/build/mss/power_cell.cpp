// Feasible power cells by exact plane clipping (see power_cell.hpp for the decisions).
#include "build/mss/power_cell.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <gmpxx.h>
#include <glm/geometric.hpp>

namespace surftrace::build::mss {
namespace {

constexpr double kU = 0x1p-53;
// |computed − exact| <= kCofactorError·hMag for every cofactor of a vertex: each entry carries
// a relative error of at most u (n) or 6u of its magnitude (c), a product of three 10u, the
// sums 3u more; 16u leaves room.
constexpr double kCofactorError = 16 * kU;
// P_m·H: the cofactors' errors times |n_m|, c_m's own 6u, the products and the sum: 64u.
constexpr double kSideError = 64 * kU;

double det3(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) { return glm::dot(a, glm::cross(b, c)); }

// The cofactors of rows (n_r, −c_r): H with P·H = det[A; B; C; P] for every row P, and the
// same over magnitudes (|n| and the bound `mag` of c) for the error bound.
void homogeneous(const CellPlane& A, const CellPlane& B, const CellPlane& C, glm::dvec4& h, glm::dvec4& hMag) {
  // Columns x, y, z, c' with c' = −c. H_k = (−1)^(k+1+4)·minor(k) (1-based k).
  const glm::dvec3 cA(A.n), cB(B.n), cC(C.n);
  const glm::dvec3 col(-A.c, -B.c, -C.c);
  const glm::dvec3 xs(cA.x, cB.x, cC.x), ys(cA.y, cB.y, cC.y), zs(cA.z, cB.z, cC.z);
  h.x = -det3(ys, zs, col);
  h.y = det3(xs, zs, col);
  h.z = -det3(xs, ys, col);
  h.w = det3(xs, ys, zs);
  // Magnitudes: the permanents of the absolute entries.
  auto perm = [](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    return a.x * (b.y * c.z + b.z * c.y) + a.y * (b.x * c.z + b.z * c.x) + a.z * (b.x * c.y + b.y * c.x);
  };
  const glm::dvec3 ax = glm::abs(xs), ay = glm::abs(ys), az = glm::abs(zs);
  const glm::dvec3 am(A.mag, B.mag, C.mag);
  hMag = {perm(ay, az, am), perm(ax, az, am), perm(ax, ay, am), perm(ax, ay, az)};
}

// Exact rows from the input doubles.
struct ExactRow {
  mpq_class n[3];
  mpq_class c;
};

mpq_class det3(const mpq_class* a, const mpq_class* b, const mpq_class* c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

}  // namespace

CellPlane PowerCell::planeOf(std::uint32_t j) const {
  const glm::dvec3 d = points_.z[j] - points_.z[atom_];
  const double dd = glm::dot(d, d);
  const double wi = points_.w[atom_], wj = points_.w[j];
  return {2.0 * d, dd - wj + wi, dd + std::abs(wj) + std::abs(wi), j};
}

void PowerCell::reset(const WeightedPoints& points, std::uint32_t atom, double half) {
  points_ = points;
  atom_ = atom;
  empty_ = false;
  exactSides_ = 0;
  planes_.clear();
  for (int k = 0; k < 6; ++k) {
    glm::dvec3 n(0.0);
    n[k / 2] = (k % 2 == 0) ? 1.0 : -1.0;
    planes_.push_back({n, half, half, kBoxPlane + static_cast<std::uint32_t>(k)});
  }
  // Corner (sx, sy, sz) is vertex sx | sy << 1 | sz << 2 (bit set: positive side).
  vertices_.clear();
  for (int v = 0; v < 8; ++v) {
    const auto px = static_cast<std::uint16_t>((v & 1) ? 0 : 1), py = static_cast<std::uint16_t>((v & 2) ? 2 : 3),
               pz = static_cast<std::uint16_t>((v & 4) ? 4 : 5);
    vertices_.push_back(makeVertex(px, py, pz));
  }
  // Faces counter-clockwise seen from outside: for axis k with the others u = k+1, w = k+2
  // (cyclic), corners (u, w) = (−,−), (+,−), (+,+), (−,+) turn about +e_k.
  faceStart_.assign(1, 0);
  faceVerts_.clear();
  for (int k = 0; k < 6; ++k) {
    const int axis = k / 2, u = (axis + 1) % 3, w = (axis + 2) % 3;
    const bool positive = k % 2 == 0;
    std::array<std::uint16_t, 4> quad;
    const int su[4] = {0, 1, 1, 0}, sw[4] = {0, 0, 1, 1};
    for (int q = 0; q < 4; ++q)
      quad[q] = static_cast<std::uint16_t>((positive ? 1 << axis : 0) | (su[q] << u) | (sw[q] << w));
    if (!positive) std::reverse(quad.begin(), quad.end());
    faceVerts_.insert(faceVerts_.end(), quad.begin(), quad.end());
    faceStart_.push_back(static_cast<std::uint32_t>(faceVerts_.size()));
  }
  maxNorm2_ = 3.0 * half * half;
  ballCentre_ = glm::dvec3(0.0);
  ballRadius_ = std::sqrt(maxNorm2_);
  boxLo_ = glm::dvec3(-half);
  boxHi_ = glm::dvec3(half);
  boxHalf_ = half;
}

CellVertex PowerCell::makeVertex(std::uint16_t a, std::uint16_t b, std::uint16_t c) {
  CellVertex v;
  v.plane = {a, b, c};
  homogeneous(planes_[a], planes_[b], planes_[c], v.h, v.hMag);
  if (std::abs(v.h.w) > kCofactorError * v.hMag.w)
    v.wSign = v.h.w > 0 ? 1 : -1;
  else
    v.wSign = exactWSign(v);
  v.p = glm::dvec3(v.h) / v.h.w;
  // The position (not the decisions, which are exact) carries the cofactors' errors over |h_w|:
  // three nearly dependent normals (the Voronoi vertex of a sliver of four nearly co-spherical
  // atoms, issue 18, where h_w ~ δ² and its rounding ~1e-15) leave it anywhere, and callers
  // measure it against the feasibility radius. Beyond 1e-12 of the box, solve exactly.
  const double error = kCofactorError * (std::max({v.hMag.x, v.hMag.y, v.hMag.z}) +
                                         std::max({std::abs(v.p.x), std::abs(v.p.y), std::abs(v.p.z)}) * v.hMag.w);
  if (!(error <= 1e-12 * planes_[0].c * std::abs(v.h.w))) v.p = exactPosition(v);
  return v;
}

// The fast path inline in the clipping loop; the rational one out of line.
inline int PowerCell::side(const CellVertex& v, std::uint16_t m) {
  const CellPlane& P = planes_[m];
  const double t = P.n.x * v.h.x + P.n.y * v.h.y + P.n.z * v.h.z - P.c * v.h.w;
  const double bound =
      kSideError * (std::abs(P.n.x) * v.hMag.x + std::abs(P.n.y) * v.hMag.y + std::abs(P.n.z) * v.hMag.z + P.mag * v.hMag.w);
  if (t > bound) return v.wSign;
  if (t < -bound) return -v.wSign;
  return exactSideCounted(v, m);
}

int PowerCell::exactSideCounted(const CellVertex& v, std::uint16_t m) {
  ++exactSides_;
  return exactSide(v, m) * v.wSign;
}

namespace {

ExactRow exactRow(const WeightedPoints& pts, std::uint32_t i, const CellPlane& plane) {
  ExactRow r;
  if (plane.atom >= kBoxPlane) {
    for (int k = 0; k < 3; ++k) r.n[k] = plane.n[k];
    r.c = plane.c;
    return r;
  }
  mpq_class dd = 0;
  for (int k = 0; k < 3; ++k) {
    const mpq_class d = mpq_class(pts.z[plane.atom][k]) - mpq_class(pts.z[i][k]);
    r.n[k] = 2 * d;
    dd += d * d;
  }
  r.c = dd - mpq_class(pts.w[plane.atom]) + mpq_class(pts.w[i]);
  return r;
}

}  // namespace

int PowerCell::exactWSign(const CellVertex& v) const {
  const ExactRow A = exactRow(points_, atom_, planes_[v.plane[0]]), B = exactRow(points_, atom_, planes_[v.plane[1]]),
                 C = exactRow(points_, atom_, planes_[v.plane[2]]);
  const int sign = sgn(det3(A.n, B.n, C.n));
  // Three planes with dependent normals meet in no point; the clipping never builds one.
  if (sign == 0) throw std::logic_error("power cell: a vertex of three planes with dependent normals");
  return sign;
}

// The meet of the vertex's three planes, n_r·x = c_r, by Cramer's rule in rationals, rounded once.
glm::dvec3 PowerCell::exactPosition(const CellVertex& v) const {
  ExactRow R[3];
  for (int r = 0; r < 3; ++r) R[r] = exactRow(points_, atom_, planes_[v.plane[r]]);
  const mpq_class det = det3(R[0].n, R[1].n, R[2].n);
  glm::dvec3 p;
  for (int k = 0; k < 3; ++k) {
    mpq_class rows[3][3];
    for (int r = 0; r < 3; ++r) {
      for (int m = 0; m < 3; ++m) rows[r][m] = R[r].n[m];
      rows[r][k] = R[r].c;
    }
    p[k] = mpq_class(det3(rows[0], rows[1], rows[2]) / det).get_d();
  }
  return p;
}

// Sign of det[A; B; C; M] for rows (n, −c), with the simulated perturbation w_k + ε_k when it
// is zero. The result times sign(H_w) is the side.
int PowerCell::exactSide(const CellVertex& v, std::uint16_t m) const {
  const CellPlane* rows[4] = {&planes_[v.plane[0]], &planes_[v.plane[1]], &planes_[v.plane[2]], &planes_[m]};
  ExactRow R[4];
  for (int r = 0; r < 4; ++r) R[r] = exactRow(points_, atom_, *rows[r]);
  // D_r: the 3×3 determinant of the normals of the rows other than r.
  mpq_class D[4];
  D[0] = det3(R[1].n, R[2].n, R[3].n);
  D[1] = det3(R[0].n, R[2].n, R[3].n);
  D[2] = det3(R[0].n, R[1].n, R[3].n);
  D[3] = det3(R[0].n, R[1].n, R[2].n);
  // Expansion along the last column (entries −c_r, sign (−1)^(r+4) for 1-based r).
  // g_r = ∂det/∂c_r = (−1)^(r+4)·(−1)·D_r: g = (+D0, −D1, +D2, −D3).
  const mpq_class g[4] = {D[0], -D[1], D[2], -D[3]};
  mpq_class det = 0;
  for (int r = 0; r < 4; ++r) det += g[r] * R[r].c;
  if (const int s = sgn(det); s != 0) return s;
  // Perturbed c_r: atom rows c + ε_i − ε_a, box rows c + ε_box. Coefficient of each ε, then
  // the first non-zero one in priority order (atom index; box planes last, by number).
  std::array<std::pair<std::uint64_t, mpq_class>, 5> terms;
  int count = 0;
  mpq_class own = 0;
  for (int r = 0; r < 4; ++r) {
    if (rows[r]->atom >= kBoxPlane) {
      terms[count++] = {std::uint64_t{1} << 40 | rows[r]->atom, g[r]};
    } else {
      terms[count++] = {rows[r]->atom, -g[r]};
      own += g[r];
    }
  }
  terms[count++] = {atom_, own};
  std::sort(terms.begin(), terms.begin() + count, [](const auto& a, const auto& b) { return a.first < b.first; });
  for (int k = 0; k < count; ++k)
    if (const int s = sgn(terms[k].second); s != 0) return s;
  // Unreachable: the new row's own ε has coefficient ±D3 = ±det of the vertex's normals != 0.
  throw std::logic_error("power cell: simulation of simplicity found no deciding term");
}

std::uint16_t PowerCell::edgeNeighbour(std::uint16_t k, std::uint16_t a, std::uint16_t b) const {
  for (std::uint16_t p : vertices_[a].plane) {
    if (p == k) continue;
    for (std::uint16_t q : vertices_[b].plane)
      if (p == q) return p;
  }
  throw std::logic_error("power cell: consecutive face vertices share no second plane");
}

PowerCell::Clip PowerCell::clip(std::uint32_t j) {
  if (empty_) return Clip::Empty;
  planes_.push_back(planeOf(j));
  const auto m = static_cast<std::uint16_t>(planes_.size() - 1);
  const std::size_t nv = vertices_.size();
  sides_.resize(nv);
  std::size_t outside = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    sides_[v] = side(vertices_[v], m);
    outside += sides_[v] > 0;
  }
  if (outside == 0) {
    planes_.pop_back();
    return Clip::Redundant;
  }
  if (outside == nv) {
    empty_ = true;
    return Clip::Empty;
  }

  // Inside vertices keep their order; crossing vertices follow.
  nextVertices_.clear();
  remap_.assign(nv, -1);
  for (std::size_t v = 0; v < nv; ++v) {
    if (sides_[v] < 0) {
      remap_[v] = static_cast<int>(nextVertices_.size());
      nextVertices_.push_back(vertices_[v]);
    }
  }
  crossings_.clear();
  auto crossing = [&](std::uint16_t a, std::uint16_t b, std::uint16_t face) -> std::uint16_t {
    const std::uint32_t key = a < b ? (std::uint32_t{a} << 16 | b) : (std::uint32_t{b} << 16 | a);
    for (const auto& [k, id] : crossings_)
      if (k == key) return id;
    const std::uint16_t other = edgeNeighbour(face, a, b);
    const auto id = static_cast<std::uint16_t>(nextVertices_.size());
    nextVertices_.push_back(makeVertex(std::min(face, other), std::max(face, other), m));
    crossings_.emplace_back(key, id);
    return id;
  };

  newFaceNext_.assign(nv + 2 * outside + 8, 0xFFFF);
  nextFaceStart_.assign(1, 0);
  nextFaceVerts_.clear();
  std::uint16_t anyCrossing = 0xFFFF;
  for (std::size_t k = 0; k + 1 < planes_.size(); ++k) {
    const std::span<const std::uint16_t> poly = face(k);
    const std::size_t n = poly.size();
    std::uint16_t exit = 0xFFFF, entry = 0xFFFF;
    for (std::size_t q = 0; q < n; ++q) {
      const std::uint16_t a = poly[q], b = poly[(q + 1) % n];
      if (sides_[a] < 0) nextFaceVerts_.push_back(static_cast<std::uint16_t>(remap_[a]));
      if ((sides_[a] < 0) != (sides_[b] < 0)) {
        const std::uint16_t x = crossing(a, b, static_cast<std::uint16_t>(k));
        nextFaceVerts_.push_back(x);
        (sides_[a] < 0 ? exit : entry) = x;
      }
    }
    if (exit != 0xFFFF) {
      if (newFaceNext_.size() <= std::max(exit, entry)) newFaceNext_.resize(std::max(exit, entry) + 1u, 0xFFFF);
      newFaceNext_[entry] = exit;  // the new face runs each cut edge the other way
      anyCrossing = entry;
    }
    nextFaceStart_.push_back(static_cast<std::uint32_t>(nextFaceVerts_.size()));
  }
  // The new face: follow the cut edges round.
  std::uint16_t cur = anyCrossing;
  std::size_t guard = 0;
  do {
    nextFaceVerts_.push_back(cur);
    cur = newFaceNext_[cur];
    if (cur == 0xFFFF || ++guard > nextVertices_.size())
      throw std::logic_error("power cell: the cut does not close (inconsistent sides)");
  } while (cur != anyCrossing);
  nextFaceStart_.push_back(static_cast<std::uint32_t>(nextFaceVerts_.size()));

  std::swap(vertices_, nextVertices_);
  std::swap(faceStart_, nextFaceStart_);
  std::swap(faceVerts_, nextFaceVerts_);
  maxNorm2_ = 0.0;
  ballCentre_ = glm::dvec3(0.0);
  boxLo_ = glm::dvec3(std::numeric_limits<double>::infinity());
  boxHi_ = -boxLo_;
  for (const CellVertex& v : vertices_) {
    maxNorm2_ = std::max(maxNorm2_, glm::dot(v.p, v.p));
    ballCentre_ += v.p;
    boxLo_ = glm::min(boxLo_, v.p);
    boxHi_ = glm::max(boxHi_, v.p);
  }
  ballCentre_ /= static_cast<double>(vertices_.size());
  double radius2 = 0.0;
  for (const CellVertex& v : vertices_) radius2 = std::max(radius2, glm::dot(v.p - ballCentre_, v.p - ballCentre_));
  ballRadius_ = std::sqrt(radius2);
  return Clip::Cut;
}

}  // namespace surftrace::build::mss
