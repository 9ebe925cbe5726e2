// The skin's geometry for simplices too flat for double precision: orthocentres and facet
// directions in rational arithmetic (GMP's mpq_class) from the input doubles, rounded once.
#include "build/mss/skin_geometry.hpp"

#include <stdexcept>

#include <gmpxx.h>

#include "build/core/rational_vector.hpp"

namespace surftrace::build::mss {
namespace {

using exact::QVec, exact::q, exact::sub, exact::add, exact::scale, exact::dot, exact::cross, exact::toDouble;

}  // namespace

Orthocentre exactOrthocentre(const WeightedPoints& p, const Simplex& x) {
  const QVec z0 = q(p.z[x[0]]);
  const mpq_class w0(p.w[x[0]]);
  QVec e[3];
  mpq_class b[3];
  for (int k = 1; k < x.size; ++k) {
    e[k - 1] = sub(q(p.z[x[k]]), z0);
    b[k - 1] = (dot(e[k - 1], e[k - 1]) - mpq_class(p.w[x[k]]) + w0) / 2;
  }
  QVec y{0, 0, 0};
  if (x.size == 2) {
    if (dot(e[0], e[0]) == 0) throw std::invalid_argument("an edge of coincident atoms");
    y = scale(e[0], b[0] / dot(e[0], e[0]));
  } else if (x.size == 3) {
    const mpq_class g00 = dot(e[0], e[0]), g01 = dot(e[0], e[1]), g11 = dot(e[1], e[1]);
    const mpq_class det = g00 * g11 - g01 * g01;
    // The builder never makes a simplex of dependent points (power_cell: no vertex of
    // dependent normals, no edge of parallel planes); a damaged file may name one.
    if (det == 0) throw std::invalid_argument("a triangle of collinear atoms");
    y = add(scale(e[0], (b[0] * g11 - b[1] * g01) / det), scale(e[1], (g00 * b[1] - g01 * b[0]) / det));
  } else if (x.size == 4) {
    const QVec c12 = cross(e[1], e[2]), c20 = cross(e[2], e[0]), c01 = cross(e[0], e[1]);
    const mpq_class det = dot(e[0], c12);
    if (det == 0) throw std::invalid_argument("a tetrahedron of coplanar atoms");
    y = scale(add(add(scale(c12, b[0]), scale(c20, b[1])), scale(c01, b[2])), 1 / det);
  }
  return {toDouble(add(z0, y)), mpq_class(dot(y, y) - w0).get_d()};
}

glm::dvec3 exactFacetDirection(const WeightedPoints& p, const Simplex& x, std::uint32_t a) {
  const QVec z0 = q(p.z[x[0]]);
  QVec v = sub(q(p.z[a]), z0);
  if (x.size == 2) {
    const QVec e = sub(q(p.z[x[1]]), z0);
    if (dot(e, e) == 0) throw std::invalid_argument("an edge of coincident atoms");
    v = sub(v, scale(e, dot(v, e) / dot(e, e)));
  } else if (x.size == 3) {
    const QVec n = cross(sub(q(p.z[x[1]]), z0), sub(q(p.z[x[2]]), z0));
    if (dot(n, n) == 0) throw std::invalid_argument("a triangle of collinear atoms");
    v = scale(n, dot(v, n) / dot(n, n));
  }
  // Components of a sliver's normal part may be ~1e-22: far above double's range limits.
  return toDouble(v);
}

}  // namespace surftrace::build::mss
