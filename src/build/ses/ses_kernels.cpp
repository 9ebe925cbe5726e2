// SES cap pre-tests: the single-precision SIMD (SSE2/AVX2) kernels and the double-precision inside test.
#include "build/ses/ses_kernels.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#if defined(__x86_64__)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace surftrace::build::detail {
namespace {

// Cap-pair decisions on the unit sphere are taken, in single precision, only when
// |M² − Q²| exceeds this; the rounding error of either side is below 1e-6 (all terms are
// O(1)), so a clear decision is the exact one. Pairs within the margin (a circle within
// ~1e-5 of tangency to a sphere) take the exact path.
constexpr float kMargin = 2e-5f;

// Which neighbour caps may meet the boundary of cap `a` (circle (x, atom[a])): sets their
// bits in `cand`, and in `clear` those that clearly cross it. Returns false, early, if one
// clearly contains the whole circle.
//
// On the unit sphere, circle a is u = cos_a a + sin_a (cos φ e1 + sin φ e2), and
// u·b − cos_b = M cos(φ − ψ) − Q with M = sin_a |b − (a·b) a|, Q = cos_b − cos_a (a·b).
// The circle crosses cap b iff M > |Q|, lies inside it iff Q < −M, misses it iff Q > M;
// d = M² − Q² up to rounding (M² = sin²_a (1 − (a·b)²) for unit a, b).
bool classifyCircleSse(const Neighbourhood& nb, std::size_t a, Word* cand, Word* clear, std::size_t words) {
  const std::size_t n = nb.ux.size();  // a multiple of kPad
  const float ax = nb.ux[a], ay = nb.uy[a], az = nb.uz[a], ca = nb.cosr[a];
  const float sa2 = 1.0f - ca * ca;
#if defined(__SSE2__)
  const __m128 vax = _mm_set1_ps(ax), vay = _mm_set1_ps(ay), vaz = _mm_set1_ps(az), vca = _mm_set1_ps(ca);
  const __m128 vsa2 = _mm_set1_ps(sa2), one = _mm_set1_ps(1.0f), zero = _mm_setzero_ps();
  const __m128 lo = _mm_set1_ps(-kMargin), hi = _mm_set1_ps(kMargin);
#endif
  for (std::size_t w = 0; w < words; ++w) {
    Word candBits = 0, clearBits = 0;
    const std::size_t end = std::min(n, (w + 1) * kWordBits);
    for (std::size_t b = w * kWordBits; b < end; b += kLanes) {
      const auto shift = b % kWordBits;  // b is a multiple of kLanes: all bits land in word w
#if defined(__SSE2__)
      const __m128 ab = _mm_add_ps(_mm_add_ps(_mm_mul_ps(vax, _mm_loadu_ps(&nb.ux[b])), _mm_mul_ps(vay, _mm_loadu_ps(&nb.uy[b]))),
                                   _mm_mul_ps(vaz, _mm_loadu_ps(&nb.uz[b])));
      const __m128 q = _mm_sub_ps(_mm_loadu_ps(&nb.cosr[b]), _mm_mul_ps(vca, ab));
      const __m128 d = _mm_sub_ps(_mm_mul_ps(vsa2, _mm_sub_ps(one, _mm_mul_ps(ab, ab))), _mm_mul_ps(q, q));
      // b = a gives d ≈ 0: never a burial.
      if (_mm_movemask_ps(_mm_and_ps(_mm_cmplt_ps(d, lo), _mm_cmplt_ps(q, zero)))) return false;
      candBits |= static_cast<Word>(_mm_movemask_ps(_mm_cmpge_ps(d, lo))) << shift;
      clearBits |= static_cast<Word>(_mm_movemask_ps(_mm_cmpgt_ps(d, hi))) << shift;
#else
      for (std::size_t l = 0; l < kLanes; ++l) {
        const float ab = ax * nb.ux[b + l] + ay * nb.uy[b + l] + az * nb.uz[b + l];
        const float q = nb.cosr[b + l] - ca * ab;
        const float d = sa2 * (1.0f - ab * ab) - q * q;
        if (d < -kMargin && q < 0.0f) return false;
        candBits |= static_cast<Word>(d >= -kMargin) << (shift + l);
        clearBits |= static_cast<Word>(d > kMargin) << (shift + l);
      }
#endif
    }
    cand[w] = candBits;
    clear[w] = clearBits;
  }
  clearBit(cand, a);
  clearBit(clear, a);
  return true;
}

// Whether some cap contains w + n and some cap w − n by kVertexMargin (the loop of
// clearlyInsideBoth).
constexpr float kVertexMargin = 1e-4f;
bool bothInsideSse(const Neighbourhood& nb, float wx, float wy, float wz, float nx, float ny, float nz) {
  const std::size_t n = nb.ux.size();  // a multiple of kPad, padded with caps that contain nothing
#if defined(__SSE2__)
  const __m128 vwx = _mm_set1_ps(wx), vwy = _mm_set1_ps(wy), vwz = _mm_set1_ps(wz);
  const __m128 vnx = _mm_set1_ps(nx), vny = _mm_set1_ps(ny), vnz = _mm_set1_ps(nz);
  const __m128 margin = _mm_set1_ps(kVertexMargin);
  __m128 plusIn = _mm_setzero_ps(), minusIn = _mm_setzero_ps();
  for (std::size_t m = 0; m < n; m += kLanes) {
    const __m128 mx = _mm_loadu_ps(&nb.ux[m]), my = _mm_loadu_ps(&nb.uy[m]), mz = _mm_loadu_ps(&nb.uz[m]);
    const __m128 mw = _mm_sub_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(mx, vwx), _mm_mul_ps(my, vwy)), _mm_mul_ps(mz, vwz)),
                                 _mm_loadu_ps(&nb.cosr[m]));
    const __m128 mn = _mm_add_ps(_mm_add_ps(_mm_mul_ps(mx, vnx), _mm_mul_ps(my, vny)), _mm_mul_ps(mz, vnz));
    plusIn = _mm_or_ps(plusIn, _mm_cmpgt_ps(_mm_add_ps(mw, mn), margin));
    minusIn = _mm_or_ps(minusIn, _mm_cmpgt_ps(_mm_sub_ps(mw, mn), margin));
    if (_mm_movemask_ps(plusIn) && _mm_movemask_ps(minusIn)) return true;
  }
#else
  bool plusIn = false, minusIn = false;
  for (std::size_t m = 0; m < n; ++m) {
    const float mw = nb.ux[m] * wx + nb.uy[m] * wy + nb.uz[m] * wz - nb.cosr[m];
    const float mn = nb.ux[m] * nx + nb.uy[m] * ny + nb.uz[m] * nz;
    plusIn = plusIn || mw + mn > kVertexMargin;
    minusIn = minusIn || mw - mn > kVertexMargin;
    if (plusIn && minusIn) return true;
  }
#endif
  return false;
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// The same two kernels eight lanes at a time, for CPUs with AVX2 (picked at run time).
// Each lane does the same IEEE single-precision operations in the same order as in the
// SSE2 kernels (no fused multiply-add: the target enables AVX2 alone), so both give the
// same decisions, and the output does not depend on the CPU.
#define SURFTRACE_AVX2_KERNELS 1
__attribute__((target("avx2"))) bool classifyCircleAvx2(const Neighbourhood& nb, std::size_t a, Word* cand, Word* clear,
                                                        std::size_t words) {
  const std::size_t n = nb.ux.size();  // a multiple of kPad
  const float ca = nb.cosr[a];
  const __m256 vax = _mm256_set1_ps(nb.ux[a]), vay = _mm256_set1_ps(nb.uy[a]), vaz = _mm256_set1_ps(nb.uz[a]);
  const __m256 vca = _mm256_set1_ps(ca), vsa2 = _mm256_set1_ps(1.0f - ca * ca), one = _mm256_set1_ps(1.0f);
  const __m256 zero = _mm256_setzero_ps(), lo = _mm256_set1_ps(-kMargin), hi = _mm256_set1_ps(kMargin);
  for (std::size_t w = 0; w < words; ++w) {
    Word candBits = 0, clearBits = 0;
    const std::size_t end = std::min(n, (w + 1) * kWordBits);
    for (std::size_t b = w * kWordBits; b < end; b += kPad) {
      const auto shift = b % kWordBits;  // b is a multiple of kPad: all bits land in word w
      const __m256 ab = _mm256_add_ps(
          _mm256_add_ps(_mm256_mul_ps(vax, _mm256_loadu_ps(&nb.ux[b])), _mm256_mul_ps(vay, _mm256_loadu_ps(&nb.uy[b]))),
          _mm256_mul_ps(vaz, _mm256_loadu_ps(&nb.uz[b])));
      const __m256 q = _mm256_sub_ps(_mm256_loadu_ps(&nb.cosr[b]), _mm256_mul_ps(vca, ab));
      const __m256 d = _mm256_sub_ps(_mm256_mul_ps(vsa2, _mm256_sub_ps(one, _mm256_mul_ps(ab, ab))), _mm256_mul_ps(q, q));
      if (_mm256_movemask_ps(_mm256_and_ps(_mm256_cmp_ps(d, lo, _CMP_LT_OQ), _mm256_cmp_ps(q, zero, _CMP_LT_OQ)))) return false;
      candBits |= static_cast<Word>(_mm256_movemask_ps(_mm256_cmp_ps(d, lo, _CMP_GE_OQ))) << shift;
      clearBits |= static_cast<Word>(_mm256_movemask_ps(_mm256_cmp_ps(d, hi, _CMP_GT_OQ))) << shift;
    }
    cand[w] = candBits;
    clear[w] = clearBits;
  }
  clearBit(cand, a);
  clearBit(clear, a);
  return true;
}

__attribute__((target("avx2"))) bool bothInsideAvx2(const Neighbourhood& nb, float wx, float wy, float wz, float nx, float ny,
                                                    float nz) {
  const std::size_t n = nb.ux.size();
  const __m256 vwx = _mm256_set1_ps(wx), vwy = _mm256_set1_ps(wy), vwz = _mm256_set1_ps(wz);
  const __m256 vnx = _mm256_set1_ps(nx), vny = _mm256_set1_ps(ny), vnz = _mm256_set1_ps(nz);
  const __m256 margin = _mm256_set1_ps(kVertexMargin);
  __m256 plusIn = _mm256_setzero_ps(), minusIn = _mm256_setzero_ps();
  for (std::size_t m = 0; m < n; m += kPad) {
    const __m256 mx = _mm256_loadu_ps(&nb.ux[m]), my = _mm256_loadu_ps(&nb.uy[m]), mz = _mm256_loadu_ps(&nb.uz[m]);
    const __m256 mw = _mm256_sub_ps(
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(mx, vwx), _mm256_mul_ps(my, vwy)), _mm256_mul_ps(mz, vwz)),
        _mm256_loadu_ps(&nb.cosr[m]));
    const __m256 mn = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(mx, vnx), _mm256_mul_ps(my, vny)), _mm256_mul_ps(mz, vnz));
    plusIn = _mm256_or_ps(plusIn, _mm256_cmp_ps(_mm256_add_ps(mw, mn), margin, _CMP_GT_OQ));
    minusIn = _mm256_or_ps(minusIn, _mm256_cmp_ps(_mm256_sub_ps(mw, mn), margin, _CMP_GT_OQ));
    if (_mm256_movemask_ps(plusIn) && _mm256_movemask_ps(minusIn)) return true;
  }
  return false;
}

bool hasAvx2() {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
}
#endif

}  // namespace

// Which neighbour caps may meet circle a, and whether one clearly buries it (above).
bool classifyCircle(const Neighbourhood& nb, std::size_t a, Word* cand, Word* clear, std::size_t words) {
#if defined(SURFTRACE_AVX2_KERNELS)
  if (hasAvx2()) return classifyCircleAvx2(nb, a, cand, clear, words);
#endif
  return classifyCircleSse(nb, a, cand, clear, words);
}

// Whether both vertices of circles a and b (caps on x's unit sphere, a·u = cos_a,
// b·u = cos_b, |u| = 1) lie inside some neighbour cap by a margin that single precision
// cannot get wrong; then the exact test agrees (|p − c_m| < R_m iff u·m > cos_m for
// p = c_x + R_x u). Any cap may be tried: one that clearly contains a vertex of circles a
// and b is a candidate of both, and a and b themselves pass through the vertices, so they
// never clearly contain them. Unsure (near-tangent circles, a vertex near a rim) is false.
bool clearlyInsideBoth(const Neighbourhood& nb, std::size_t a, std::size_t b) {
  const float ax = nb.ux[a], ay = nb.uy[a], az = nb.uz[a], ca = nb.cosr[a];
  const float bx = nb.ux[b], by = nb.uy[b], bz = nb.uz[b], cb = nb.cosr[b];
  const float g = ax * bx + ay * by + az * bz;
  const float den = 1.0f - g * g;
  if (!(den > 1e-3f)) return false;
  const float inv = 1.0f / den;
  const float alpha = (ca - cb * g) * inv, beta = (cb - ca * g) * inv;
  const float t2 = 1.0f - (alpha * ca + beta * cb);
  if (!(t2 > 1e-3f)) return false;
  const float gamma = std::sqrt(t2 * inv);
  // Vertices w ± n.
  const float wx = alpha * ax + beta * bx, wy = alpha * ay + beta * by, wz = alpha * az + beta * bz;
  const float nx = (ay * bz - az * by) * gamma, ny = (az * bx - ax * bz) * gamma, nz = (ax * by - ay * bx) * gamma;
#if defined(SURFTRACE_AVX2_KERNELS)
  if (hasAvx2()) return bothInsideAvx2(nb, wx, wy, wz, nx, ny, nz);
#endif
  return bothInsideSse(nb, wx, wy, wz, nx, ny, nz);
}


// Which of p (bit 0) and q (bit 1) lie inside a sphere of (m1 & m2) other than skip1, skip2
// beyond the tie tolerance, |p − c|² < lo = R²(1 − kTie) (computed as glm::dot(p − c, p − c));
// bits 2 and 3: which lie within the tolerance of such a sphere's surface or inside it,
// |p − c|² < hi = R²(1 + kTie). The comparisons are of the exact probe positions: a double
// |p − c|² within `slack` of lo or hi is decided by exactProbeSide. Bits 4 and 5: which lie
// closer than R²(1 + nearBand) (in double; only a hint). Stops once both are inside.
int insideMask(const Neighbourhood& nb, const Word* m1, const Word* m2, std::size_t words, std::size_t skip1,
               std::size_t skip2, const ProbeTriple& triple, const glm::dvec3& p, const glm::dvec3& q, double slack,
               double nearBand) {
  int inside = 0, near = 0;
#if defined(__SSE2__)
  const __m128d px = _mm_set_pd(q.x, p.x), py = _mm_set_pd(q.y, p.y), pz = _mm_set_pd(q.z, p.z);
  const __m128d vslack = _mm_set1_pd(slack);
#endif
  for (std::size_t w = 0; w < words; ++w) {
    Word bits = m1[w] & m2[w];
    while (bits) {
      const std::size_t b = w * kWordBits + static_cast<std::size_t>(std::countr_zero(bits));
      bits &= bits - 1;
      if (b == skip1 || b == skip2) continue;
      const glm::dvec4& c = nb.sphere[b];
      const double lo = c.w * (1.0 - kTie), hi = c.w * (1.0 + kTie), nearHi = c.w * (1.0 + nearBand);
      int sureLo, maybeLo, sureHi, maybeHi;  // bit 0 for p, bit 1 for q
#if defined(__SSE2__)
      const __m128d dx = _mm_sub_pd(px, _mm_set1_pd(c.x));
      const __m128d dy = _mm_sub_pd(py, _mm_set1_pd(c.y));
      const __m128d dz = _mm_sub_pd(pz, _mm_set1_pd(c.z));
      const __m128d d2 = _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz));
      const __m128d vlo = _mm_set1_pd(lo), vhi = _mm_set1_pd(hi);
      sureLo = _mm_movemask_pd(_mm_cmplt_pd(d2, _mm_sub_pd(vlo, vslack)));
      maybeLo = _mm_movemask_pd(_mm_cmplt_pd(d2, _mm_add_pd(vlo, vslack)));
      sureHi = _mm_movemask_pd(_mm_cmplt_pd(d2, _mm_sub_pd(vhi, vslack)));
      maybeHi = _mm_movemask_pd(_mm_cmplt_pd(d2, _mm_add_pd(vhi, vslack)));
      near |= _mm_movemask_pd(_mm_cmplt_pd(d2, _mm_set1_pd(nearHi)));
#else
      const glm::dvec3 c3(c);
      const glm::dvec3 u = p - c3, v = q - c3;
      const double du = glm::dot(u, u), dv = glm::dot(v, v);
      sureLo = (du < lo - slack ? 1 : 0) | (dv < lo - slack ? 2 : 0);
      maybeLo = (du < lo + slack ? 1 : 0) | (dv < lo + slack ? 2 : 0);
      sureHi = (du < hi - slack ? 1 : 0) | (dv < hi - slack ? 2 : 0);
      maybeHi = (du < hi + slack ? 1 : 0) | (dv < hi + slack ? 2 : 0);
      near |= (du < nearHi ? 1 : 0) | (dv < nearHi ? 2 : 0);
#endif
      // Within the error bound of a threshold: the exact sign (rare: a probe position within
      // ~1e-12 Å of R(1 ± 1e-10)).
      for (int l = 0; l < 2; ++l) {
        const bool plus = l == 0;
        if ((maybeLo & ~sureLo) >> l & 1)
          sureLo |= exactProbeSide(triple, plus, glm::dvec3(c), lo) < 0 ? 1 << l : 0;
        if ((maybeHi & ~sureHi) >> l & 1)
          sureHi |= exactProbeSide(triple, plus, glm::dvec3(c), hi) < 0 ? 1 << l : 0;
      }
      inside |= sureLo | (sureHi << 2);
      if ((inside & 3) == 3) return inside | near << 4;
    }
  }
  return inside | near << 4;
}

}  // namespace surftrace::build::detail
