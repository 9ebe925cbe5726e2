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
  // buffer"): ΔD = G∗D − D with D the view depth in Å (the background just behind the
  // farthest hit: the camera's far plane would lie a molecule's radius behind the rim and
  // turn the halo black) and G a Gaussian of darkeningSigma pixels, truncated at 3σ and
  // normalised over the pixels inside the image; where ΔD < 0 (the pixel lies behind its
  // surroundings) each colour channel gets λ·ΔD added. The background next to the molecule lies
  // behind it too: it gets the paper's dark halo.
  bool depthDarkening = false;
  double darkeningSigma = 8.0;         // px
  double darkeningStrength = 0.03;     // λ, colour per Å of ΔD
  // Depth cueing, the depth-dependent lighting of molecular viewers (linear fog, as OpenGL's
  // GL_LINEAR): a hit's colour moves towards the background by
  // f = depthCueStrength · clamp((viewZ − start) / (end − start), 0, 1); start and end default
  // to the camera's depth range (zNear, zFar: tight around the scene, fixed for a trajectory).
  bool depthCue = false;
  double depthCueStrength = 0.6;
  std::optional<double> depthCueStart, depthCueEnd;  // Å of view depth

  bool lines() const { return silhouettes || creaseAngle > 0.0; }
  bool any() const { return lines() || depthDarkening || depthCue; }
  // The settings as JSON (for the image's metadata), with the depth-cue range `camera` gives.
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
// The depth of the background for depth darkening: the farthest hit's.
double backgroundDepth(const FrameBuffers& frame);
// The depth-cue range: the effect's own, else the camera's, else the frame's hits.
void depthCueRange(const ImageEffects& effects, const Camera& camera, const FrameBuffers& frame, double& start,
                   double& end);

}  // namespace surftrace::view
