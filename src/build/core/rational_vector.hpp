// Vectors of exact rationals (GMP's mpq_class) for the predicates and constructions that
// double precision cannot decide: the SES's probe heights (ses/exact_predicates.cpp) and the
// skin's too-flat simplices (mss/skin_geometry.cpp). Every double converts exactly.
#pragma once

#include <gmpxx.h>

#include <glm/vec3.hpp>

namespace surftrace::build::exact {

struct QVec {
  mpq_class x, y, z;
};

inline QVec q(const glm::dvec3& v) { return {mpq_class(v.x), mpq_class(v.y), mpq_class(v.z)}; }
inline QVec sub(const QVec& u, const QVec& v) { return {u.x - v.x, u.y - v.y, u.z - v.z}; }
inline QVec add(const QVec& u, const QVec& v) { return {u.x + v.x, u.y + v.y, u.z + v.z}; }
inline QVec scale(const QVec& u, const mpq_class& s) { return {u.x * s, u.y * s, u.z * s}; }
inline mpq_class dot(const QVec& u, const QVec& v) { return u.x * v.x + u.y * v.y + u.z * v.z; }
inline QVec cross(const QVec& u, const QVec& v) {
  return {u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
}
// Each component rounded once to the nearest double.
inline glm::dvec3 toDouble(const QVec& v) { return {v.x.get_d(), v.y.get_d(), v.z.get_d()}; }

}  // namespace surftrace::build::exact
