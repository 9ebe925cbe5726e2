// SES saddle (toroidal) patch: exact ray–torus intersection by quartic root isolation (ORACLES A.3, B).
// glm/common.hpp first: trace/ray.hpp calls glm::min/max without including it.
#include <glm/common.hpp>

#include "trace/torus_patch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>

#include "trace/polynomial.hpp"

namespace surftrace::trace {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
// Outward padding of the box in ulps of the coordinate's magnitude plus S: the corners come
// from a handful of products with cos/sin (each within 1 ulp), so 16 is conservative.
constexpr double kBoundsPadUlps = 16.0;
// The bounding sphere of the patch is |x − c| <= sqrt(R² + rp²) (below); it is widened by
// this relative amount so that contact-circle points on that sphere are never clipped by
// the rounding of the interval ends.
constexpr double kSpherePad = 1e-12;
// Likewise for the cylinder ρ <= R, whose chord ends carry √ε-level error for rays nearly
// tangent to it; patch points never come near it (|θ| < π/2 strictly), so the pad is free.
constexpr double kCylinderPad = 1e-9;
// The visibility sphere and φ-wedge clips (normalised units); as above, they only need to be
// conservative, and points this close to a θ or φ limit are flagged kHitNearBoundary anyway.
constexpr double kVisibilityPad = 1e-9;
constexpr double kWedgePad = 1e-9;
constexpr double kMinVisibilityCos = 1e-2;
// Newton polish on the own tube after root isolation (ORACLES B.4 step 2.2). Each step is
// kept only if it stays within kPolishRadius (normalised units) and reduces |D|: a trust
// region in place of a bracket, since the isolated root is already within ~1e-9 of the
// true one even for rays 1e-5 from tangency, where the quartic's slope F2·F1' vanishes.
constexpr int kPolishSteps = 2;
// occludes(): the quartic (normalised units, coefficients O(1) on |s| <= 1) proved to stay
// further than this from zero on [lo, hi] has no root there. Far above the rounding of its values (~1e-14) and the
// tangency tolerance (1e-14), so that realRoots' computed values there are positive too.
constexpr double kNoRootFloor = 1e-9;
constexpr int kNoRootHalvings = 1;
constexpr double kPolishRadius = 1e-6;

// The patch in the frame of ORACLES B.1: centre at the origin, e1/e2/axis as x/y/z, lengths in
// units of S = R + rp.
struct Normalised {
  double R;  // R/S
  double r;  // rp/S
};

struct ClipResult {
  bool inside = false;
  bool nearBoundary = false;
};

// 2-D cross product a × b: positive when b is counter-clockwise from a.
double cross2(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

// The trimming limits as unit directions, widened by `slack` radians: in the meridian plane
// (ρ-towards-axis, a) the cone limits u_i = (cos θi, sin θi), u_j; in the equatorial plane
// the φ limits. Three sincos per intersect call, after which every clip test is a few cross
// products: no atan2 per root.
struct Limits {
  double thetaICos, thetaISin, thetaJCos, thetaJSin;
  double startCos, startSin, endCos, endSin;
  double phiWidth;  // Δφ + 2·slack
};

Limits makeLimits(const TorusPatch& p, double slack) {
  Limits l;
  l.thetaICos = std::cos(p.thetaI - slack);
  l.thetaISin = std::sin(p.thetaI - slack);
  l.thetaJCos = std::cos(p.thetaJ + slack);
  l.thetaJSin = std::sin(p.thetaJ + slack);
  l.startCos = slack == 0.0 ? 1.0 : std::cos(slack);
  l.startSin = slack == 0.0 ? 0.0 : -std::sin(slack);
  l.endCos = std::cos(p.phiExtent + slack);
  l.endSin = std::sin(p.phiExtent + slack);
  l.phiWidth = p.phiExtent + 2.0 * slack;
  return l;
}

// Whether p.derived was computed for p's current radii and angles (bitwise: NaN never matches).
bool derivedValid(const TorusPatch& p) {
  const double* k = p.derived.key;
  return k[0] == p.bigRadius && k[1] == p.probeRadius && k[2] == p.thetaI && k[3] == p.thetaJ && k[4] == p.phiExtent;
}

// makeLimits(p, 0.0), from p.derived when it is valid (it holds exactly those values).
Limits limitsOf(const TorusPatch& p, bool valid) {
  if (!valid) return makeLimits(p, 0.0);
  const TorusPatch::Derived& c = p.derived;
  return Limits{c.thetaICos, c.thetaISin, c.thetaJCos, c.thetaJSin, 1.0, 0.0, c.endCos, c.endSin, p.phiExtent + 2.0 * 0.0};
}

// Distance from w to the half-line from the origin along the unit u.
double toHalfLine(double ux, double uy, double wx, double wy) {
  return ux * wx + uy * wy >= 0.0 ? std::abs(cross2(ux, uy, wx, wy)) : std::hypot(wx, wy);
}

// The patch membership test of a point x on the torus, in normalised local coordinates with
// ρ = hypot(x.x, x.y) (ORACLES A.3, B.4 steps 2.3–2.5). Shared by intersect and insidePatch,
// through the same Limits, so that the intersector and its oracle agree exactly.
ClipResult clipLocal(const Normalised& n, const Limits& l, const glm::dvec3& x, double rho, double slack) {
  ClipResult out;
  // Spindle: keep the apple, |x|² = h² + 2ρR, not the lemon, |x|² = h² − 2ρR (A.3). The two
  // meet at the cusps, where the classification is ill-posed; accepting lemon points with
  // ρ < kCuspFraction·rp there keeps the cusp itself on the patch (it is flagged anyway).
  if (n.R < n.r) {
    const double h2 = (n.r - n.R) * (n.r + n.R);
    if (glm::dot(x, x) < h2 - 2.0 * n.R * n.r * (kCuspFraction + slack)) return out;
  }
  // Cone test: v = (R − ρ, a) = rp (cos θ, sin θ) must lie between u_i and u_j. θj − θi < π,
  // so the cone is convex and two cross products decide it exactly; they are also rp·sin of
  // the angle to each limit, the arc length to the edge for small angles.
  const double vx = n.R - rho, vy = x.z;
  const double fromI = cross2(l.thetaICos, l.thetaISin, vx, vy);
  const double toJ = cross2(vx, vy, l.thetaJCos, l.thetaJSin);
  if (fromI < 0.0 || toJ < 0.0) return out;
  double edge = std::min(fromI, toJ);
  // Azimuth test, φ ∈ [−slack, Δφ + slack] from e1 towards e2.
  if (l.phiWidth < kTwoPi) {
    const double fromStart = cross2(l.startCos, l.startSin, x.x, x.y);
    const double toEnd = cross2(x.x, x.y, l.endCos, l.endSin);
    // Up to π the wedge is convex (both cross products >= 0); beyond, it is the complement
    // of the convex wedge from the end to the start. The axis itself (ρ = 0) is inside.
    const bool inPhi = l.phiWidth <= std::numbers::pi ? fromStart >= 0.0 && toEnd >= 0.0
                                                      : !(fromStart < 0.0 && toEnd < 0.0);
    if (!inPhi) return out;
    edge = std::min(edge, std::min(toHalfLine(l.startCos, l.startSin, x.x, x.y),
                                   toHalfLine(l.endCos, l.endSin, x.x, x.y)));
  }
  out.inside = true;
  // Arc length to the nearest trimming edge, relative to S: the seam tolerance of ray.hpp.
  out.nearBoundary = edge < kBoundaryTolerance;
  return out;
}

glm::dvec3 toLocal(const TorusPatch& p, const glm::dvec3& v) {
  return {glm::dot(v, p.e1), glm::dot(v, p.e2), glm::dot(v, p.axis)};
}

glm::dvec3 toWorld(const TorusPatch& p, const glm::dvec3& v) { return v.x * p.e1 + v.y * p.e2 + v.z * p.axis; }

// Outward normal (P − x)/|P − x| in local coordinates, P = R·(x, y, 0)/ρ the probe centre of
// x's meridian (A.3). At ρ = 0 (a spindle cusp) the normals of the cone around the cusp
// average to ∓axis, which is what we return there.
glm::dvec3 localNormal(const glm::dvec3& x, double rho, double bigRadius) {
  if (!(rho > 0.0)) return {0.0, 0.0, x.z >= 0.0 ? -1.0 : 1.0};
  const double s = bigRadius / rho;
  const glm::dvec3 g{s * x.x - x.x, s * x.y - x.y, -x.z};
  const double len = glm::length(g);
  if (!(len > 0.0)) return {0.0, 0.0, 1.0};  // x on the probe circle: not a torus point
  return g / len;
}

// Signed distance to the own tube, D = |x − P| − r, and its derivative along the unit d.
// D is Lipschitz-1 and its slope is n·d, so Newton on D is as well conditioned as the
// geometry allows, unlike the quartic whose slope also carries the factor F2.
bool tubeDistance(const glm::dvec3& x, const glm::dvec3& d, const Normalised& n, double& D, double& slope) {
  const double rho = std::sqrt(x.x * x.x + x.y * x.y);
  if (!(rho > 0.0)) return false;
  const double s = (rho - n.R) / rho;
  const glm::dvec3 g{s * x.x, s * x.y, x.z};
  const double len = glm::length(g);
  if (!(len > 0.0)) return false;
  D = len - n.r;
  slope = glm::dot(g, d) / len;
  return true;
}

double polishOnTube(const glm::dvec3& o, const glm::dvec3& d, const Normalised& n, double s, double lo, double hi) {
  double D, slope;
  if (!tubeDistance(o + s * d, d, n, D, slope)) return s;
  for (int k = 0; k < kPolishSteps && D != 0.0 && slope != 0.0; ++k) {
    const double next = s - D / slope;
    if (!(next >= lo && next <= hi && std::abs(next - s) <= kPolishRadius)) break;
    double nextD, nextSlope;
    if (!tubeDistance(o + next * d, d, n, nextD, nextSlope) || !(std::abs(nextD) < std::abs(D))) break;
    s = next;
    D = nextD;
    slope = nextSlope;
  }
  return s;
}

// Narrow [lo, hi] to the part of o + s d inside a convex set; false if nothing is left.
bool narrow(double chordLo, double chordHi, double& lo, double& hi) {
  lo = std::max(lo, chordLo);
  hi = std::min(hi, chordHi);
  return lo <= hi;
}

// o + s d (|d| = 1) inside the infinite cylinder x² + y² <= radius2 about the local z axis.
// A ray parallel to the axis is inside everywhere or nowhere.
bool clipToCylinder(const glm::dvec3& o, const glm::dvec3& d, double radius2, double& lo, double& hi) {
  const double a = d.x * d.x + d.y * d.y;
  const double b = o.x * d.x + o.y * d.y;
  const double c = o.x * o.x + o.y * o.y - radius2;
  if (a == 0.0) return c <= 0.0;
  // b² − ac in the perpendicular-distance form (ORACLES B.5): a·radius2 − |o_xy × d_xy|².
  const double cross = o.x * d.y - o.y * d.x;
  const double disc = a * radius2 - cross * cross;
  if (!(disc >= 0.0)) return false;
  const double q = -(b + std::copysign(std::sqrt(disc), b));
  if (q == 0.0) return narrow(0.0, 0.0, lo, hi);  // through the axis and tangent: one point
  const double r1 = q / a, r2 = c / q;
  return narrow(std::min(r1, r2), std::max(r1, r2), lo, hi);
}

// o + s d inside the visibility sphere (Krone et al. 2009; ORACLES A.3), padded. It passes
// through both contact circles, and the tube arc θ ∈ [θi, θj] facing the axis lies inside
// it (two circles of the meridian plane meet in at most those two points); this holds for
// the arc's ρ < 0 part too, so also on a spindle torus. Its centre is where the bisecting
// direction u_m = (u_i + u_j)/|u_i + u_j| from the probe circle meets the axis: a_v =
// R tan θm, at distance R/cos θm from the probe circle, so with Δ = θj − θi,
// r_v² = (R/cos θm − r)² + 4 (R/cos θm) r sin²(Δ/4), free of cancellation, and
// sin²(Δ/4) = sin²(Δ/2) / (2 (1 + cos(Δ/2))) with sin(Δ/2) = |u_j − u_i|/2, cos(Δ/2) =
// |u_i + u_j|/2.
struct VisibilitySphere {
  bool clip = false;  // false near θm = ±π/2, where the sphere degenerates (see below)
  double height = 0.0, radius = 0.0;
};

VisibilitySphere makeVisibilitySphere(const Normalised& n, const Limits& l) {
  VisibilitySphere v;
  const double sumX = l.thetaICos + l.thetaJCos, sumY = l.thetaISin + l.thetaJSin;
  const double sum = std::sqrt(sumX * sumX + sumY * sumY);
  const double cosMid = sumX / sum;
  // Near θm = ±π/2 the sphere grows into a half-space and its formulas lose their digits;
  // skipping the clip there only costs time.
  if (!(cosMid > kMinVisibilityCos)) return v;
  const double tanMid = sumY / sumX;
  const double difX = l.thetaJCos - l.thetaICos, difY = l.thetaJSin - l.thetaISin;
  const double sinHalf2 = 0.25 * (difX * difX + difY * difY), cosHalf = 0.5 * sum;
  const double sinQuarter2 = sinHalf2 / (2.0 * (1.0 + cosHalf));
  const double toProbe = n.R / cosMid;
  v.clip = true;
  v.height = n.R * tanMid;
  v.radius = std::sqrt((toProbe - n.r) * (toProbe - n.r) + 4.0 * toProbe * n.r * sinQuarter2) + kVisibilityPad;
  return v;
}

bool clipToVisibilitySphere(const VisibilitySphere& v, const glm::dvec3& o, const glm::dvec3& d, double& lo,
                            double& hi) {
  if (!v.clip) return true;
  const glm::dvec3 oc{o.x, o.y, o.z - v.height};
  const double b = glm::dot(oc, d);
  const glm::dvec3 f = oc - b * d;
  const double disc = v.radius * v.radius - glm::dot(f, f);
  if (!(disc >= 0.0)) return false;
  const double root = std::sqrt(disc);
  return narrow(-b - root, -b + root, lo, hi);
}

// o + s d inside the wedge φ ∈ [0, Δφ] about the local z axis, padded, when Δφ <= π (then the
// wedge is the intersection of the half-planes y >= 0 and sin Δφ·x − cos Δφ·y >= 0;
// a point at azimuth φ gives ρ sin φ and ρ sin(Δφ − φ)). A wider wedge is not convex.
bool clipToWedge(const Limits& l, const glm::dvec3& o, const glm::dvec3& d, double& lo, double& hi) {
  if (!(l.phiWidth <= std::numbers::pi)) return true;
  auto halfPlane = [&](double nx, double ny) {
    // nx·x + ny·y >= −pad along the line.
    const double g0 = nx * o.x + ny * o.y + kWedgePad, g1 = nx * d.x + ny * d.y;
    if (g1 == 0.0) return g0 >= 0.0;
    const double s = -g0 / g1;
    return g1 > 0.0 ? narrow(s, hi, lo, hi) : narrow(lo, s, lo, hi);
  };
  return halfPlane(-l.startSin, l.startCos) && halfPlane(l.endSin, -l.endCos);
}

// A ring torus's saddle (R >= rp) lies in the slab between its contact circles' planes,
// a ∈ [rp sin θi, rp sin θj], and outside the cylinder ρ < R − rp·max cos θ: the two sets that
// the sphere, cylinder, visibility and wedge clips leave open above and below the saddle and
// in the hole of the ring. Whether o + s d (|d| = 1) for s in [lo, hi] meets both, padded by
// kShellPad: false only for a ray that can have no root on the patch, so the quartic is
// skipped and the interval [lo, hi] it would solve on is left as it is (every hit found is
// the one found without this test, bit for bit). Accepted roots lie on the tube to the
// quartic's rounding (polishOnTube), within kShellPad of both sets. On a spindle torus
// (R < rp) the lemon points a cusp keeps (clipLocal) are not on the tube, and for limits
// outside (−π/2, π/2) sin θ is not monotonic: there it always says yes.
constexpr double kShellPad = 1e-6;

bool mayMeetRingSaddle(const Normalised& n, const Limits& l, const glm::dvec3& o, const glm::dvec3& d, double lo,
                       double hi) {
  // Both limits within (−π/2, π/2), θi <= θj (as the builder makes them): sin θ increases there.
  if (n.R < n.r || !(l.thetaICos > 0.0 && l.thetaJCos > 0.0 && l.thetaISin <= l.thetaJSin)) return true;
  const double zLo = n.r * l.thetaISin - kShellPad, zHi = n.r * l.thetaJSin + kShellPad;
  if (d.z == 0.0) {
    if (!(o.z >= zLo && o.z <= zHi)) return false;
  } else {
    const double a = (zLo - o.z) / d.z, b = (zHi - o.z) / d.z;
    if (!narrow(std::min(a, b), std::max(a, b), lo, hi)) return false;
  }
  // cos θ peaks at θ = 0 when it lies in [θi, θj], else at the limit nearer to it.
  const double cosMax = l.thetaISin <= 0.0 && l.thetaJSin >= 0.0 ? 1.0 : std::max(l.thetaICos, l.thetaJCos);
  const double rhoMin = n.R - n.r * cosMax - kShellPad;
  if (!(rhoMin > 0.0)) return true;
  // The cylinder is convex: the segment lies inside it when both ends do.
  const glm::dvec3 a = o + lo * d, b = o + hi * d;
  const double inside2 = rhoMin * rhoMin;
  return !(a.x * a.x + a.y * a.y < inside2 && b.x * b.x + b.y * b.y < inside2);
}

// [min, max] of cos over [a, b] (b − a <= 2π): the endpoints, or ±1 where a multiple of π
// lies inside.
void cosRange(double a, double b, double& lo, double& hi) {
  const double ca = std::cos(a), cb = std::cos(b);
  lo = std::min(ca, cb);
  hi = std::max(ca, cb);
  for (int k = -1; k <= 2; ++k) {
    const double m = k * std::numbers::pi;
    if (m >= a && m <= b) {
      if (k % 2 == 0) {
        hi = 1.0;
      } else {
        lo = -1.0;
      }
    }
  }
}

}  // namespace

void prepare(TorusPatch& p) {
  TorusPatch::Derived& c = p.derived;
  const double S = p.bigRadius + p.probeRadius;
  c.invScale = 1.0 / S;
  c.normBigRadius = p.bigRadius * c.invScale;
  c.normProbeRadius = p.probeRadius * c.invScale;
  const Limits l = makeLimits(p, 0.0);
  c.thetaICos = l.thetaICos;
  c.thetaISin = l.thetaISin;
  c.thetaJCos = l.thetaJCos;
  c.thetaJSin = l.thetaJSin;
  c.endCos = l.endCos;
  c.endSin = l.endSin;
  const VisibilitySphere v = makeVisibilitySphere(Normalised{c.normBigRadius, c.normProbeRadius}, l);
  c.visibilityClip = v.clip;
  c.visibilityHeight = v.height;
  c.visibilityRadius = v.radius;
  c.key[0] = p.bigRadius;
  c.key[1] = p.probeRadius;
  c.key[2] = p.thetaI;
  c.key[3] = p.thetaJ;
  c.key[4] = p.phiExtent;
}

TorusPatch makeTorusPatch(const glm::dvec3& center, const glm::dvec3& axis, const glm::dvec3& e1, double bigRadius,
                          double probeRadius, double thetaI, double thetaJ, double phiExtent) {
  TorusPatch p;
  p.center = center;
  p.axis = axis;
  p.e1 = e1;
  p.e2 = glm::cross(axis, e1);  // ORACLES A.1: e1 × e2 = n, φ runs from e1 towards e2
  p.bigRadius = bigRadius;
  p.probeRadius = probeRadius;
  p.thetaI = thetaI;
  p.thetaJ = thetaJ;
  p.phiExtent = phiExtent;
  prepare(p);
  return p;
}

TorusPatch torusPatch(const build::Tori& tori, std::size_t index, double probeRadius) {
  TorusPatch p;
  p.center = tori.center[index];
  p.axis = tori.axis[index];
  p.e1 = tori.e1[index];
  p.e2 = glm::cross(p.axis, p.e1);  // ORACLES A.1: e1 × e2 = n, φ runs from e1 towards e2
  p.bigRadius = tori.bigRadius[index];
  p.probeRadius = probeRadius;
  p.thetaI = tori.thetaI[index];
  p.thetaJ = tori.thetaJ[index];
  p.phiExtent = tori.phiExtent[index];
  prepare(p);
  return p;
}

Bounds3d bounds(const TorusPatch& p) {
  const double R = p.bigRadius, r = p.probeRadius, S = R + r;
  // θ range of the patch: [θi, θj], and on a spindle torus only its part with |θ| >= θc
  // (ρ >= 0, A.3), which may be two intervals, each within (−π/2, π/2).
  double intervals[2][2];
  int count = 0;
  if (R >= r) {
    intervals[count][0] = p.thetaI;
    intervals[count++][1] = p.thetaJ;
  } else {
    const double thetaC = std::acos(R / r);
    if (p.thetaI <= -thetaC) {
      intervals[count][0] = p.thetaI;
      intervals[count++][1] = std::min(p.thetaJ, -thetaC);
    }
    if (p.thetaJ >= thetaC) {
      intervals[count][0] = std::max(p.thetaI, thetaC);
      intervals[count++][1] = p.thetaJ;
    }
  }
  // Meridian box: ρ = R − rp cos θ, a = rp sin θ (sin increasing, cos peaking at θ = 0).
  double rhoMin = std::numeric_limits<double>::infinity(), rhoMax = 0.0;
  double aMin = std::numeric_limits<double>::infinity(), aMax = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < count; ++k) {
    const double lo = intervals[k][0], hi = intervals[k][1];
    const double cosMax = lo <= 0.0 && hi >= 0.0 ? 1.0 : std::max(std::cos(lo), std::cos(hi));
    const double cosMin = std::min(std::cos(lo), std::cos(hi));
    rhoMin = std::min(rhoMin, std::max(0.0, R - r * cosMax));
    rhoMax = std::max(rhoMax, std::max(0.0, R - r * cosMin));
    aMin = std::min(aMin, r * std::sin(lo));
    aMax = std::max(aMax, r * std::sin(hi));
  }
  Bounds3d b;
  if (count == 0 || !(rhoMin <= rhoMax) || !(aMin <= aMax)) {
    // Empty patch (a spindle whose θ range misses the SES sheet): a finite point box.
    rhoMin = rhoMax = aMin = aMax = 0.0;
  }
  // Exact box of the annular sector {ρ e_ρ(φ) : ρ ∈ [ρmin, ρmax], φ ∈ [0, Δφ]} swept along
  // the axis over [amin, amax]. Per world axis k, e_ρ(φ)_k = A_k cos(φ − ψ_k).
  const bool fullRing = p.phiExtent >= kTwoPi;
  for (int k = 0; k < 3; ++k) {
    const double amp = std::hypot(p.e1[k], p.e2[k]);
    double cLo = -1.0, cHi = 1.0;
    if (!fullRing) {
      const double psi = std::atan2(p.e2[k], p.e1[k]);
      cosRange(-psi, p.phiExtent - psi, cLo, cHi);
    }
    const double radialHi = amp * (cHi >= 0.0 ? rhoMax : rhoMin) * cHi;
    const double radialLo = amp * (cLo <= 0.0 ? rhoMax : rhoMin) * cLo;
    const double n = p.axis[k];
    const double axialLo = std::min(aMin * n, aMax * n), axialHi = std::max(aMin * n, aMax * n);
    const double pad = kBoundsPadUlps * kEpsilon * (std::abs(p.center[k]) + S);
    b.lower[k] = p.center[k] + radialLo + axialLo - pad;
    b.upper[k] = p.center[k] + radialHi + axialHi + pad;
  }
  return b;
}

namespace {

// intersect()'s set-up: the ray in the frame of ORACLES B.1, the interval [lo, hi] of s that the
// convex sets holding the patch leave, and the quartic along it (B.2).
struct TorusRay {
  double S, dirLength, tShift;
  Normalised n;
  Limits limits;
  glm::dvec3 o, d;
  double lo, hi;
  double coefficients[5];
};

// False when the clips leave no interval: no root of the patch on the ray.
inline bool torusRay(const TorusPatch& p, const UnitRay& ray, double tMin, double tMax, TorusRay& r) {
  r.S = p.bigRadius + p.probeRadius;
  const double S = r.S;
  r.dirLength = ray.length;
  const double dirLength = r.dirLength;
  if (!(dirLength > 0.0) || !std::isfinite(dirLength) || !(S > 0.0)) return false;
  const glm::dvec3& u = ray.unit;
  const bool valid = derivedValid(p);
  const double invS = valid ? p.derived.invScale : 1.0 / S;
  r.n = valid ? Normalised{p.derived.normBigRadius, p.derived.normProbeRadius}
              : Normalised{p.bigRadius * invS, p.probeRadius * invS};
  const Normalised& n = r.n;

  // B.1 step 4: shift the origin to the ray's closest approach to the centre (world distance
  // tShift from org), so the quartic's roots are O(1) and a camera at 1e4 S costs nothing.
  const glm::dvec3 w = ray.org - p.center;
  r.tShift = -glm::dot(w, u);
  const double tShift = r.tShift;
  const glm::dvec3 shifted = (w + tShift * u) * invS;
  // B.1 step 3, with the patch's own bounding sphere: on the saddle ρ <= R (θ ∈ (−π/2, π/2)),
  // so |x|² = R² + rp² − 2R·rp·cos θ <= R² + rp², tighter than S² = (R + rp)² and trig-free.
  const double sphere2 = (n.R * n.R + n.r * n.r) * (1.0 + kSpherePad);
  const double o2 = glm::dot(shifted, shifted);
  if (!(o2 <= sphere2)) return false;
  const double half = std::sqrt(sphere2 - o2);
  // The caller's t ↦ normalised s: world distance t·|dir| = S·s + tShift.
  const double sphereLo = std::max(-half, (tMin * dirLength - tShift) * invS);
  const double sphereHi = std::min(half, (tMax * dirLength - tShift) * invS);
  if (!(sphereLo <= sphereHi)) return false;

  r.o = toLocal(p, shifted);
  r.d = glm::normalize(toLocal(p, u));
  const glm::dvec3 &o = r.o, &d = r.d;
  // The saddle also lies in the cylinder ρ <= R (cos θ >= 0): clip to its chord too. This
  // drops the outer half of the torus, so most rays leave the quartic with at most two roots
  // in the interval and its root isolation does half the work.
  r.lo = sphereLo;
  r.hi = sphereHi;
  if (!clipToCylinder(o, d, n.R * n.R * (1.0 + kCylinderPad), r.lo, r.hi)) return false;
  // Two more convex sets hold the patch: the visibility sphere through both contact circles
  // (θ limits) and, when Δφ <= π, the wedge of the φ limits. Clipping to them (padded) reuses
  // the limit directions of the clip test and leaves an empty interval for most rays that
  // pass the patch's box but miss the patch, which then never reach the quartic.
  r.limits = limitsOf(p, valid);
  const VisibilitySphere visibility =
      valid ? VisibilitySphere{p.derived.visibilityClip, p.derived.visibilityHeight, p.derived.visibilityRadius}
            : makeVisibilitySphere(n, r.limits);
  if (!clipToVisibilitySphere(visibility, o, d, r.lo, r.hi) || !clipToWedge(r.limits, o, d, r.lo, r.hi)) return false;
  if (!mayMeetRingSaddle(n, r.limits, o, d, r.lo, r.hi)) return false;
  // B.2: monic quartic (|x|² − R² − r²)² + 4R²(z² − r²) along o + s d.
  const double R2 = n.R * n.R;
  const double K = glm::dot(o, o) - R2 - n.r * n.r;
  const double f = glm::dot(o, d);
  r.coefficients[0] = K * K + 4.0 * R2 * (o.z * o.z - n.r * n.r);
  r.coefficients[1] = 4.0 * f * K + 8.0 * R2 * o.z * d.z;
  r.coefficients[2] = 2.0 * K + 4.0 * f * f + 4.0 * R2 * d.z * d.z;
  r.coefficients[3] = 4.0 * f;
  r.coefficients[4] = 1.0;
  return true;
}

// A root of the quartic that is a point of the patch: its local point, ρ, caller's t and clip.
struct TorusRoot {
  glm::dvec3 x;
  double rho, t;
  bool cusp;
  ClipResult clip;
};

// Whether the quartic's root s is on the saddle (not the lemon), in (tMin, tMax] and inside the
// patch's limits, after polishing it on the tube.
inline bool rootOnPatch(const TorusRay& r, double s, double tMin, double tMax, TorusRoot& h) {
  const Normalised& n = r.n;
  h.x = r.o + s * r.d;
  h.rho = std::sqrt(h.x.x * h.x.x + h.x.y * h.x.y);
  h.cusp = h.rho < kCuspFraction * n.r;
  if (!h.cusp) {
    // B.4 step 2.1: the quartic is F1·F2; a root nearer the lemon F2 = (ρ + R)² + z² − r²
    // (non-empty only on a spindle torus) is inside the probe on the far side, not SES.
    const double zr = (h.x.z - n.r) * (h.x.z + n.r);
    const double f1 = (h.rho - n.R) * (h.rho - n.R) + zr, f2 = (h.rho + n.R) * (h.rho + n.R) + zr;
    if (std::abs(f1) > std::abs(f2)) return false;
    s = polishOnTube(r.o, r.d, n, s, r.lo, r.hi);
    h.x = r.o + s * r.d;
    h.rho = std::sqrt(h.x.x * h.x.x + h.x.y * h.x.y);
  }
  h.t = (s * r.S + r.tShift) / r.dirLength;
  if (!(h.t > tMin && h.t <= tMax)) return false;
  h.clip = clipLocal(n, r.limits, h.x, h.rho, 0.0);
  return h.clip.inside;
}

}  // namespace

std::optional<PatchHit> intersect(const TorusPatch& p, const UnitRay& ray, double tMin, double tMax) {
  TorusRay r;
  if (!torusRay(p, ray, tMin, tMax, r)) return std::nullopt;
  // The roots in ascending order, stopping at the first on the patch: the quartic's monotone
  // pieces (and the critical points) beyond it are never solved. The roots handed over are
  // the values realRoots reports, so the hit is the same.
  TorusRoot h;
  if (!firstRoot(r.coefficients, r.lo, r.hi, [&](double s, bool) { return rootOnPatch(r, s, tMin, tMax, h); }))
    return std::nullopt;
  const glm::dvec3 normalLocal = localNormal(h.x, h.rho, r.n.R);
  PatchHit hit;
  hit.t = h.t;
  hit.normal = glm::normalize(toWorld(p, normalLocal));
  if (std::abs(glm::dot(normalLocal, r.d)) < kGrazingCosine) hit.flags |= kHitGrazing;
  if (h.cusp) hit.flags |= kHitCusp;
  if (h.clip.nearBoundary) hit.flags |= kHitNearBoundary;
  return hit;
}

// The any-hit form of intersect(): the same interval, quartic and per-root tests (so it says
// yes exactly when intersect() returns a hit), but it stops at the first root that passes
// them (firstRoot leaves the quartic's later monotone pieces unsolved) and makes no normal
// or flags.
bool occludes(const TorusPatch& p, const UnitRay& ray, double tMin, double tMax) {
  TorusRay r;
  if (!torusRay(p, ray, tMin, tMax, r)) return false;
  // Most rays that get this far neither enter nor leave the tube within [lo, hi] (on 1VIS's
  // soft lighting, 92 % of the quartics solved have no root there): a Taylor bound that keeps
  // |quartic| above kNoRootFloor proves it for many of them at a fraction of the cost of
  // isolating the critical points, and then realRoots would report no root either.
  if (provablyAwayFromZero(r.coefficients, r.lo, r.hi, kNoRootFloor, kNoRootHalvings)) return false;
  return firstRoot(r.coefficients, r.lo, r.hi, [&](double s, bool) {
    TorusRoot h;
    return rootOnPatch(r, s, tMin, tMax, h);
  });
}

glm::dvec3 normalAt(const TorusPatch& p, const glm::dvec3& x) {
  const glm::dvec3 local = toLocal(p, x - p.center);
  const double rho = std::sqrt(local.x * local.x + local.y * local.y);
  return glm::normalize(toWorld(p, localNormal(local, rho, p.bigRadius)));
}

bool insidePatch(const TorusPatch& p, const glm::dvec3& x, double slack) {
  const double S = p.bigRadius + p.probeRadius;
  if (!(S > 0.0)) return false;
  const double invS = 1.0 / S;
  const Normalised n{p.bigRadius * invS, p.probeRadius * invS};
  const glm::dvec3 local = toLocal(p, x - p.center) * invS;
  const double rho = std::sqrt(local.x * local.x + local.y * local.y);
  return clipLocal(n, slack == 0.0 ? limitsOf(p, derivedValid(p)) : makeLimits(p, slack), local, rho, slack).inside;
}

namespace {

// A circle about the axis is nearest at x's own azimuth: the distance is the one in the
// meridian half-plane (ρ, z), to the contact circle's point (R − rp cos θ, rp sin θ).
double contactCircleDistanceLocal(const TorusPatch& p, double theta, double rho, double z) {
  return std::hypot(rho - (p.bigRadius - p.probeRadius * std::cos(theta)), z - p.probeRadius * std::sin(theta));
}

}  // namespace

double contactCircleDistance(const TorusPatch& p, bool atomJ, const glm::dvec3& x) {
  const glm::dvec3 local = toLocal(p, x - p.center);
  return contactCircleDistanceLocal(p, atomJ ? p.thetaJ : p.thetaI, std::hypot(local.x, local.y), local.z);
}

double boundaryDistance(const TorusPatch& p, const glm::dvec3& x) {
  const glm::dvec3 local = toLocal(p, x - p.center);
  const double rho = std::hypot(local.x, local.y), R = p.bigRadius, rp = p.probeRadius;
  double d = std::min(contactCircleDistanceLocal(p, p.thetaI, rho, local.z), contactCircleDistanceLocal(p, p.thetaJ, rho, local.z));
  if (p.phiExtent < kTwoPi)
    for (const double phi : {0.0, p.phiExtent}) {
      // The tube circle of azimuth φ: centre R·e(φ), radius rp, in the plane of e(φ) and the axis.
      const double c = std::cos(phi), s = std::sin(phi);
      const double along = c * local.x + s * local.y, across = cross2(c, s, local.x, local.y);
      d = std::min(d, std::hypot(across, std::hypot(along - R, local.z) - rp));
    }
  if (R < rp) {
    const double h = std::sqrt((rp - R) * (rp + R));
    d = std::min(d, std::min(glm::length(local - glm::dvec3(0.0, 0.0, h)), glm::length(local + glm::dvec3(0.0, 0.0, h))));
  }
  return d;
}

std::uint32_t atomOf(const TorusPatch& t, const glm::uvec2& atoms, const glm::dvec3& x) {
  // The saddle meets atom i at θ_i and atom j at θ_j; the axial coordinate decides.
  const double a = glm::dot(x - t.center, t.axis);
  // The prepared sines are these very values (sin(θ − 0) = sin θ), without two sin calls per hit.
  const bool valid = derivedValid(t);
  const double aI = t.probeRadius * (valid ? t.derived.thetaISin : std::sin(t.thetaI));
  const double aJ = t.probeRadius * (valid ? t.derived.thetaJSin : std::sin(t.thetaJ));
  return a - aI <= aJ - a ? atoms.x : atoms.y;
}

}  // namespace surftrace::trace
