// SES contour pass: exposed arcs, tori, convex patch areas and the faces of each atom's exposed region.
#include "build/ses/ses_contours.hpp"

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
#include <glm/vec2.hpp>

#include "build/ses/sas_geometry.hpp"

namespace surftrace::build::detail {
namespace {

void pushTorus(ContourBuf& t, const SasCircle& circle, double phi0, double extent, std::uint32_t i, std::uint32_t j) {
  t.torusCenter.push_back(circle.center);
  t.torusAxis.push_back(circle.axis);
  t.torusE1.push_back(std::cos(phi0) * circle.e1 + std::sin(phi0) * circle.e2);
  t.bigRadius.push_back(circle.radius);
  t.thetaI.push_back(std::atan2(-circle.t, circle.radius));
  t.thetaJ.push_back(std::atan2(circle.distance - circle.t, circle.radius));
  t.phiExtent.push_back(extent);
  t.torusI.push_back(i);
  t.torusJ.push_back(j);
}

// Exterior angle of the region's boundary at u, between circles a and b: the angle between
// their axes projected into the tangent plane at u (ORACLES D.2).
double exteriorAngle(const glm::dvec3& axisA, const glm::dvec3& axisB, const glm::dvec3& u) {
  const glm::dvec3 ma = axisA - glm::dot(axisA, u) * u;
  const glm::dvec3 mb = axisB - glm::dot(axisB, u) * u;
  const double la = glm::length(ma), lb = glm::length(mb);
  if (la == 0.0 || lb == 0.0) return 0.0;
  return std::acos(std::clamp(glm::dot(ma, mb) / (la * lb), -1.0, 1.0));
}

int findRoot(std::vector<int>& parent, int v) {
  while (parent[static_cast<std::size_t>(v)] != v) {
    parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    v = parent[static_cast<std::size_t>(v)];
  }
  return v;
}

// The exposed arcs of one circle from its valid vertices, ordered along it: an arc runs
// from a vertex where the circle leaves a sphere to the next where it enters one.
template <class Emit> void sweepArcs(std::span<const Entry> list, Emit&& emit) {
  const std::size_t count = list.size();
  const auto firstLeave = std::find_if(list.begin(), list.end(), [](const Entry& e) { return e.leaves; });
  if (firstLeave == list.end()) return;
  const std::size_t start = static_cast<std::size_t>(firstLeave - list.begin());
  std::size_t pending = count;  // index of an unmatched leaving vertex
  for (std::size_t step = 0; step <= count; ++step) {
    const std::size_t idx = (start + step) % count;
    const Entry& e = list[idx];
    if (e.leaves) {
      if (step < count) pending = idx;
    } else if (pending != count) {
      double extent = e.phi - list[pending].phi;
      if (extent < 0.0) extent += kTwoPi;
      if (extent > 0.0) emit(list[pending], e, extent);
      pending = count;
    }
  }
}

void sortAlongCircle(std::span<Entry> list) {
  std::sort(list.begin(), list.end(), [](const Entry& u, const Entry& v) {
    if (u.phi != v.phi) return u.phi < v.phi;
    if (u.third != v.third) return u.third < v.third;
    return u.plus > v.plus;
  });
}

// The winding number of cycle `cycle` of s.arcs around q, seen in the stereographic
// projection from p0 (a point off the cycle): ±1 if q and p0 lie on opposite sides of it,
// 0 if on the same side. Counted as signed crossings of a ray from q by the projected
// arcs, sampled finely (every π/16 of each circle) so that the polygon winds like the arcs
// unless q all but touches the cycle.
int windingNumber(const Scratch& s, int cycle, const glm::dvec3& p0, const glm::dvec3& q) {
  // The ray leaves q in a direction no symmetry of the input favours (the plane's axes
  // rotated by 1 radian), so it does not run through vertices of symmetric inputs.
  const glm::dvec3 g1 = perpendicularTo(p0), g2 = glm::cross(p0, g1);
  const glm::dvec3 f1 = std::cos(1.0) * g1 + std::sin(1.0) * g2, f2 = glm::cross(p0, f1);
  auto project = [&](const glm::dvec3& u) {
    const double w = 1.0 / (1.0 - glm::dot(u, p0));
    return glm::dvec2(glm::dot(u, f1) * w, glm::dot(u, f2) * w);
  };
  const glm::dvec2 at = project(q);
  int winding = 0;
  for (std::size_t k = 0; k < s.arcs.size(); ++k) {
    if (s.cycleOf[k] != cycle) continue;
    const Arc& arc = s.arcs[k];
    const int steps = std::max(4, static_cast<int>(std::ceil(arc.extent * (16.0 / kPi))));
    const double step = arc.extent / steps, cosStep = std::cos(step), sinStep = std::sin(step);
    double c = std::cos(arc.phi0), sn = std::sin(arc.phi0);
    glm::dvec2 prev = project(arc.cosA * arc.axis + arc.sinA * (c * arc.e1 + sn * arc.e2)) - at;
    for (int i = 1; i <= steps; ++i) {
      const double c2 = c * cosStep - sn * sinStep;
      sn = sn * cosStep + c * sinStep;
      c = c2;
      const glm::dvec2 cur = project(arc.cosA * arc.axis + arc.sinA * (c * arc.e1 + sn * arc.e2)) - at;
      if ((prev.y < 0.0) != (cur.y < 0.0)) {
        // Where the segment crosses y = 0: on the ray (x > 0) it counts, upward +1.
        const double cross = prev.x * cur.y - prev.y * cur.x;  // sign of x at the crossing, times dy
        if ((cross > 0.0) == (cur.y > prev.y)) winding += cur.y > prev.y ? 1 : -1;
      }
      prev = cur;
    }
  }
  return winding;
}

// A point of cycle `cycle` (the start of its first arc) and one certainly on its right (the
// centre of that arc's cap: the open cap lies wholly right of the cycle).
glm::dvec3 pointOn(const Scratch& s, int cycle) {
  for (std::size_t k = 0; k < s.arcs.size(); ++k) {
    if (s.cycleOf[k] != cycle) continue;
    const Arc& arc = s.arcs[k];
    return arc.cosA * arc.axis + arc.sinA * (std::cos(arc.phi0) * arc.e1 + std::sin(arc.phi0) * arc.e2);
  }
  return glm::dvec3(0.0);
}
glm::dvec3 pointRightOf(const Scratch& s, int cycle) {
  for (std::size_t k = 0; k < s.arcs.size(); ++k)
    if (s.cycleOf[k] == cycle) return s.arcs[k].axis;
  return glm::dvec3(0.0);
}
bool leftOfCycle(const Scratch& s, int cycle, const glm::dvec3& q) {
  return windingNumber(s, cycle, pointRightOf(s, cycle), q) != 0;
}

// The faces of atom x's exposed region (sphere minus caps): its connected components. A
// face with several boundary cycles (a band between two caps) is one piece of surface; two
// faces (a thin wall, exposed on both sides) can belong to different SES components. The
// cycles are disjoint closed curves with the region on their left, so two cycles bound the
// same face iff each lies left of the other and every other cycle sees them on one side.
// Fills s.cycleFace (face of each cycle, numbered in cycle order); returns the face count.
int groupCyclesIntoFaces(Scratch& s, int cycles) {
  const auto n = static_cast<std::size_t>(std::max(cycles, 0));
  s.cycleFace.assign(n, 0);
  if (cycles <= 1) return 1;
  s.leftOf.assign(n * n, 1);
  for (int i = 0; i < cycles; ++i) {
    const glm::dvec3 q = pointOn(s, i);
    for (int j = 0; j < cycles; ++j)
      if (i != j) s.leftOf[static_cast<std::size_t>(i) * n + static_cast<std::size_t>(j)] = leftOfCycle(s, j, q) ? 1 : 0;
  }
  auto left = [&](std::size_t i, std::size_t j) { return s.leftOf[i * n + j] != 0; };
  s.parent.resize(n);
  for (std::size_t i = 0; i < n; ++i) s.parent[i] = static_cast<int>(i);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      bool same = left(i, j) && left(j, i);
      for (std::size_t k = 0; k < n && same; ++k)
        if (k != i && k != j) same = left(i, k) == left(j, k);
      if (same) s.parent[static_cast<std::size_t>(findRoot(s.parent, static_cast<int>(j)))] = findRoot(s.parent, static_cast<int>(i));
    }
  }
  int faces = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto root = static_cast<std::size_t>(findRoot(s.parent, static_cast<int>(i)));
    s.cycleFace[i] = root == i ? faces++ : s.cycleFace[root];
  }
  return faces;
}

// The face that contains the region point u (after groupCyclesIntoFaces): the face whose
// cycles all have u on their left and whose other cycles see u on the face's side.
std::uint32_t faceContaining(Scratch& s, int cycles, const glm::dvec3& u) {
  if (cycles <= 1) return 0;
  const auto n = static_cast<std::size_t>(cycles);
  for (std::size_t i = 0; i < n; ++i) {
    bool inside = leftOfCycle(s, static_cast<int>(i), u);
    for (std::size_t j = 0; j < n && inside; ++j)
      if (j != i) inside = leftOfCycle(s, static_cast<int>(j), u) == (s.leftOf[i * n + j] != 0);
    if (inside) return static_cast<std::uint32_t>(s.cycleFace[i]);
  }
  return 0;
}


// Whether concave patch v is a triangle of a merged vertex (ORACLES E.6): some edge is not
// a boundary edge, or it is not alone in its group.
bool ofMergedVertex(const Incidence& inc, std::uint32_t v) {
  return inc.edges[v] != 7 || inc.group[v] != 0 || (v + 1 < inc.group.size() && inc.group[v + 1] == 1);
}

// The entries of atom x's circles into s.entries, sorted by circle and vertex: each vertex
// {x, o1, o2} twice (on circles (x, o1) and (x, o2)), a merged vertex twice at its first
// triangle that has x, a free circle once. Returns whether x has a merged vertex.
bool gatherEntries(const Atoms& a, const Incidence& inc, std::uint32_t x, Scratch& s) {
  auto& entries = s.entries;
  entries.clear();
  bool anyMerged = false;
  for (std::uint32_t k = inc.vertexBegin[x]; k < inc.vertexBegin[x + 1]; ++k) {
    const std::uint32_t v = inc.vertex[k];
    const std::uint32_t i = inc.atomI[v], j = inc.atomJ[v], l = inc.atomK[v];
    if (ofMergedVertex(inc, v)) {
      // A triangle of a merged vertex (ORACLES E.6): x's arcs end there on the circles of
      // its two boundary edges; the sphere entered is the other boundary neighbour. Once
      // per merged vertex, at its first triangle that has x.
      anyMerged = true;
      const std::uint32_t first = v - inc.group[v];
      std::uint32_t end = first + 1;
      while (end < inc.group.size() && inc.group[end] == end - first) ++end;
      bool earlier = false;
      for (std::uint32_t t = first; t < v && !earlier; ++t)
        earlier = inc.atomI[t] == x || inc.atomJ[t] == x || inc.atomK[t] == x;
      if (earlier) continue;
      std::uint32_t nbr[2] = {~0u, ~0u};
      int found = 0;
      for (std::uint32_t t = first; t < end; ++t) {
        const std::uint32_t tri[3] = {inc.atomI[t], inc.atomJ[t], inc.atomK[t]};
        for (int e = 0; e < 3; ++e) {
          if (!(inc.edges[t] & (1u << e))) continue;
          const std::uint32_t p0 = tri[e], p1 = tri[(e + 1) % 3];
          if (p0 != x && p1 != x) continue;
          if (found < 2) nbr[found] = p0 == x ? p1 : p0;
          ++found;
        }
      }
      if (found != 2) continue;  // no boundary at x (a probe enclosed by the atoms)
      auto sidePlus = [&](std::uint32_t o, std::uint32_t w) {
        std::uint32_t t3[3] = {x, o, w};
        std::sort(t3, t3 + 3);
        const glm::dvec3 c0 = a.c[t3[0]];
        return glm::dot(inc.probe[first] - c0, glm::cross(a.c[t3[1]] - c0, a.c[t3[2]] - c0)) > 0.0;
      };
      entries.push_back({nbr[0], nbr[1], first, sidePlus(nbr[0], nbr[1]), false, 0.0, 0.0, 0.0, k});
      entries.push_back({nbr[1], nbr[0], first, sidePlus(nbr[1], nbr[0]), false, 0.0, 0.0, 0.0, k});
      continue;
    }
    const std::uint32_t o1 = x == i ? j : i;
    const std::uint32_t o2 = x == l ? j : l;
    const bool plus = inc.plus[v] != 0;
    entries.push_back({o1, o2, v, plus, false, 0.0, 0.0, 0.0, k});
    entries.push_back({o2, o1, v, plus, false, 0.0, 0.0, 0.0, k});
  }
  for (std::uint32_t k = inc.freeBegin[x]; k < inc.freeBegin[x + 1]; ++k)
    entries.push_back({inc.free[k], ~0u, ~0u, false, false, 0.0, 0.0, 0.0, k});
  std::sort(entries.begin(), entries.end(), [](const Entry& u, const Entry& v) {
    return u.other < v.other || (u.other == v.other && u.vertex < v.vertex);
  });

  return anyMerged;
}

// What the arcs of x's region add up to (ORACLES D.2): the turning of its boundary
// (Σ geodesic-curvature terms − Σ exterior angles), its vector area, and the largest cap.
struct RegionSums {
  double turning = 0.0;
  glm::dvec3 vectorArea{0.0};
  double maxCapArea = 0.0;
};

// The exposed arcs of circle (x, o) from its entries (ordered along it here) into s.arcs,
// with their tori (x the lower atom) into out, and what they add to the region's sums.
// Returns the number of tori.
std::uint32_t traceCircle(const Atoms& a, const Incidence& inc, std::uint32_t x, std::uint32_t o, std::span<Entry> list,
                          Scratch& s, ContourBuf& out, RegionSums& sums) {
  std::uint32_t toriCount = 0;
  const glm::dvec3 cx = a.c[x];
  const double Rx = a.R[x];
  double& turning = sums.turning;
  glm::dvec3& vectorArea = sums.vectorArea;
  double& maxCapArea = sums.maxCapArea;

  // The cap of o on x's unit sphere, as the convex patch sees it.
  const double d = glm::distance(cx, a.c[o]);
  const double t = (d * d + Rx * Rx - a.R[o] * a.R[o]) / (2.0 * d);
  const glm::dvec3 axis = (a.c[o] - cx) / d;
  const double cosA = t / Rx;
  const double sinA = std::sqrt(std::max(0.0, 1.0 - cosA * cosA));
  maxCapArea = std::max(maxCapArea, kTwoPi * (1.0 - cosA));

  // For x < o the cap's frame is the circle's own (same axis and e1, bit for bit).
  std::optional<SasCircle> circle;
  glm::dvec3 e1, e2;
  if (x < o) {
    circle = sasCircle(cx, Rx, a.c[o], a.R[o]);
    if (!circle) return 0;
    e1 = circle->e1;
    e2 = circle->e2;
  } else {
    e1 = perpendicularTo(axis);
    e2 = glm::cross(axis, e1);
  }
  // The region lies outside the cap, so its boundary runs with decreasing φ about the
  // axis; with the region on the left, an arc φ0→φ1 adds −½[...] to W (ORACLES D.2).
  // (The sines and cosines of the ends are the vertices' own, so no trigonometry.)
  auto addArc = [&](double extent, double cos0, double sin0, double cos1, double sin1) {
    turning += cosA * extent;
    vectorArea -= 0.5 * (sinA * sinA * extent * axis - cosA * sinA * ((sin1 - sin0) * e1 + (cos0 - cos1) * e2));
  };

  if (list[0].vertex == ~0u) {  // a free circle
    addArc(kTwoPi, 1.0, 0.0, 1.0, 0.0);
    s.arcs.push_back({~0u, ~0u, o, axis, e1, e2, cosA, sinA, 0.0, kTwoPi});
    if (circle) {
      pushTorus(out, *circle, 0.0, kTwoPi, x, o);
      s.torusArc.push_back(static_cast<std::uint32_t>(s.arcs.size() - 1));
      ++toriCount;
    }
    return toriCount;
  }

  for (Entry& e : list) {
    const glm::dvec3 p = inc.probe[e.vertex];
    double px, py;
    if (circle) {
      const glm::dvec3 w = p - circle->center;
      px = glm::dot(w, circle->e1);
      py = glm::dot(w, circle->e2);
      e.leaves = e.plus == plusLeavesSphere(x, o, e.third);
    } else {
      // Seen from x > o the circle of (o, x) runs backwards (axis −n, e1 −e1, e2 e2).
      const glm::dvec3 u = p - cx;
      px = glm::dot(u, e1);
      py = glm::dot(u, e2);
      e.leaves = e.plus != plusLeavesSphere(o, x, e.third);
    }
    e.phi = std::atan2(py, px);
    const double len = std::sqrt(px * px + py * py);
    e.cosPhi = len > 0.0 ? px / len : 1.0;
    e.sinPhi = len > 0.0 ? py / len : 0.0;
  }
  sortAlongCircle(list);
  sweepArcs(list, [&](const Entry& from, const Entry& to, double extent) {
    s.arcs.push_back({from.vertex, to.vertex, o, axis, e1, e2, cosA, sinA, from.phi, extent});
    if (circle) {
      pushTorus(out, *circle, from.phi, extent, x, o);
      s.torusArc.push_back(static_cast<std::uint32_t>(s.arcs.size() - 1));
      ++toriCount;
    }
    addArc(extent, from.cosPhi, from.sinPhi, to.cosPhi, to.sinPhi);
    const glm::dvec3 u1 = (inc.probe[to.vertex] - cx) / Rx;
    const glm::dvec3 entered = glm::normalize(a.c[to.third] - cx);
    turning -= exteriorAngle(axis, entered, u1);
  });
  return toriCount;
}

// The exposed arcs of each circle of x into s.arcs, each with its torus (x the lower atom)
// into out; returns the number of tori.
std::uint32_t traceArcs(const Atoms& a, const Incidence& inc, std::uint32_t x, Scratch& s, ContourBuf& out,
                        RegionSums& sums) {
  std::uint32_t toriCount = 0;
  auto& entries = s.entries;
  s.arcs.clear();
  s.torusArc.clear();

  for (std::size_t g = 0; g < entries.size();) {
    std::size_t end = g;
    while (end < entries.size() && entries[end].other == entries[g].other) ++end;
    std::span<Entry> list(entries.data() + g, entries.data() + end);
    g = end;
    const std::uint32_t o = list[0].other;
    // Free-circle entries sort last; beside vertices (only conceivable at exact tangency)
    // the vertices win.
    while (list.size() > 1 && list.back().vertex == ~0u && list.front().vertex != ~0u) list = list.first(list.size() - 1);
    toriCount += traceCircle(a, inc, x, o, list, s, out, sums);
  }
  return toriCount;
}

// The boundary cycles of x's region: the arc that ends at a vertex continues, on the
// other circle through it, with the arc that starts there; a free circle is a cycle of its
// own. Sets s.cycleOf per arc; returns the number of cycles.
int linkCycles(Scratch& s) {
  const std::size_t arcs = s.arcs.size();
  s.parent.resize(arcs);
  for (std::size_t k = 0; k < arcs; ++k) s.parent[k] = static_cast<int>(k);
  for (std::size_t e = 0; e < arcs; ++e) {
    if (s.arcs[e].to == ~0u) continue;
    for (std::size_t st = 0; st < arcs; ++st) {
      if (s.arcs[st].from == s.arcs[e].to) {
        s.parent[static_cast<std::size_t>(findRoot(s.parent, static_cast<int>(e)))] = findRoot(s.parent, static_cast<int>(st));
        break;
      }
    }
  }
  s.cycleOf.resize(arcs);
  int cycles = 0;
  for (std::size_t k = 0; k < arcs; ++k) {
    if (findRoot(s.parent, static_cast<int>(k)) == static_cast<int>(k)) s.cycleOf[k] = cycles++;
  }
  for (std::size_t k = 0; k < arcs; ++k) s.cycleOf[k] = s.cycleOf[static_cast<std::size_t>(findRoot(s.parent, static_cast<int>(k)))];

  return cycles;
}

// The faces of x's region (connected components of the exposed region, for the SES
// components): the face of each torus, incident vertex and free circle, x's face count,
// and the face facing +x if x is the extreme atom.
void assignFaces(const Incidence& inc, std::uint32_t x, Scratch& s, int cycles, bool anyMerged, ContourBuf& out) {
  const auto& entries = s.entries;
  const std::size_t arcs = s.arcs.size();
  const int faces = groupCyclesIntoFaces(s, cycles);
  for (std::size_t k = 0; k < s.torusArc.size(); ++k)
    out.torusFace.push_back(static_cast<std::uint32_t>(s.cycleFace[static_cast<std::size_t>(s.cycleOf[s.torusArc[k]])]));
  inc.faceCount[x] = static_cast<std::uint32_t>(faces);
  for (const Entry& e : entries) {
    std::uint32_t face = 0;
    for (std::size_t k = 0; k < arcs; ++k) {
      const Arc& arc = s.arcs[k];
      const bool mine = e.vertex == ~0u ? arc.from == ~0u && arc.other == e.other : arc.from == e.vertex || arc.to == e.vertex;
      if (mine) {
        face = static_cast<std::uint32_t>(s.cycleFace[static_cast<std::size_t>(s.cycleOf[k])]);
        break;
      }
    }
    if (e.vertex == ~0u) inc.freeFace[e.slot] = face;
    else inc.vertexFace[e.slot] = face;
  }
  if (anyMerged) {
    // Every triangle of a merged vertex takes the face of the arcs that end there; none
    // (~0u) where x has no arc there.
    for (std::uint32_t k = inc.vertexBegin[x]; k < inc.vertexBegin[x + 1]; ++k) {
      const std::uint32_t v = inc.vertex[k];
      if (!ofMergedVertex(inc, v)) continue;
      const std::uint32_t first = v - inc.group[v];
      std::uint32_t face = ~0u;
      for (std::size_t m = 0; m < arcs; ++m) {
        const Arc& arc = s.arcs[m];
        if (arc.from == first || arc.to == first) {
          face = static_cast<std::uint32_t>(s.cycleFace[static_cast<std::size_t>(s.cycleOf[m])]);
          break;
        }
      }
      inc.vertexFace[k] = face;
    }
  }
  if (x == inc.extremeAtom) *inc.extremeFace = faceContaining(s, cycles, glm::dvec3(1.0, 0.0, 0.0));

}

// x's convex patch, if its region is not empty: the area from Gauss–Bonnet. Returns the
// number of convex patches (0 or 1).
std::uint32_t pushConvexPatch(const Atoms& a, const Incidence& inc, std::uint32_t x, const RegionSums& sums, int cycles,
                              ContourBuf& out) {
  std::uint32_t convexCount = 0;
  const glm::dvec3 cx = a.c[x];
  const double turning = sums.turning, maxCapArea = sums.maxCapArea;
  glm::dvec3 vectorArea = sums.vectorArea;
  double area = 0.0;
  const CapState caps = inc.capState[x];
  if (caps == CapState::None) {
    area = 4.0 * kPi;
    cycles = 0;
    vectorArea = glm::dvec3(0.0);
  } else if (caps == CapState::Covered || cycles == 0) {
    cycles = 0;
  } else {
    // Gauss–Bonnet fixes the area modulo 4π (2πχ ≡ −2π·cycles). The area is at most 4π
    // minus any cap, so a value above 4π minus half the largest bounding cap is a tiny
    // area that wrapped around.
    area = std::fmod(turning - kTwoPi * cycles, 2.0 * kTwoPi);
    if (area < 0.0) area += 2.0 * kTwoPi;
    if (area > 2.0 * kTwoPi - 0.5 * maxCapArea) area -= 2.0 * kTwoPi;
    area = std::max(area, 0.0);
  }
  if (cycles > 0 || area > 0.0) {
    out.convexCenter.push_back(cx);
    out.convexRadius.push_back(a.r[x]);
    out.convexAtom.push_back(x);
    out.convexArea.push_back(a.r[x] * a.r[x] * area);
    out.convexVectorArea.push_back(vectorArea);
    ++convexCount;
  }
  return convexCount;
}
}  // namespace

void contourPass(const Atoms& a, const Incidence& inc, std::uint32_t x, Scratch& s, ContourBuf& out) {
  const bool anyMerged = gatherEntries(a, inc, x, s);
  RegionSums sums;
  const std::uint32_t toriCount = traceArcs(a, inc, x, s, out, sums);
  const int cycles = linkCycles(s);
  assignFaces(inc, x, s, cycles, anyMerged, out);
  const std::uint32_t convexCount = pushConvexPatch(a, inc, x, sums, cycles, out);
  out.convexCount.push_back(convexCount);
  out.toriCount.push_back(toriCount);
}

}  // namespace surftrace::build::detail
