// The sRGB transfer function (IEC 61966-2-1:1999, section 5.2) both ways. Colours come in as
// sRGB (every table, colour map and colour a user gives, as published and as screens show them)
// and are decoded to linear once, where they enter; shading and compositing are linear; 8-bit
// images encode back (image_io.cpp). So a colour drawn unshaded comes out as the bytes it went in as.
#pragma once

#include <cmath>

#include <glm/vec3.hpp>

namespace surftrace::view {

// sRGB-encoded [0, 1] to linear: e/12.92 up to 0.04045, ((e + 0.055)/1.055)^2.4 above; the
// exact inverse of linearToSrgb.
inline double srgbToLinear(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}
inline glm::vec3 srgbToLinear(const glm::vec3& encoded) {
  return {static_cast<float>(srgbToLinear(static_cast<double>(encoded.r))),
          static_cast<float>(srgbToLinear(static_cast<double>(encoded.g))),
          static_cast<float>(srgbToLinear(static_cast<double>(encoded.b)))};
}

// Linear [0, 1] to sRGB-encoded: 12.92·v up to 0.0031308, 1.055·v^(1/2.4) − 0.055 above.
inline double linearToSrgb(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}
inline glm::vec3 linearToSrgb(const glm::vec3& linear) {
  return {static_cast<float>(linearToSrgb(static_cast<double>(linear.r))),
          static_cast<float>(linearToSrgb(static_cast<double>(linear.g))),
          static_cast<float>(linearToSrgb(static_cast<double>(linear.b)))};
}

}  // namespace surftrace::view
