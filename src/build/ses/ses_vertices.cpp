// SES vertex pass: probe positions, their validity, and cospherical vertices merged into concave polygons.
#include "build/ses/ses_vertices.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "build/ses/sas_geometry.hpp"
#include "build/ses/ses_kernels.hpp"

namespace surftrace::build::detail {
namespace {

std::optional<ProbePair> sortedProbes(const Atoms& a, std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  std::uint32_t t[3] = {x, y, z};
  if (t[0] > t[1]) std::swap(t[0], t[1]);
  if (t[1] > t[2]) std::swap(t[1], t[2]);
  if (t[0] > t[1]) std::swap(t[0], t[1]);
  return probePositions(a.c[t[0]], a.R[t[0]], a.c[t[1]], a.R[t[1]], a.c[t[2]], a.R[t[2]]);
}

// Fills s.nb with x's live neighbours and their caps; returns the convex patch's cap state.
CapState gatherNeighbourhood(const Atoms& a, std::uint32_t x, std::span<const std::uint32_t> row, Scratch& s) {
  auto& nb = s.nb;
  nb.clear();
  const glm::dvec3 cx = a.c[x];
  const double Rx = a.R[x];
  bool some = false, covered = false;
  // Larger caps first: they bury most circles and contain most vertices, so the tests
  // that stop at the first such cap stop early. A bucket sort by cap size is enough for
  // that (bonded neighbours have cos ≈ 0.25, the others 0.5 to 1).
  auto& order = s.order;
  order.clear();
  std::uint32_t bucketStart[kCapBuckets + 1] = {};
  const double RxRx = Rx * Rx, invRx = 1.0 / Rx;
  for (const std::uint32_t j : row) {
    if (a.buried[j]) continue;
    const glm::dvec3 v = a.c[j] - cx;
    const double d = std::sqrt(glm::dot(v, v));  // glm::distance(cx, c_j)
    const double inv = 1.0 / d;
    double cosr = (d * d + RxRx - a.R[j] * a.R[j]) * (0.5 * inv) * invRx;
    // The convex patch's fate hangs on cos ≤ −1 (covered) and cos < 1 (a cap at all), that
    // is on whether the spheres cut or one contains the other; near ±1 that is decided
    // exactly, and the cosine put on the side it decides.
    if (!(std::abs(std::abs(cosr) - 1.0) > 1e-9)) {
      if (spheresCut(cx, Rx, a.c[j], a.R[j])) cosr = std::clamp(cosr, std::nextafter(-1.0, 0.0), std::nextafter(1.0, 0.0));
      else cosr = sphereInside(cx, Rx, a.c[j], a.R[j]) ? std::min(cosr, -1.0) : std::max(cosr, 1.0);
    }
    covered = covered || cosr <= -1.0;
    some = some || cosr < 1.0;
    const auto bucket = static_cast<std::uint32_t>(cosr >= kCapBucketBound[0]) +
                        static_cast<std::uint32_t>(cosr >= kCapBucketBound[1]) +
                        static_cast<std::uint32_t>(cosr >= kCapBucketBound[2]);
    // Caps far outside [−1, 1] decide the same way clamped; the clamp keeps floats tame.
    order.push_back({static_cast<float>(v.x * inv), static_cast<float>(v.y * inv), static_cast<float>(v.z * inv),
                     static_cast<float>(std::clamp(cosr, -4.0, 4.0)), j, bucket});
    ++bucketStart[bucket + 1];
  }
  for (std::size_t b = 0; b < kCapBuckets; ++b) bucketStart[b + 1] += bucketStart[b];
  const std::size_t count = order.size();
  nb.atom.resize(count);
  nb.sphere.resize(count);
  nb.ux.resize(count);
  nb.uy.resize(count);
  nb.uz.resize(count);
  nb.cosr.resize(count);
  nb.upper.clear();
  nb.maxRadius = 0.0;
  for (const auto& o : order) {
    const std::uint32_t l = bucketStart[o.bucket]++;
    const std::uint32_t j = o.atom;
    nb.atom[l] = j;
    nb.sphere[l] = glm::dvec4(a.c[j], a.R[j] * a.R[j]);
    nb.maxRadius = std::max(nb.maxRadius, a.R[j]);
    nb.ux[l] = o.ux;
    nb.uy[l] = o.uy;
    nb.uz[l] = o.uz;
    nb.cosr[l] = o.cosr;
    // The circles (x, j > x) in increasing j (the row is ascending): the output order.
    if (j > x) nb.upper.push_back(l);
  }
  while (nb.ux.size() % kPad != 0) {
    nb.ux.push_back(0.0f);
    nb.uy.push_back(0.0f);
    nb.uz.push_back(0.0f);
    nb.cosr.push_back(2.0f);  // misses every circle: q = 2, d < 0
  }
  return covered ? CapState::Covered : some ? CapState::Some : CapState::None;
}

// A probe position and what decides its tests exactly: its triple (sorted), which of the
// triple's two positions it is, and a bound on how far a double |p − c|² may be from the
// exact one for any sphere of the neighbourhood (the slack of insideMask).
struct ExactProbe {
  glm::dvec3 p;
  ProbeTriple triple;
  bool plus;
  double slack;
};

// The slack of |p − c|² for a position within `error` of the exact one and spheres of radius
// up to `maxRadius`: the error carried through |p − c| ≤ R + error, plus the rounding of the
// sum of squares.
double sideSlack(double error, double maxRadius) {
  const double reach = maxRadius + error;
  return 2.0 * reach * error + 0x1p-50 * reach * reach;
}

// |p − c|² against R² of neighbourhood sphere b, for the exact position: −1 inside beyond
// the tie tolerance, 0 a tie, 1 outside beyond it. Within the slack of a threshold the exact
// sign decides, as insideMask decides, so the two never disagree on a vertex.
int sideOf(const Neighbourhood& nb, std::size_t b, const ExactProbe& e) {
  const glm::dvec4& c = nb.sphere[b];
  const glm::dvec3 u = e.p - glm::dvec3(c);
  const double d2 = glm::dot(u, u);
  const auto below = [&](double threshold) {
    if (d2 < threshold - e.slack) return true;
    if (!(d2 < threshold + e.slack)) return false;
    return exactProbeSide(e.triple, e.plus, glm::dvec3(c), threshold) < 0;
  };
  return below(c.w * (1.0 - kTie)) ? -1 : below(c.w * (1.0 + kTie)) ? 0 : 1;
}

// The atoms whose spheres pass through the probe position (x and every live neighbour that
// ties), ascending; false if it lies strictly inside a neighbour sphere. A sphere through p
// meets x's sphere, so it is a neighbour of x.
bool tiesAt(const Neighbourhood& nb, std::uint32_t x, const ExactProbe& e, std::vector<std::uint32_t>& tied) {
  tied.clear();
  tied.push_back(x);
  for (std::size_t b = 0; b < nb.atom.size(); ++b) {
    const int side = sideOf(nb, b, e);
    if (side < 0) return false;
    if (side == 0) tied.push_back(nb.atom[b]);
  }
  std::sort(tied.begin(), tied.end());
  return true;
}

bool plusSideOf(const Atoms& a, std::uint32_t i, std::uint32_t j, std::uint32_t k, const glm::dvec3& p) {
  const glm::dvec3 ci = a.c[i];
  return glm::dot(p - ci, glm::cross(a.c[j] - ci, a.c[k] - ci)) > 0.0;
}

// The merged vertex of the cospherical atoms `atoms` (ascending, k >= 4) near p: the probe
// position of their first triple (in lexicographic order) that has one, on p's side, placed
// to within an ulp (preciseProbePair: merged vertices are rare, and other vertices within
// the error of a double position from one must not change order along a circle). A pure
// function of the atoms (and the side), so every owner computes the same bits.
std::optional<ExactProbe> mergedProbe(const Atoms& a, std::span<const std::uint32_t> atoms, const glm::dvec3& p,
                                      double maxRadius) {
  const std::size_t k = atoms.size();
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = i + 1; j < k; ++j)
      for (std::size_t l = j + 1; l < k; ++l) {
        const std::uint32_t u = atoms[i], v = atoms[j], w = atoms[l];
        const auto probes = preciseProbePair(a.c[u], a.R[u], a.c[v], a.R[v], a.c[w], a.R[w]);
        if (!probes) continue;
        const glm::dvec3 dp = probes->plus - p, dm = probes->minus - p;
        const bool plus = glm::dot(dp, dp) <= glm::dot(dm, dm);
        return ExactProbe{plus ? probes->plus : probes->minus, {a.c[u], a.c[v], a.c[w], a.R[u], a.R[v], a.R[w]}, plus,
                          sideSlack(probes->error, maxRadius)};
      }
  return std::nullopt;
}

// The concave polygon of a merged vertex: the probe sphere inside the convex cone of the
// contact directions u_m = (c_m − p)/|c_m − p|, triangulated. Its faces are the faces of the
// convex hull of {u_m} ∪ {0} that miss 0 (a pointed cone: one face, or several when the
// directions are not coplanar; all hull faces of {u_m} when the cone is all of space, a
// probe trapped at the centre of a cube). Each face is fanned from its lowest atom over its
// extreme directions in order; an edge is a boundary edge (where the torus of the pair ends)
// when no other triangle of the polygon has it. Directions lying within kFlat of a great
// circle through 0 give no face: a probe that just fits through a ring (E.7b) bounds no area.
void buildPolygon(const Atoms& a, std::span<const std::uint32_t> atoms, Polygon& poly) {
  constexpr double kFlat = 1e-12;
  const std::size_t k = atoms.size();
  std::vector<glm::dvec3> u(k);
  for (std::size_t m = 0; m < k; ++m) u[m] = glm::normalize(a.c[atoms[m]] - poly.p);
  poly.tri.clear();
  poly.edges.clear();
  std::vector<std::size_t> face;
  std::vector<std::pair<double, std::size_t>> ring;
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = i + 1; j < k; ++j)
      for (std::size_t l = j + 1; l < k; ++l) {
        glm::dvec3 nrm = glm::cross(u[j] - u[i], u[l] - u[i]);
        const double len = glm::length(nrm);
        if (!(len > 1e-9)) continue;
        nrm /= len;
        double off = glm::dot(nrm, u[i]);
        if (off < 0.0) nrm = -nrm, off = -off;  // 0 on the inner side
        if (!(off > kFlat)) continue;           // a plane through the probe: no face
        face.clear();
        bool hull = true;
        for (std::size_t m = 0; m < k && hull; ++m) {
          const double dm = glm::dot(nrm, u[m]) - off;
          if (dm > 1e-9) hull = false;
          else if (dm >= -1e-9) face.push_back(m);
        }
        if (!hull || face[0] != i || face[1] != j || face[2] != l) continue;  // each face once
        // Extreme directions of the face in order about its normal (convex position).
        const glm::dvec3 e1 = perpendicularTo(nrm), e2 = glm::cross(nrm, e1);
        glm::dvec3 g(0.0);
        for (const std::size_t m : face) g += u[m];
        g /= static_cast<double>(face.size());
        ring.clear();
        for (const std::size_t m : face) ring.push_back({std::atan2(glm::dot(u[m] - g, e2), glm::dot(u[m] - g, e1)), m});
        std::sort(ring.begin(), ring.end());
        // Drop directions on the segment between their neighbours (not extreme).
        for (bool dropped = true; dropped && ring.size() > 3;) {
          dropped = false;
          for (std::size_t r = 0; r < ring.size(); ++r) {
            const glm::dvec3& p0 = u[ring[(r + ring.size() - 1) % ring.size()].second];
            const glm::dvec3& p1 = u[ring[r].second];
            const glm::dvec3& p2 = u[ring[(r + 1) % ring.size()].second];
            if (glm::dot(glm::cross(p1 - p0, p2 - p1), nrm) <= 1e-12) {
              ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(r));
              dropped = true;
              break;
            }
          }
        }
        // Fan from the lowest atom (the face's first direction in atom order).
        std::size_t start = 0;
        for (std::size_t r = 1; r < ring.size(); ++r)
          if (ring[r].second < ring[start].second) start = r;
        for (std::size_t r = 1; r + 1 < ring.size(); ++r) {
          std::array<std::uint32_t, 3> t = {atoms[ring[start].second], atoms[ring[(start + r) % ring.size()].second],
                                            atoms[ring[(start + r + 1) % ring.size()].second]};
          std::sort(t.begin(), t.end());
          poly.tri.push_back(t);
        }
      }
  // Boundary edges: those of one triangle only.
  auto count = [&](std::uint32_t p, std::uint32_t q) {
    int c = 0;
    for (const auto& t : poly.tri)
      c += ((t[0] == p || t[1] == p || t[2] == p) && (t[0] == q || t[1] == q || t[2] == q)) ? 1 : 0;
    return c;
  };
  for (const auto& t : poly.tri)
    poly.edges.push_back(static_cast<std::uint8_t>((count(t[0], t[1]) == 1 ? 1 : 0) | (count(t[1], t[2]) == 1 ? 2 : 0) |
                                                   (count(t[2], t[0]) == 1 ? 4 : 0)));
}


// The circle (x, j) of neighbourhood position ai, computed when first needed; nothing
// when the extended spheres do not cut (then the circle contributes nothing).
const SasCircle* circleOf(const Atoms& a, std::uint32_t x, Scratch& s, std::size_t ai) {
  if (!s.hasCircle[ai]) {
    const std::uint32_t j = s.nb.atom[ai];
    const auto circle = sasCircle(a.c[x], a.R[x], a.c[j], a.R[j]);
    if (!circle) {
      s.state[ai] = CircleState::NoCircle;
      return nullptr;
    }
    s.circle[ai] = *circle;
    s.hasCircle[ai] = 1;
  }
  return &s.circle[ai];
}

// Every circle (x, j > x) first, so that settleCircles knows which circles are clearly
// buried; above[t]: the positions of the atoms after upper[t] in atom order (k > j).
void classifyCircles(Scratch& s, std::size_t words) {
  const auto& nb = s.nb;
  const std::size_t n = nb.atom.size();
  s.state.assign(n, CircleState::Open);
  s.cand.resize(n * words);
  s.cross.resize(n * words);
  s.circle.resize(n);
  s.hasCircle.assign(n, 0);
  s.buriedMask.assign(words, 0);
  for (const std::size_t ai : nb.upper) {
    if (!classifyCircle(nb, ai, &s.cand[ai * words], &s.cross[ai * words], words)) {
      s.state[ai] = CircleState::Buried;
      setBit(s.buriedMask.data(), ai);
    }
  }
  const std::size_t uppers = nb.upper.size();
  s.polys.clear();
  s.above.assign((uppers + 1) * words, 0);
  for (std::size_t t = uppers; t-- > 0;) {
    std::copy_n(&s.above[(t + 1) * words], words, &s.above[t * words]);
    if (t + 1 < uppers) setBit(&s.above[t * words], nb.upper[t + 1]);
  }
}

// The exact state of each open circle (x, j > x): buried, crossed by other spheres (it
// has vertices), or free (into out.freeOther). Returns the number of free circles.
std::uint32_t settleCircles(const Atoms& a, std::uint32_t x, Scratch& s, std::size_t words, VertexBuf& out) {
  std::uint32_t freeCount = 0;
  const auto& nb = s.nb;
  const glm::dvec3 cx = a.c[x];
  const double Rx = a.R[x];
  for (const std::size_t ai : nb.upper) {
    if (s.state[ai] != CircleState::Open) continue;
    const std::uint32_t j = nb.atom[ai];
    Word* cand = &s.cand[ai * words];
    Word* cross = &s.cross[ai * words];
    // Undecided spheres (within the margin of tangency) take the exact tests, as for any
    // sphere k of the circle's neighbourhood.
    bool buried = false;
    for (std::size_t w = 0; w < words && !buried; ++w) {
      Word undecided = cand[w] & ~cross[w];
      while (undecided) {
        const std::size_t b = w * kWordBits + static_cast<std::size_t>(std::countr_zero(undecided));
        undecided &= undecided - 1;
        const std::uint32_t k = nb.atom[b];
        if (!circleOf(a, x, s, ai)) break;
        if (!spheresCut(a.c[j], a.R[j], a.c[k], a.R[k])) {
          // Sphere k misses sphere j (or touches it), so it misses the circle, which lies on
          // j; it cannot contain j either, or j would be buried.
          clearBit(cand, b);
        } else if (sortedProbes(a, x, j, k)) {
          setBit(cross, b);
        } else if (circleBuriedBy(cx, Rx, a.c[j], a.R[j], a.c[k], a.R[k])) {
          // No crossing: the circle lies wholly inside sphere k (touching it at one point
          // at most), or wholly outside.
          buried = true;
          break;
        }
      }
    }
    if (s.state[ai] == CircleState::NoCircle) continue;
    bool crossed = false;
    for (std::size_t w = 0; w < words; ++w) crossed = crossed || cross[w] != 0;
    if (buried) {
      s.state[ai] = CircleState::BuriedExact;
    } else if (crossed) {
      s.state[ai] = CircleState::Crossed;
    } else if (circleOf(a, x, s, ai)) {
      s.state[ai] = CircleState::Free;
      out.freeOther.push_back(j);
      ++freeCount;
    }
  }

  return freeCount;
}

// Order along a circle. Two distinct vertices on one circle, p of sphere k and p' of
// sphere l, are apart by more than p's distance to sphere l, which is more than
// (√(1 + kTie) − 1) R_l ≥ 1e-10 rp unless p ties with l (then they merge). Positions from
// double are within eMax of the exact ones (probePositions), which is far less in real
// data, but not in every input; so a position closer than 8 eMax to another sphere is
// placed to an ulp: p and p' can only be confused if each lies that close to the other's
// sphere, and then both are placed exactly enough for atan2 to order them. Returns that
// band, relative.
double nearBandOf(const Atoms& a, std::uint32_t x, const Neighbourhood& nb) {
  const glm::dvec3 cx = a.c[x];
  const double Rx = a.R[x];
  const double coords = std::max({std::abs(cx.x), std::abs(cx.y), std::abs(cx.z)}) + Rx + 2.0 * nb.maxRadius;
  const double eMax = kMaxProbeError * std::max(Rx, nb.maxRadius) + 64.0 * kUnitRoundoff * coords;
  const double nearDist = 8.0 * eMax / a.rp;  // relative to the smallest possible R = rp
  const double nearBand = nearDist * (2.0 + nearDist);

  return nearBand;
}

// The valid vertices {x, j, k}, k > j, of the crossed circle upper[t] = (x, j) into
// s.verts (a merged vertex once, with its polygon in s.polys): a vertex is valid iff inside
// no other sphere. A sphere that contains a vertex meets both its circles (x, j) and (x, k),
// so it is a candidate of both; the others clearly miss one of the circles.
void findVertices(const Atoms& a, std::uint32_t x, Scratch& s, std::size_t t, std::size_t words, double nearBand) {
  const auto& nb = s.nb;
  const glm::dvec3 cx = a.c[x];
  const double Rx = a.R[x];
  const std::size_t ai = nb.upper[t];
  const std::uint32_t j = nb.atom[ai];
  const Word* candA = &s.cand[ai * words];
  const Word* crossA = &s.cross[ai * words];
  const Word* above = &s.above[t * words];
  s.verts.clear();
  for (std::size_t w = 0; w < words; ++w) {
    // Circles (x, k), k > j, not clearly buried (or so would be the vertex); a vertex
    // {x, k, j} with k < j is emitted from circle (x, k).
    Word bits = crossA[w] & above[w] & ~s.buriedMask[w];
    while (bits) {
      const std::size_t bi = w * kWordBits + static_cast<std::size_t>(std::countr_zero(bits));
      bits &= bits - 1;
      const std::uint32_t k = nb.atom[bi];
      const Word* candB = &s.cand[bi * words];
      // Most vertices lie deep inside some other sphere: a single-precision look first,
      // then the exact probe positions and tests for what it cannot settle.
      if (clearlyInsideBoth(nb, ai, bi)) continue;
      auto probes = probePositions(cx, Rx, a.c[j], a.R[j], a.c[k], a.R[k]);
      if (!probes) continue;
      // Both probe positions against each sphere at once: bit 0 plus, bit 1 minus.
      const ProbeTriple triple{cx, a.c[j], a.c[k], Rx, a.R[j], a.R[k]};
      const double slack = sideSlack(probes->error, nb.maxRadius);
      const int inside = insideMask(nb, candA, candB, words, ai, bi, triple, probes->plus, probes->minus, slack, nearBand);
      // A valid position (inside nothing, tied to nothing) near another sphere may be near
      // that sphere's own vertex on this circle: placed to within an ulp, so that their
      // order along it is the exact one. Bit 0 plus, bit 1 minus.
      if (const int nearOnly = (inside >> 4) & ~(inside >> 2) & ~inside & 3) {
        if (const auto precise = preciseProbePair(cx, Rx, a.c[j], a.R[j], a.c[k], a.R[k])) {
          if (nearOnly & 1) probes->plus = precise->plus;
          if (nearOnly & 2) probes->minus = precise->minus;
        }
      }
      for (const bool plus : {true, false}) {
        const glm::dvec3 p = plus ? probes->plus : probes->minus;
        if (inside & (plus ? 1 : 2)) continue;
        if (inside & (plus ? 4 : 8)) {
          // Further spheres pass through p (cospherical atoms, ORACLES E.6): one merged
          // vertex, emitted by the lowest of its atoms from the first triple that finds it.
          if (!tiesAt(nb, x, {p, triple, plus, slack}, s.tied) || s.tied.size() < 4) continue;
          const auto merged = mergedProbe(a, s.tied, p, nb.maxRadius);
          if (!merged || !tiesAt(nb, x, *merged, s.tied) || s.tied.size() < 4 || s.tied[0] != x) continue;
          bool seen = false;
          for (const Polygon& poly : s.polys) seen = seen || std::memcmp(&poly.p, &merged->p, sizeof(glm::dvec3)) == 0;
          if (seen) continue;
          s.polys.emplace_back();
          s.polys.back().p = merged->p;
          buildPolygon(a, s.tied, s.polys.back());
          s.verts.push_back({0.0, k, plus, merged->p, static_cast<std::uint32_t>(s.polys.size() - 1)});
          continue;
        }
        s.verts.push_back({0.0, k, plus, p});
      }
    }
  }
}

// s.verts in order of φ along the circle (ties by third atom, plus first).
void orderAlongCircle(const SasCircle& circle, std::vector<Vertex>& verts) {
  for (Vertex& v : verts) {
    const glm::dvec3 wv = v.p - circle.center;
    v.phi = std::atan2(glm::dot(wv, circle.e2), glm::dot(wv, circle.e1));
  }
  if (verts.size() > 1) {
    std::sort(verts.begin(), verts.end(), [](const Vertex& u, const Vertex& v) {
      if (u.phi != v.phi) return u.phi < v.phi;
      if (u.third != v.third) return u.third < v.third;
      return u.plus > v.plus;
    });
  }
}

// The concave patches of the ordered vertices on circle (x, j) into out: one per simple
// vertex, the triangles of a merged vertex's polygon. Returns their number.
std::uint32_t emitVertices(const Atoms& a, std::uint32_t x, std::uint32_t j, const Scratch& s, VertexBuf& out) {
  std::uint32_t concaveCount = 0;
  const glm::dvec3 cx = a.c[x];
  for (const Vertex& v : s.verts) {
    if (v.poly != ~0u) {
      const Polygon& poly = s.polys[v.poly];
      for (std::size_t f = 0; f < poly.tri.size(); ++f) {
        const auto& tri = poly.tri[f];
        out.probe.push_back(poly.p);
        out.dirI.push_back(glm::normalize(a.c[tri[0]] - poly.p));
        out.dirJ.push_back(glm::normalize(a.c[tri[1]] - poly.p));
        out.dirK.push_back(glm::normalize(a.c[tri[2]] - poly.p));
        out.atomI.push_back(tri[0]);
        out.atomJ.push_back(tri[1]);
        out.atomK.push_back(tri[2]);
        out.plus.push_back(plusSideOf(a, tri[0], tri[1], tri[2], poly.p) ? 1 : 0);
        out.edges.push_back(poly.edges[f]);
        out.group.push_back(static_cast<std::uint32_t>(f));
        ++concaveCount;
      }
      continue;
    }
    out.probe.push_back(v.p);
    out.dirI.push_back(glm::normalize(cx - v.p));
    out.dirJ.push_back(glm::normalize(a.c[j] - v.p));
    out.dirK.push_back(glm::normalize(a.c[v.third] - v.p));
    out.atomI.push_back(x);
    out.atomJ.push_back(j);
    out.atomK.push_back(v.third);
    out.plus.push_back(v.plus ? 1 : 0);
    out.edges.push_back(7);
    out.group.push_back(0);
    ++concaveCount;
  }
  return concaveCount;
}

}  // namespace

void vertexPass(const Atoms& a, std::uint32_t x, std::span<const std::uint32_t> row, Scratch& s, VertexBuf& out,
                CapState& capState) {
  std::uint32_t concaveCount = 0;
  capState = gatherNeighbourhood(a, x, row, s);
  const auto& nb = s.nb;
  const std::size_t words = (nb.atom.size() + kWordBits - 1) / kWordBits;
  classifyCircles(s, words);
  const std::uint32_t freeCount = settleCircles(a, x, s, words, out);
  const double nearBand = nearBandOf(a, x, nb);
  for (std::size_t t = 0; t < nb.upper.size(); ++t) {
    const std::size_t ai = nb.upper[t];
    if (s.state[ai] != CircleState::Crossed) continue;
    findVertices(a, x, s, t, words, nearBand);
    if (s.verts.empty()) continue;
    const SasCircle* circle = circleOf(a, x, s, ai);
    if (!circle) continue;
    orderAlongCircle(*circle, s.verts);
    concaveCount += emitVertices(a, x, nb.atom[ai], s, out);
  }
  out.concaveCount.push_back(concaveCount);
  out.freeCount.push_back(freeCount);
}

}  // namespace surftrace::build::detail
