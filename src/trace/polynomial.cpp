// Real-root isolation of polynomials of degree <= 4 in an interval (ORACLES B.4 (ii)).
#include "trace/polynomial.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace surftrace::trace {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
// Newton converges quadratically from inside a monotone bracket; bisection needs ~60 halvings
// to reach 4 ulp of a root of size ~1 from a bracket of size ~1. The cap only guards against
// pathological brackets (a root at 1e-200 in [−1, 1]); the bracket is still valid there.
constexpr int kMaxNewtonIterations = 100;
// Stop when the last step or the bracket is below this many ulps of the root (ORACLES B.4).
constexpr double kStopUlps = 4.0;

// The degree is a template parameter below so that Horner's loops unroll and the recursion
// on derivatives is resolved at compile time: this runs per ray and candidate patch.
template <int D>
double horner(const double* c, double t) {
  double p = c[D];
  for (int k = D - 1; k >= 0; --k) p = p * t + c[k];
  return p;
}

// p(t), p'(t) and Σ|c_k||t|^k, the scale of Horner's rounding error in p(t): |computed p −
// p| <= γ_2n·Σ|c_k||t|^k ≈ n·ε·Σ|c_k||t|^k (Higham, "Accuracy and Stability of Numerical
// Algorithms", §5.1).
template <int D>
void hornerWithDerivative(const double* c, double t, double& p, double& dp, double& magnitude) {
  const double at = std::abs(t);
  p = c[D];
  dp = 0.0;
  magnitude = std::abs(c[D]);
  for (int k = D - 1; k >= 0; --k) {
    dp = dp * t + p;
    p = p * t + c[k];
    magnitude = magnitude * at + std::abs(c[k]);
  }
}

double hornerAny(const double* c, int degree, double t) {
  double p = c[degree];
  for (int k = degree - 1; k >= 0; --k) p = p * t + c[k];
  return p;
}

// a·b − c·d with one rounding (Kahan's algorithm; pbrt-v4 DifferenceOfProducts): b² − 4ac
// loses every digit to cancellation exactly where the roots are close.
double differenceOfProducts(double a, double b, double c, double d) {
  const double cd = c * d;
  const double err = std::fma(-c, d, cd);
  const double dop = std::fma(a, b, -cd);
  return dop + err;
}

double ulpScale(double t) { return kEpsilon * std::max(std::abs(t), std::numeric_limits<double>::min()); }

// Fixed-capacity output shared by the recursion levels. It never stops the walk (done()).
struct RootSink {
  double* value;
  std::uint32_t* mask;
  int count = 0;

  void push(double t, bool tangent) {
    if (count >= kMaxPolynomialDegree) return;  // cannot happen for degree <= 4 (see below)
    if (tangent) *mask |= 1u << count;
    value[count++] = t;
  }
  static constexpr bool done() { return false; }
};

// firstRoot's output: each root goes to the visitor as it is found, and the walk over the
// monotone pieces stops once the visitor accepts one, so the pieces beyond it, and the
// critical points that would split them (PieceWalk), are never solved. Every root handed
// over is the very value realRoots would report at that place.
struct StoppingSink {
  const RootVisitor& visit;
  bool accepted = false;

  void push(double t, bool tangent) {
    if (!accepted) accepted = visit.accept(visit.context, t, tangent);
  }
  bool done() const { return accepted; }
};

// The single root of p in [a, b], where p is monotone and p(a), p(b) have opposite signs:
// Newton from the secant point, falling back to bisection whenever the Newton step leaves
// the bracket or does not at least halve the previous step (rtsafe, Numerical Recipes §9.4;
// STYLE §3.4: iterative solvers must bracket). It stops when the step is within 4 ulp, or
// when |p(t)| is below Horner's error bound: p is then zero as far as double can tell, and
// further steps only chase rounding noise (a one-sided Newton run never moves the far end
// of the bracket, so without this test the noise forces bisections of a wide bracket).
template <int D>
double newtonBisect(const double* c, double a, double b, double pa, double pb) {
  double t = a - pa * (b - a) / (pb - pa);
  if (!(t > a && t < b)) t = 0.5 * (a + b);
  double stepOld = b - a, step = stepOld;
  const bool aNegative = pa < 0.0;
  constexpr double noise = D * kEpsilon;
  for (int it = 0; it < kMaxNewtonIterations; ++it) {
    double p, dp, magnitude;
    hornerWithDerivative<D>(c, t, p, dp, magnitude);
    if (std::abs(p) <= noise * magnitude) return t;
    if ((p < 0.0) == aNegative) {
      a = t;
    } else {
      b = t;
    }
    double next = 0.0;
    bool newton = dp != 0.0 && std::abs(2.0 * p) <= std::abs(stepOld * dp);
    if (newton) {
      next = t - p / dp;
      newton = next > a && next < b;
    }
    if (!newton) next = 0.5 * (a + b);
    stepOld = step;
    step = next - t;
    t = next;
    if (std::abs(step) <= kStopUlps * ulpScale(t) || b - a <= kStopUlps * ulpScale(t)) return t;
  }
  return t;
}

template <class Sink>
void linearRoots(const double* c, double lo, double hi, Sink& sink) {
  const double t = -c[0] / c[1];
  if (t >= lo && t <= hi) sink.push(t, false);
}

template <class Sink>
void quadraticRoots(const double* c, double lo, double hi, double tau, Sink& sink) {
  const double a = c[2], b = c[1], c0 = c[0];
  const double disc = differenceOfProducts(b, b, 4.0 * a, c0);
  if (!(disc > 0.0)) {
    // No real roots, or a double one. The vertex value is p(t*) = −Δ/(4a): a vertex that
    // is zero within τ is a tangential root (ORACLES B.4, step 1).
    const double t = -b / (2.0 * a);
    if (disc == 0.0 || std::abs(disc / (4.0 * a)) <= tau) {
      if (t >= lo && t <= hi) sink.push(t, true);
    }
    return;
  }
  // q = −(b + sign(b)√Δ)/2 adds two numbers of one sign, so neither root is the difference
  // of nearly equal numbers (STYLE §3.3).
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  double r1 = q / a, r2 = c0 / q;
  if (r1 > r2) std::swap(r1, r2);
  if (r1 >= lo && r1 <= hi) sink.push(r1, false);
  if (sink.done()) return;
  if (r2 >= lo && r2 <= hi) sink.push(r2, false);
}

template <int D, class Sink>
void isolate(const double* c, double lo, double hi, double tau, Sink& sink);

// The walk over p's monotone pieces, fed with the split points in ascending order as the
// roots of p' are found (it is the sink of p''s own isolation), so that a sink that stops
// early (StoppingSink) also stops the isolation of the later critical points: a root
// accepted in the first piece needs only the first critical point. Each piece is solved, and
// each critical point tested for tangency, with the same values in the same order as when
// every critical point is found first: the critical points are the same values (the same
// brackets of p''s own walk), and a piece's root needs only its two ends, a critical
// point's tangency test only it and its two neighbours.
template <int D, class Sink>
struct PieceWalk {
  const double* c;
  double hi, tau;
  Sink& sink;
  // The last two split points and p's values there ([1] the latest); count so far.
  double split[2], value[2];
  int count = 0;

  PieceWalk(const double* c_, double lo, double hi_, double tau_, Sink& sink_) : c(c_), hi(hi_), tau(tau_), sink(sink_) {
    split[1] = lo;
    value[1] = horner<D>(c, lo);
    count = 1;
    if (value[1] == 0.0) sink.push(lo, false);
  }

  // A root of p' (ascending); those outside (last split point, hi) split nothing.
  void push(double t, bool) {
    if (t > split[1] && t < hi) next(t, horner<D>(c, t));
  }
  bool done() const { return sink.done(); }

  // The next split point: the tangency test at the latest one (now that its right neighbour
  // is known), then the piece between them.
  void next(double t, double v) {
    if (sink.done()) return;
    if (count >= 2) {
      const double pl = value[0], p1 = value[1], pr = v;
      if (p1 == 0.0) {
        sink.push(split[1], true);  // an exact zero at a critical point: a multiple root
      } else {
        // Tangency (ORACLES B.4 step 1): a local extremum towards zero that does not cross.
        // Requiring |p| smaller than at both neighbours leaves out inflection points (p' has
        // a double root there, p is monotone through it and nothing touches zero).
        const bool noCrossing = pl != 0.0 && pr != 0.0 && (pl < 0.0) == (p1 < 0.0) && (pr < 0.0) == (p1 < 0.0);
        if (noCrossing && std::abs(p1) <= std::abs(pl) && std::abs(p1) <= std::abs(pr) && std::abs(p1) <= tau)
          sink.push(split[1], true);
      }
      if (sink.done()) return;
    }
    const double p0 = value[1];
    if (p0 != 0.0 && v != 0.0 && (p0 < 0.0) != (v < 0.0)) sink.push(newtonBisect<D>(c, split[1], t, p0, v), false);
    split[0] = split[1];
    value[0] = value[1];
    split[1] = t;
    value[1] = v;
    ++count;
  }

  // The last split point, hi.
  void finish() {
    next(hi, horner<D>(c, hi));
    if (!sink.done() && value[1] == 0.0) sink.push(hi, false);
  }
};

template <int D, class Sink>
void generalRoots(const double* c, double lo, double hi, double tau, Sink& sink) {
  // Critical points split [lo, hi] into pieces on which p is monotone. p' has the leading
  // coefficient D·c[D] != 0, so its degree is exactly D − 1. The pieces are walked left to
  // right so the output is sorted. At most D roots come out: each piece gives at most one, a
  // split point with p = 0 removes the strict sign change from both neighbours, and a
  // tangential root needs both neighbours rootless.
  double derivative[D];
  for (int k = 0; k < D; ++k) derivative[k] = static_cast<double>(k + 1) * c[k + 1];
  PieceWalk<D, Sink> walk(c, lo, hi, tau, sink);
  if (sink.done()) return;
  isolate<D - 1>(derivative, lo, hi, tau, walk);
  if (sink.done()) return;
  walk.finish();
}

template <int D, class Sink>
void isolate(const double* c, double lo, double hi, double tau, Sink& sink) {
  if constexpr (D == 1) {
    linearRoots(c, lo, hi, sink);
  } else if constexpr (D == 2) {
    quadraticRoots(c, lo, hi, tau, sink);
  } else {
    generalRoots<D>(c, lo, hi, tau, sink);
  }
}

}  // namespace

double evaluatePolynomial(std::span<const double> c, double t) {
  if (c.empty()) return 0.0;
  return hornerAny(c.data(), static_cast<int>(c.size()) - 1, t);
}

namespace {

// realRoots' walk into any sink: the same degree reduction, guards and isolation.
template <class Sink>
void findRoots(std::span<const double> c, double lo, double hi, double tangencyTolerance, Sink& sink) {
  if (c.empty() || c.size() > static_cast<std::size_t>(kMaxPolynomialDegree + 1)) return;
  if (!(lo <= hi) || !std::isfinite(lo) || !std::isfinite(hi)) return;
  int degree = static_cast<int>(c.size()) - 1;
  while (degree > 0 && c[static_cast<std::size_t>(degree)] == 0.0) --degree;
  if (degree == 0) return;  // a non-zero constant has no roots; nor, as reported, has zero
  if (lo == hi) {
    if (hornerAny(c.data(), degree, lo) == 0.0) sink.push(lo, false);
    return;
  }
  switch (degree) {
    case 1: isolate<1>(c.data(), lo, hi, tangencyTolerance, sink); break;
    case 2: isolate<2>(c.data(), lo, hi, tangencyTolerance, sink); break;
    case 3: isolate<3>(c.data(), lo, hi, tangencyTolerance, sink); break;
    default: isolate<4>(c.data(), lo, hi, tangencyTolerance, sink); break;
  }
}

}  // namespace

PolynomialRoots realRoots(std::span<const double> c, double lo, double hi, double tangencyTolerance) {
  PolynomialRoots out;
  RootSink sink{out.value.data(), &out.tangentMask};
  findRoots(c, lo, hi, tangencyTolerance, sink);
  out.count = sink.count;
  return out;
}

namespace {

// provablyAwayFromZero on [m − h, m + h], halving up to `halvings` more times. Each piece
// may have its own sign: the pieces' ends meet, so p keeps one sign over all of them.
bool pieceAwayFromZero(const double* c, int degree, double m, double h, double floor, int halvings) {
  // The Taylor coefficients at m (a Horner shift: b_k = p^(k)(m)/k!).
  double b[kMaxPolynomialDegree + 1];
  for (int k = 0; k <= degree; ++k) b[k] = c[k];
  for (int k = 0; k < degree; ++k)
    for (int j = degree - 1; j >= k; --j) b[j] += m * b[j + 1];
  double bound = std::abs(b[0]), hk = 1.0;
  for (int k = 1; k <= degree; ++k) {
    hk *= h;
    bound -= std::abs(b[k]) * hk;
  }
  if (bound > floor) return true;
  // Hopeless when |p(m)| itself is below the floor; else halve.
  if (halvings == 0 || !(std::abs(b[0]) > floor)) return false;
  const double half = 0.5 * h;
  return pieceAwayFromZero(c, degree, m - half, half, floor, halvings - 1) &&
         pieceAwayFromZero(c, degree, m + half, half, floor, halvings - 1);
}

}  // namespace

bool provablyAwayFromZero(std::span<const double> c, double lo, double hi, double floor, int maxHalvings) {
  if (c.empty() || c.size() > static_cast<std::size_t>(kMaxPolynomialDegree + 1)) return false;
  if (!(lo <= hi) || !std::isfinite(lo) || !std::isfinite(hi)) return false;
  // Widened a little, so that the pieces' rounded ends still cover [lo, hi].
  const double h = 0.5 * (hi - lo) * (1.0 + 1e-9) + 4.0 * kEpsilon * std::max(std::abs(lo), std::abs(hi));
  return pieceAwayFromZero(c.data(), static_cast<int>(c.size()) - 1, 0.5 * (lo + hi), h, floor, maxHalvings);
}

bool firstRoot(std::span<const double> c, double lo, double hi, const RootVisitor& visit, double tangencyTolerance) {
  StoppingSink sink{visit};
  findRoots(c, lo, hi, tangencyTolerance, sink);
  return sink.accepted;
}

}  // namespace surftrace::trace
