// Another renderer's depth and normal buffers, in the conventions GL programs use, turned into
// FrameBuffers along the reference camera's rays so that compareFrames measures them in Å.
#pragma once

#include <string>

#include "view/camera.hpp"
#include "view/frame_buffers.hpp"
#include "view/image_compare.hpp"
#include "view/image_io.hpp"

namespace surftrace::view {

// How a depth buffer measures distance (README "Validating your renderer"). Background is
// whatever no surface can have: 1.0 in window depth; +inf or <= 0 otherwise. NaN is never
// background: it is carried into the frame, where compare counts it as a mismatch.
enum class DepthConvention {
  Window,  // GL window depth in [0, 1] under glDepthRange(0, 1), for the camera's near and far
  ViewZ,   // distance from the eye's plane along the view direction (−z of the view frame), Å
  Ray,     // distance along the pixel's ray from its origin (the eye; orthographic: the eye's plane), Å
};
// Which image row the buffer's first row is (rows as the file stores them: ImageChannels).
enum class RowOrigin {
  BottomLeft,  // glReadPixels' order
  TopLeft,     // image files' (and SurfTrace's) order
};
enum class NormalSpace { View, World };  // view: x right, y up, z towards the eye (glm::lookAt's frame)
enum class NormalEncoding { Signed, Unorm };  // components in [−1, 1], or stored as (n + 1) / 2

const char* conventionName(DepthConvention c);  // "window", "view-z", "ray": the flags' spellings
const char* originName(RowOrigin o);            // "bottom-left", "top-left"
const char* spaceName(NormalSpace s);           // "view", "world"
const char* encodingName(NormalEncoding e);     // "signed", "unorm"
// The other way round, for a program that takes the names (the Python module's keywords): throw
// std::invalid_argument naming the value and the names known. "snorm" is "signed".
DepthConvention depthConventionNamed(const std::string& name);
RowOrigin rowOriginNamed(const std::string& name);
NormalSpace normalSpaceNamed(const std::string& name);
NormalEncoding normalEncodingNamed(const std::string& name);

// How to read another renderer's buffers.
struct ForeignBufferOptions {
  std::string depthChannel;  // empty: Z, depth or Y, else the only channel
  DepthConvention depthConvention = DepthConvention::Window;
  RowOrigin origin = RowOrigin::BottomLeft;
  NormalSpace normalSpace = NormalSpace::View;
  NormalEncoding normalEncoding = NormalEncoding::Signed;
  // The normals negated (no flag: compare tries it for its hints, e.g. inward normals).
  bool negateNormals = false;
};

// The ray distance a depth value means at a pixel of `camera`. Window depth is taken back to
// the view frame through the projection's z and w rows (for the glFrustum and glOrtho forms
// every camera has, view z alone fixes them), view z to the ray through the camera's own
// pixel-centre rays, so that the distance is along the very ray the reference traced.
class DepthToRay {
 public:
  // std::invalid_argument when window depth meets a camera without near and far.
  DepthToRay(const Camera& camera, DepthConvention convention);
  // Distance (Å, unit direction) along the ray through the centre of pixel (x, y), row 0 at
  // the top; +inf for background.
  double rayDistance(int x, int y, double value) const;
  // The view-frame depth (Å along −z) of a value that is not background.
  double viewZ(int x, int y, double value) const;
  bool background(double value) const;  // false for NaN

 private:
  Camera::Frame frame_;
  DepthConvention convention_;
  double p22_ = 0.0, p32_ = 0.0, p23_ = 0.0, p33_ = 0.0;  // projection rows z and w (column-major [c][r])
};

struct ForeignFrame {
  FrameBuffers frame;     // depth (Å along the reference's rays), viewZ and world-space normals
  TestChannels carried;   // normals when given; never patch kinds or ids
  std::string depthChannel;  // the channel the depth came from
};

// The frame the buffers describe, pixel for pixel in `camera`'s image (row 0 at the top).
// `normals` may be null. std::runtime_error naming the file when a channel is missing or a
// size differs from the camera's (what was found and what was expected), when view-z or ray
// depth sits in an integer channel, or when window depth meets a camera without near and far.
ForeignFrame foreignFrame(const ImageChannels& depth, const ImageChannels* normals, const ForeignBufferOptions& options,
                          const Camera& camera);

// The values of the depth channel that its convention cannot hold, for `camera` and a reference
// whose hits lie at view depths nearest..farthest (Å): window depth outside [0, 1]; view-z or
// ray depth nearer than the camera's near plane (and the reference's nearest hit) or farther
// than its far plane (ray: along the widest ray). Empty when every value fits (or, for view-z
// and ray, the camera has no depth range); else one sentence naming the file, the channel, how
// many pixels, their range and what the convention holds.
std::string impossibleDepths(const ImageChannels& depth, const ForeignBufferOptions& options, const Camera& camera,
                             double nearest, double farthest);

}  // namespace surftrace::view
