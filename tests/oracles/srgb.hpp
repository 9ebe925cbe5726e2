// The test oracle for 8-bit images: the standard sRGB transfer function (IEC 61966-2-1:1999,
// section 5.2) written out from the standard, apart from SurfTrace's own encoder.
#pragma once

#include <algorithm>
#include <cmath>

namespace surftrace::test {

// Linear [0, 1] to sRGB-encoded [0, 1].
inline double srgbFromLinear(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

// sRGB-encoded [0, 1] to linear (the standard's decoding): what the renderer shades a colour
// given or tabled in sRGB as.
inline double linearFromSrgb(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

// The 8-bit code of a linear colour value: clamped to [0, 1], encoded, scaled and rounded.
inline int srgbCode(double linear) {
  return static_cast<int>(std::lround(255.0 * srgbFromLinear(std::clamp(linear, 0.0, 1.0))));
}

}  // namespace surftrace::test
