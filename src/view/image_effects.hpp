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

// Which effects to apply and their parameters. Every effect reads the pixel-centre buffers
// (viewZ, normal, kind), so with samplesPerPixel > 1 it is decided by the centre sample and
// applied to the pixel's averaged colour: lines are not anti-aliased, and a pixel whose centre
// misses gets no effect even if other samples hit.
struct ImageEffects {
  // Silhouettes: a hit pixel p is on a silhouette when some pixel q with
  // max(|qx − px|, |qy − py|) <= lineWidth (inside the image) is a miss or lies farther by more
  // than silhouetteJump: viewZ(q) − viewZ(p) > silhouetteJump (Å). The line thus lies on the
  // nearer surface, lineWidth pixels wide.
  bool silhouettes = false;
  int lineWidth = 2;                   // px
  glm::vec3 lineColor{0.0f};
  double silhouetteJump = 2.0;         // Å of view depth
  // Crease lines: a hit pixel p whose normal turns by more than creaseAngle degrees towards some
  // hit q in the same window on the same surface (|viewZ(q) − viewZ(p)| <= silhouetteJump).
  // 0 = none. Drawn with the silhouettes' width and colour.
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

// The pieces, for tests and benchmarks. One byte per pixel, 1 where a line is drawn.
std::vector<unsigned char> silhouetteMask(const FrameBuffers& frame, int width, double jump);
std::vector<unsigned char> creaseMask(const FrameBuffers& frame, int width, double jump, double angleDegrees);
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
