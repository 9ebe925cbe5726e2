// Brute-force ray oracle (STYLE §4): march an implicit function along a ray in long
// double, bisect every sign change, and hand each root to the caller's clip test. Slow and
// obviously correct; what every intersector is tested against.
#pragma once

#include <cmath>
#include <optional>
#include <vector>

namespace surftrace::oracles {

// All sign changes of f on [tMin, tMax], sampled at `steps` equal intervals, each bisected
// to long-double resolution, in ascending order. Tangential (double) roots without a sign
// change are invisible to it: tests exclude grazing rays, as ORACLES B.4 says.
template <class F>
std::vector<long double> marchRoots(F f, long double tMin, long double tMax, int steps) {
  std::vector<long double> roots;
  long double t0 = tMin, f0 = f(t0);
  for (int s = 1; s <= steps; ++s) {
    const long double t1 = tMin + (tMax - tMin) * static_cast<long double>(s) / steps;
    const long double f1 = f(t1);
    if (f0 == 0.0L) {
      roots.push_back(t0);
    } else if ((f0 < 0.0L) != (f1 < 0.0L) && f1 != 0.0L) {
      long double a = t0, b = t1, fa = f0;
      for (int k = 0; k < 200 && b - a > 0.0L; ++k) {
        const long double m = 0.5L * (a + b);
        if (m <= a || m >= b) break;
        const long double fm = f(m);
        if ((fm < 0.0L) == (fa < 0.0L)) {
          a = m;
          fa = fm;
        } else {
          b = m;
        }
      }
      roots.push_back(0.5L * (a + b));
    }
    t0 = t1;
    f0 = f1;
  }
  return roots;
}

// The first root of f in [tMin, tMax] whose point passes `accept`, if any.
template <class F, class Accept>
std::optional<long double> firstAcceptedRoot(F f, Accept accept, long double tMin, long double tMax, int steps) {
  for (long double t : marchRoots(f, tMin, tMax, steps))
    if (accept(t)) return t;
  return std::nullopt;
}

}  // namespace surftrace::oracles
