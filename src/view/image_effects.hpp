// Image-space effects on a rendered frame (silhouette and crease lines, depth darkening, depth
// cueing): one pass over view::FrameBuffers that every engine's frame goes through alike.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "view/camera.hpp"
#include "view/frame_buffers.hpp"

namespace surftrace::view {

// Which effects to apply and their parameters. Depth darkening and depth cueing read the
// pixel-centre buffers (viewZ, normal, kind), so with samplesPerPixel > 1 they are decided by the
// centre sample and applied to the pixel's averaged colour. The lines are anti-aliased from the
// same buffers (silhouetteCoverage, creaseCoverage), so they need no extra samples and are the
// same for every engine.
struct ImageEffects {
  // Silhouettes: a band lineWidth wide on the nearer side of every depth jump (a hit pixel next
  // to a miss, or to a pixel deeper by more than silhouetteJump Å of view depth), measured from
  // the sub-pixel position of the jump (silhouetteCoverage) and drawn with its pixel coverage.
  bool silhouettes = false;
  // Line width as a fraction of the image height, so that a preview and a large figure of the
  // same view look alike (0.002: 1 px at 512 px, 4.3 px at 2160 px).
  double lineWidth = 0.002;
  glm::vec3 lineColor{0.0f};  // sRGB, as given; drawn decoded (view/srgb.hpp)
  double silhouetteJump = 2.0;         // Å of view depth
  // Crease lines: where the normal turns by more than creaseAngle degrees within the line width
  // on one surface (|viewZ(q) − viewZ(p)| <= silhouetteJump), kept only in connected pieces at
  // least kCreaseMinLength line widths long (creaseCoverage). 0 = none. Drawn with the
  // silhouettes' width and colour.
  double creaseAngle = 0.0;
  // Depth darkening (Luft, Colditz, Deussen 2006, "Image enhancement by unsharp masking the depth
  // buffer"): ΔD = G∗D − D with D the view depth in Å and G a Gaussian of σ pixels, truncated at
  // 3σ and normalised over the pixels inside the image; where ΔD < 0 (the pixel lies behind its
  // surroundings) each colour channel gets λ·ΔD/R added. Sized in the image's terms, so that a
  // 512² preview and a 4K figure look alike and a small and a large molecule alike:
  // - σ = darkeningSigma × the image height (auto-framing fills the height with the scene, so
  //   the halo is the same share of any molecule), unless darkeningSigmaPx gives pixels;
  // - R, the scene's depth range (Å), is the camera's zFar − zNear (tight around the scene,
  //   fixed for a trajectory) unless darkeningRange gives it, else the frame's hits' range;
  // - the background (misses) lies at the camera's far plane, else at the farthest hit.
  // Neither R nor the background depends on the frame's hits when the camera has a depth range,
  // so the halo of a trajectory does not flicker; the background next to the molecule lies
  // behind it and gets the paper's soft halo.
  bool depthDarkening = false;
  double darkeningSigma = 0.015;                // σ as a fraction of the image height
  std::optional<double> darkeningSigmaPx;       // σ in pixels, in place of darkeningSigma
  double darkeningStrength = 1.0;               // λ, colour removed per R of ΔD
  std::optional<double> darkeningRange;         // R in Å, in place of the scene's depth range
  // σ in pixels for an image `imageHeight` pixels high.
  double darkeningSigmaPixels(int imageHeight) const;
  // Depth cueing, the depth-dependent lighting of molecular viewers (linear fog, as OpenGL's
  // GL_LINEAR): a hit's colour moves towards the background by
  // f = depthCueStrength · clamp((viewZ − start) / (end − start), 0, 1); start and end default
  // to the camera's depth range (zNear, zFar: tight around the scene, fixed for a trajectory).
  bool depthCue = false;
  double depthCueStrength = 0.6;
  std::optional<double> depthCueStart, depthCueEnd;  // Å of view depth

  bool lines() const { return silhouettes || creaseAngle > 0.0; }
  bool any() const { return lines() || depthDarkening || depthCue; }
  // The settings as JSON (for the image's metadata), with the depth-darkening σ in pixels and
  // the depths and range, and the depth-cue range, that `camera` gives.
  std::string json(const Camera& camera) const;
  // std::invalid_argument naming the bad field.
  void validate() const;
};

// Applies the effects in a fixed order: depth darkening, depth cueing, then the lines on top.
// `background` is the colour depth cueing fades to. Leaves `frame` untouched when none is on.
void applyImageEffects(FrameBuffers& frame, const ImageEffects& effects, const Camera& camera,
                       const glm::vec3& background);

// The lines' pieces, for tests and benchmarks: per pixel, the share of the pixel a line covers,
// in [0, 1]. `widthPx` is the line width in pixels (ImageEffects::lineWidth × height).
//
// Silhouettes: an edge pixel is a hit pixel with an 8-neighbour that is a miss or deeper by more
// than `jump`, unless the tangent plane of one of the two hits passes within `jump` of the other
// (one surface turning away near its rim, not a jump). Where the near surface turns away from the eye (the rim of a smooth surface:
// g = |n × d| → 1, with d the pixel's ray), the jump's sub-pixel position is where g, extrapolated
// linearly from the edge pixel and its inner neighbour, reaches 1, across the image direction
// of the normal; g is linear in the image position on a sphere's rim, so this is exact there.
// Elsewhere the jump lies half way to the neighbours beyond it. The line is the band of width
// `widthPx` inside the jump; each pixel gets the overlap of its 1-px extent across the jump with
// the band, so the line moves with the geometry by fractions of a pixel.
std::vector<float> silhouetteCoverage(const FrameBuffers& frame, const Camera& camera, double widthPx, double jump);
// Creases: the largest turn of the normal to a pixel q within the square window of radius
// creaseWindowRadius(widthPx) on the same surface (|Δ viewZ| <= jump). With hysteresis (Canny 1986):
// pixels turning by more than angleDegrees seed, pixels turning by more than
// kCreaseWeakRatio × angleDegrees extend them, and a connected piece shorter than
// `minLengthPx` (its bounding box's diagonal) is dropped, so that curved but smooth places do
// not leave specks. A kept pixel's coverage ramps from 0 at the weak to 1 at the strong angle.
inline constexpr double kCreaseWeakRatio = 0.75;
inline constexpr double kCreaseMinLength = 8.0;  // line widths (at least 1 px each)
std::vector<float> creaseCoverage(const FrameBuffers& frame, double widthPx, double jump, double angleDegrees,
                                  double minLengthPx);
// max(1, round(widthPx / 2)): a crease between two pixels marks a band about widthPx wide.
int creaseWindowRadius(double widthPx);
// The line width in pixels and the shortest crease piece kept, in pixels, for a frame `height` high.
double lineWidthPixels(const ImageEffects& effects, int height);
double creaseMinLengthPixels(const ImageEffects& effects, int height);
// ΔD = G∗D − D per pixel, misses at `backgroundDepth`, as two 1-D passes.
std::vector<float> depthUnsharpMask(const FrameBuffers& frame, double sigma, double backgroundDepth);
// The scene's depth range (Å of view depth): the camera's zNear..zFar when it has one (the same
// for every frame of a trajectory), else the frame's nearest and farthest hits.
void sceneDepthRange(const Camera& camera, const FrameBuffers& frame, double& nearest, double& farthest);
// Depth darkening's background depth and the range R its ΔD is divided by (ImageEffects).
void darkeningDepths(const ImageEffects& effects, const Camera& camera, const FrameBuffers& frame,
                     double& backgroundDepth, double& range);
// The depth-cue range: the effect's own, else the camera's, else the frame's hits.
void depthCueRange(const ImageEffects& effects, const Camera& camera, const FrameBuffers& frame, double& start,
                   double& end);

}  // namespace surftrace::view
