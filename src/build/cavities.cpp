// Cavities located: lining atoms, surface centroid and exact box of every buried SES component.
#include "build/cavities.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "build/ses/surface_area.hpp"
#include "build/spherical_region.hpp"

namespace surftrace::build {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Slack of the in-region tests, on the unit sphere: a candidate this close to a cap or an arc's
// end is taken, so the box can only grow by it.
constexpr double kSlack = 1e-9;

struct Box {
  glm::dvec3 lower{std::numeric_limits<double>::infinity()};
  glm::dvec3 upper{-std::numeric_limits<double>::infinity()};
  void add(const glm::dvec3& x) { lower = glm::min(lower, x), upper = glm::max(upper, x); }
  void add(const Box& b) { lower = glm::min(lower, b.lower), upper = glm::max(upper, b.upper); }
};

// Whether angle phi lies in [from, to] (to − from <= 2π), modulo 2π.
bool inAngleRange(double phi, double from, double to) {
  double d = std::fmod(phi - from, kTwoPi);
  if (d < 0.0) d += kTwoPi;
  return d <= to - from + kSlack || d >= kTwoPi - kSlack;
}

// A circle arc on the unit sphere, u(φ) = α a + β (cos φ e1 + sin φ e2) for φ from phi0 to
// phi1: a torus's contact circle on one of its atoms, run with the atom's exposed part on
// its left (as surface_area.cpp runs it: decreasing φ for the torus's atom i).
struct CircleArc {
  glm::dvec3 a, e1, e2;
  double alpha, beta, phi0, phi1;
  glm::dvec3 at(double phi) const { return alpha * a + beta * (std::cos(phi) * e1 + std::sin(phi) * e2); }
};

CircleArc contactArc(const PatchList& p, std::size_t t, std::uint32_t atom, const glm::dvec3& center, double sasRadius) {
  const auto& tr = p.tori;
  const bool first = tr.atomI[t] == atom;
  const double ext = tr.phiExtent[t];
  return {tr.axis[t], tr.e1[t], glm::cross(tr.axis[t], tr.e1[t]), glm::dot(tr.center[t] - center, tr.axis[t]) / sasRadius,
          tr.bigRadius[t] / sasRadius, first ? ext : 0.0, first ? 0.0 : ext};
}

// The arc's end points and, per axis, its extremes A cos φ + B sin φ = M cos(φ − ψ) at ψ
// and ψ + π where they fall inside it.
void extendByArc(const CircleArc& c, glm::dvec3& lo, glm::dvec3& hi) {
  const double from = std::min(c.phi0, c.phi1), to = std::max(c.phi0, c.phi1);
  lo = glm::min(lo, glm::min(c.at(from), c.at(to)));
  hi = glm::max(hi, glm::max(c.at(from), c.at(to)));
  for (int k = 0; k < 3; ++k) {
    const double A = c.beta * c.e1[k], B = c.beta * c.e2[k], M = std::hypot(A, B), psi = std::atan2(B, A);
    if (inAngleRange(psi, from, to)) hi[k] = std::max(hi[k], c.alpha * c.a[k] + M);
    if (inAngleRange(psi + std::numbers::pi, from, to)) lo[k] = std::min(lo[k], c.alpha * c.a[k] - M);
  }
}

// Whether u lies in the region on the left of `arcs` (its whole boundary): a point w just to
// the left of an arc's middle is inside, and u is inside iff the great-circle path from u to
// w crosses the arcs an even number of times. No answer when the path grazes an arc or
// passes through an arc's end (the caller tries another arc).
std::optional<bool> insideByParity(const glm::dvec3& u, const CircleArc& reference, double fraction,
                                   const std::vector<CircleArc>& arcs) {
  const double phiMid = reference.phi0 + fraction * (reference.phi1 - reference.phi0);
  const glm::dvec3 v = reference.at(phiMid);
  const glm::dvec3 T = (reference.phi1 > reference.phi0 ? 1.0 : -1.0) *
                       (-std::sin(phiMid) * reference.e1 + std::cos(phiMid) * reference.e2);
  const glm::dvec3 w = glm::normalize(v + 1e-6 * glm::normalize(glm::cross(v, T)));
  glm::dvec3 d = w - glm::dot(w, u) * u;
  if (!(glm::length(d) > 1e-9)) return std::nullopt;
  d = glm::normalize(d);
  const double sEnd = std::atan2(glm::dot(w, d), glm::dot(w, u));  // in (0, π]
  int crossings = 0;
  for (const CircleArc& c : arcs) {
    // (cos s u + sin s d)·a = α.
    const double P = glm::dot(u, c.a), Q = glm::dot(d, c.a), M = std::hypot(P, Q);
    if (!(M > 0.0) || std::abs(c.alpha) > M) continue;
    if (std::abs(std::abs(c.alpha) - M) < 1e-12) return std::nullopt;  // tangent to the circle
    const double psi = std::atan2(Q, P), delta = std::acos(std::clamp(c.alpha / M, -1.0, 1.0));
    const double from = std::min(c.phi0, c.phi1), to = std::max(c.phi0, c.phi1);
    for (double s : {psi + delta, psi - delta}) {
      s = std::fmod(s, kTwoPi);
      if (s < 0.0) s += kTwoPi;
      if (s > sEnd + 1e-9) continue;
      if (s < 1e-9 || s > sEnd - 1e-9) return std::nullopt;  // u or w on the circle
      const glm::dvec3 x = std::cos(s) * u + std::sin(s) * d;
      const double phi = std::atan2(glm::dot(x, c.e2), glm::dot(x, c.e1));
      if (to - from < kTwoPi) {
        // Near an arc's end: a vertex, where two arcs meet, is counted once or twice; retry.
        double e = std::fmod(phi - from, kTwoPi);
        if (e < 0.0) e += kTwoPi;
        if (std::abs(e) < 1e-9 || std::abs(e - (to - from)) < 1e-9 || std::abs(e - kTwoPi) < 1e-9) return std::nullopt;
        if (e > to - from) continue;
      }
      ++crossings;
    }
  }
  return crossings % 2 == 0;
}

// The box (on the unit sphere about the atom) of the part of atom x's convex patch that
// belongs to `component`: bounded by the contact arcs of x's tori of that component. Its
// extremes lie on those arcs or at a pole ±e_k inside the part (insideByParity). (Not "outside
// every torus neighbour's cap": an atom with no torus with x can still cover a pole, where
// its own circle is covered by others.)
Box convexPartBox(const PatchList& p, std::uint32_t x, const glm::dvec3& center, double radius, std::uint32_t component,
                  const std::vector<std::uint32_t>& tori) {
  const double sasRadius = radius + p.params.probeRadius;
  std::vector<CircleArc> own;
  for (const std::uint32_t t : tori)
    if (p.tori.component[t] == component) own.push_back(contactArc(p, t, x, center, sasRadius));
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  if (own.empty()) {
    // A patch with no arc of its component: the whole sphere (an atom alone), conservatively.
    lo = glm::dvec3(-1.0), hi = glm::dvec3(1.0);
  } else {
    for (const CircleArc& c : own) extendByArc(c, lo, hi);
    for (int k = 0; k < 3; ++k) {
      for (const double sign : {1.0, -1.0}) {
        glm::dvec3 u(0.0);
        u[k] = sign;
        std::optional<bool> answer;
        for (std::size_t r = 0; r < 3 * own.size() && !answer; ++r)
          answer = insideByParity(u, own[r % own.size()], 0.5 - 0.13 * static_cast<double>(r / own.size()), own);
        const bool inside = answer.value_or(true);  // undecided: taken, so the box stays conservative
        if (inside) lo = glm::min(lo, u), hi = glm::max(hi, u);
      }
    }
  }
  Box b;
  b.add(center + radius * lo);
  b.add(center + radius * hi);
  return b;
}

// The box of torus patch t. Per axis k, x_k = c_k + ρ(θ)(A cos φ + B sin φ) + rp sin θ n_k with
// ρ = R − rp cos θ >= 0 on the SES part of θ: over φ the extreme is ρ times the extreme C of
// A cos φ + B sin φ on [0, Δφ], then over θ that of R C + rp (n_k sin θ − C cos θ), a sinusoid.
Box torusBox(const PatchList& p, std::size_t t) {
  const auto& tr = p.tori;
  const double R = tr.bigRadius[t], rp = p.params.probeRadius, ext = tr.phiExtent[t];
  const glm::dvec3 n = tr.axis[t], e1 = tr.e1[t], e2 = glm::cross(n, e1);
  std::vector<std::pair<double, double>> intervals;
  if (R >= rp) {
    intervals.emplace_back(tr.thetaI[t], tr.thetaJ[t]);
  } else {
    const double thetaC = std::acos(R / rp);
    if (tr.thetaI[t] < -thetaC) intervals.emplace_back(tr.thetaI[t], std::min(tr.thetaJ[t], -thetaC));
    if (tr.thetaJ[t] > thetaC) intervals.emplace_back(std::max(tr.thetaI[t], thetaC), tr.thetaJ[t]);
  }
  Box b;
  for (int k = 0; k < 3; ++k) {
    const double A = e1[k], B = e2[k], M = std::hypot(A, B), psi = std::atan2(B, A);
    const double atEnds[2] = {A, A * std::cos(ext) + B * std::sin(ext)};
    double cMax = std::max(atEnds[0], atEnds[1]), cMin = std::min(atEnds[0], atEnds[1]);
    if (inAngleRange(psi, 0.0, ext)) cMax = M;
    if (inAngleRange(psi + std::numbers::pi, 0.0, ext)) cMin = -M;
    for (const auto& [from, to] : intervals) {
      for (const double C : {cMax, cMin}) {
        auto value = [&](double th) { return tr.center[t][k] + (R - rp * std::cos(th)) * C + rp * std::sin(th) * n[k]; };
        // Candidates: the ends and the sinusoid's extremes n_k sin θ − C cos θ, at atan2(n_k, −C) ± π.
        const double crit = std::atan2(n[k], -C);
        for (const double th : {from, to, crit, crit - std::numbers::pi, crit + std::numbers::pi})
          if (th >= from && th <= to) {
            b.lower[k] = std::min(b.lower[k], value(th));
            b.upper[k] = std::max(b.upper[k], value(th));
          }
      }
    }
  }
  return b;
}

// The box of concave patch c: its probe sphere minus caps (concaveCaps). The extremes of such
// a region lie at a pole, at a cap circle's own extreme, or where two cap circles meet, each
// taken when no other cap covers it.
Box concaveBox(const PatchList& p, std::size_t c, std::vector<Cap>& caps) {
  concaveCaps(p, c, caps);
  const double rp = p.params.probeRadius;
  Box b;
  auto take = [&](const glm::dvec3& u, int onA, int onB) {
    for (int m = 0; m < static_cast<int>(caps.size()); ++m)
      if (m != onA && m != onB && glm::dot(u, caps[static_cast<std::size_t>(m)].axis) > caps[static_cast<std::size_t>(m)].cosRadius + kSlack)
        return;
    b.add(p.concave.probe[c] + rp * u);
  };
  for (int k = 0; k < 3; ++k)
    for (const double sign : {1.0, -1.0}) {
      glm::dvec3 u(0.0);
      u[k] = sign;
      take(u, -1, -1);
    }
  for (std::size_t m = 0; m < caps.size(); ++m) {
    const Cap& cap = caps[m];
    if (std::abs(cap.cosRadius) >= 1.0) continue;
    const double s = std::sqrt(1.0 - cap.cosRadius * cap.cosRadius);
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 w = -cap.axis[k] * cap.axis;
      w[k] += 1.0;
      const double len = glm::length(w);
      if (!(len > 1e-12)) continue;  // the circle lies in a plane ⊥ e_k: its points bound it alike
      take(cap.cosRadius * cap.axis + s * (w / len), static_cast<int>(m), -1);
      take(cap.cosRadius * cap.axis - s * (w / len), static_cast<int>(m), -1);
    }
    for (std::size_t o = m + 1; o < caps.size(); ++o) {
      // u = α a1 + β a2 + γ (a1 × a2) on both circles u·a1 = c1, u·a2 = c2.
      const glm::dvec3 a1 = cap.axis, a2 = caps[o].axis, cr = glm::cross(a1, a2);
      const double g = glm::dot(a1, a2), det = 1.0 - g * g, cr2 = glm::dot(cr, cr);
      if (!(det > 1e-14) || !(cr2 > 1e-14)) continue;
      const double c1 = cap.cosRadius, c2 = caps[o].cosRadius;
      const double alpha = (c1 - g * c2) / det, beta = (c2 - g * c1) / det;
      const glm::dvec3 base = alpha * a1 + beta * a2;
      const double rest = 1.0 - glm::dot(base, base);
      if (rest < 0.0) continue;
      const double gamma = std::sqrt(rest / cr2);
      take(base + gamma * cr, static_cast<int>(m), static_cast<int>(o));
      take(base - gamma * cr, static_cast<int>(m), static_cast<int>(o));
    }
  }
  if (!(b.lower.x <= b.upper.x)) {
    // No candidate taken (an empty or degenerate patch): the whole probe sphere bounds it.
    b.add(p.concave.probe[c] - glm::dvec3(rp));
    b.add(p.concave.probe[c] + glm::dvec3(rp));
  }
  return b;
}

}  // namespace

std::vector<Cavity> locateCavities(const PatchList& p) {
  if (p.params.surface != SurfaceKind::Ses)
    throw std::invalid_argument(std::string("cavities are located on the SES; this is a ") + surfaceKindName(p.params.surface) +
                                " patch list, whose patches carry no component labels");
  const SurfaceAreas areas = computeAreas(p);
  const std::size_t count = areas.components.size();
  std::vector<Box> boxes(count);
  std::vector<std::vector<std::uint32_t>> atoms(count);
  auto cavity = [&](std::uint32_t label) { return label < count && !areas.components[label].outer(); };
  // Atom → its tori, a counting sort.
  const std::size_t n = p.params.atomCount;
  std::vector<std::uint32_t> toriBegin(n + 2, 0), toriOf;
  for (std::size_t t = 0; t < p.tori.size(); ++t) ++toriBegin[p.tori.atomI[t] + 2], ++toriBegin[p.tori.atomJ[t] + 2];
  for (std::size_t i = 0; i < n; ++i) toriBegin[i + 2] += toriBegin[i + 1];
  toriOf.resize(toriBegin[n + 1]);
  for (std::size_t t = 0; t < p.tori.size(); ++t)
    for (const std::uint32_t x : {p.tori.atomI[t], p.tori.atomJ[t]}) toriOf[toriBegin[x + 1]++] = static_cast<std::uint32_t>(t);
  std::vector<std::uint32_t> tori, partComponents;
  for (std::size_t k = 0; k < p.convex.size(); ++k) {
    const std::uint32_t x = p.convex.atom[k];
    tori.assign(toriOf.begin() + toriBegin[x], toriOf.begin() + toriBegin[x + 1]);
    // The patch's own label and every other component its tori bound a part of.
    partComponents.assign(1, p.convex.component[k]);
    for (const std::uint32_t t : tori)
      if (std::find(partComponents.begin(), partComponents.end(), p.tori.component[t]) == partComponents.end())
        partComponents.push_back(p.tori.component[t]);
    for (const std::uint32_t label : partComponents) {
      if (!cavity(label)) continue;
      atoms[label].push_back(x);
      boxes[label].add(convexPartBox(p, x, p.convex.center[k], p.convex.radius[k], label, tori));
    }
  }
  for (std::size_t t = 0; t < p.tori.size(); ++t) {
    const std::uint32_t label = p.tori.component[t];
    if (!cavity(label)) continue;
    atoms[label].push_back(p.tori.atomI[t]);
    atoms[label].push_back(p.tori.atomJ[t]);
    boxes[label].add(torusBox(p, t));
  }
  std::vector<Cap> caps;
  for (std::size_t c = 0; c < p.concave.size(); ++c) {
    const std::uint32_t label = p.concave.component[c];
    if (!cavity(label)) continue;
    for (const std::uint32_t x : {p.concave.atomI[c], p.concave.atomJ[c], p.concave.atomK[c]}) atoms[label].push_back(x);
    boxes[label].add(concaveBox(p, c, caps));
  }
  std::vector<Cavity> out;
  for (std::uint32_t label = 0; label < count; ++label) {
    if (!cavity(label)) continue;
    const SurfaceAreas::Component& component = areas.components[label];
    Cavity c;
    c.component = label;
    c.area = component.area;
    c.volume = -component.volume;
    c.centroid = component.area > 0.0 ? component.areaMoment / component.area : glm::dvec3(0.0);
    c.boxLower = boxes[label].lower;
    c.boxUpper = boxes[label].upper;
    std::sort(atoms[label].begin(), atoms[label].end());
    atoms[label].erase(std::unique(atoms[label].begin(), atoms[label].end()), atoms[label].end());
    c.atoms = std::move(atoms[label]);
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace surftrace::build
