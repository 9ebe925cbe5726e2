// The GL ray caster: the patch list drawn by geometry shaders and fragment ray casting (Lindow et al. 2010, Sect. 5).
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "build/bonds.hpp"
#include "build/patch_list.hpp"
#include "build/sphere_blockers.hpp"
#include "gl/gl_context.hpp"
#include "gl/gpu_kinds.hpp"
#include "gl/shaders.hpp"
#include "view/frame_buffers.hpp"
#include "view/patch_kind.hpp"
#include "view/render_options.hpp"

namespace surftrace::gl {

// How the fragment shader intersects a saddle.
enum class TorusMethod {
  Quartic,        // all real roots of the quartic in float by root isolation, polished on the tube
  SphereTracing,  // the paper's sphere tracing, at most maxSteps steps per ray
};
TorusMethod parseTorusMethod(const std::string& name);  // "quartic" | "sphere-tracing"; throws std::invalid_argument
const char* torusMethodName(TorusMethod method);

// The rasterisation primitive of tori and concave triangles (spheres always get a square).
enum class Primitive {
  Cylinder,  // the paper's: the trapezoid of the patch's bounding cylinder (Sect. 5.2, Fig. 6)
  Box,       // the eye-facing faces of a tight bounding box
};
Primitive parsePrimitive(const std::string& name);  // "cylinder" | "box"; throws std::invalid_argument
const char* primitiveName(Primitive primitive);

// The defaults of GlOptions::mergeDistance and mergeRelative (measured: tests/gl/gl_peel_test.cpp).
inline constexpr double kDefaultMergeDistance = 1e-5;
inline constexpr double kDefaultMergeRelative = 2e-6;
// The most layers one transparent frame peels (trace::kMaxLayers, RenderOptions::maxLayers).
inline constexpr int kMaxPeelLayers = 1024;

// An opaque image drawn before the peels (e.g. a ball-and-stick model): textures of the
// frame's size, colour RGBA32F (alpha its coverage) and depth whose red channel is the ray
// distance t of view::Camera::ray (Å, +inf where it drew nothing), as the renderer's own
// (t, viewZ) target. Peeled layers at or behind its depth are dropped, and the layers are
// composited over its colour instead of the background.
struct OpaqueLayer {
  unsigned color = 0;  // GL texture names
  unsigned depth = 0;
};

// GL's soft shadows and ambient occlusion (--lighting soft and full): depth maps of the whole
// scene, orthographic along directions over the key light's disc (key) and over the sphere
// (ambient), drawn once per frame before it (gl_renderer.cpp, drawLightMaps) and read by the
// shading (fragment_common.glsl, lightVisibility). Their side covers the scene's bounding ball
// with texels `texel` Å wide (at most kMaxLightMapSize), so that a large molecule's shadows are
// as sharp as a small one's; the key light's maps with texels `keyTexel` wide (0: `texel`);
// `size` > 0 sets the side of every map instead.
struct LightMaps {
  int key = 0;
  int ambient = 0;
  double texel = 0.0;
  int size = 0;
  double keyTexel = 0.0;
};
inline constexpr int kMaxLightMapSize = 2048;
// The maps of a lighting preset: none for headlight and simple (the Lighting has no shadow or
// occlusion rays); soft and full: see gl_renderer.cpp.
LightMaps lightMapsFor(const view::Lighting& lighting);

struct GlOptions {
  TorusMethod torus = TorusMethod::Quartic;
  int maxSteps = 30;             // sphere tracing: steps per ray (Lindow et al. 2010: 30)
  double traceEpsilon = 1e-4;    // sphere tracing: stop distance to the tube, Å
  // Sphere tracing inside the probe tube: jump to the far side of the local probe ball
  // (true), or step by the distance as outside (false, the textbook march).
  bool probeBallJumps = true;
  // Rasterisation primitive of tori and concave triangles. The cylinder falls back to the
  // box where a cap reaches the eye plane (eye inside or beside the cylinder). The box is
  // the default: on 1VIS it shades fewer fragments (the cylinder around a torus axis
  // covers the whole ring, not the saddle's φ sector; a spherical triangle fills its
  // tight box better than its cylinder) and renders faster.
  Primitive primitive = Primitive::Box;
  // Count, per patch, the fragments shaded and the hits (GlRenderer::fragmentCounts);
  // statistics for tests and benchmarks, slower.
  bool countFragments = false;
  // Transparency: a hit is the next layer when it lies beyond the previous one by more than
  // mergeDistance + mergeRelative·t (Å). Embree merges seam duplicates within 1e-6 Å, which
  // float cannot resolve: a pixel's t (~100 Å from the eye) has an ulp of ~1e-5 Å and the
  // float intersectors agree on a seam point to ~1e-4 Å (ORACLES D.4's depth error); two
  // true crossings that close are a grazing ray, inside the silhouette band.
  double mergeDistance = kDefaultMergeDistance;
  double mergeRelative = kDefaultMergeRelative;
  // The light maps to draw instead of the lighting preset's (lightMapsFor), when given: tests
  // and benchmarks trade their number and size against time.
  std::optional<LightMaps> lightMaps;
};

// Holds the compiled programs, the uploaded patches and the render targets of one context.
// Use (and destroy) it on the context's thread while that context is current.
class GlRenderer {
 public:
  // Compiles and links one program per kind (gpu_kinds.hpp); throws std::runtime_error with the info log.
  explicit GlRenderer(const GlContext& context);
  ~GlRenderer();
  GlRenderer(const GlRenderer&) = delete;
  GlRenderer& operator=(const GlRenderer&) = delete;

  // Uploads the patch list in the compact GPU form (gpu_kinds.hpp), coordinates shifted by
  // −origin in double first (use the camera's look-at or the molecule centre), and the
  // ball-and-stick model when given (drawn first, opaque: a transparent draw peels the surface
  // in front of it). Once per frame. `blockers` (build::sphereBlockers of this list and all
  // atoms) clip the spheres of a transparent draw; without them the first transparent draw
  // computes them from the spheres alone (complete for vdW and SAS, not for the SES:
  // build/sphere_blockers.hpp).
  void upload(const build::PatchList& patches, const glm::dvec3& origin, const build::SphereBlockers* blockers = nullptr,
              const build::BallStickModel* model = nullptr);
  // Draws the uploaded patches as `options.camera` sees them and waits for the GPU.
  // Supports the centre sample only: samplesPerPixel > 1, --shadows and --ao are rejected with
  // std::invalid_argument (the Embree path renders those); the soft and full lighting presets'
  // shadows and occlusion come from light maps (LightMaps) instead of rays. With
  // options.opacity < 1 it peels up to options.maxLayers layers, the transparency of
  // trace::render, over `opaque` when given (peel()).
  void draw(const view::RenderOptions& options, std::span<const glm::vec3> atomColors, const GlOptions& gl = {},
            const OpaqueLayer* opaque = nullptr);
  // Reads the last frame back: the buffers of trace::render, rows top first; flags 0; after a
  // transparent draw, `layers` holds the layers composited per pixel.
  view::FrameBuffers readBack() const;
  // Peeling passes the last draw ran (1 for an opaque draw): its deepest pixel's layers + 1,
  // at most maxLayers.
  int peelPasses() const;

  // Per global patch id (view::PatchIdOrder): (fragments shaded, hits) of the
  // last draw with GlOptions::countFragments; empty otherwise.
  std::vector<glm::uvec2> fragmentCounts() const;

  // The program of a kind, for layout queries in the tests.
  unsigned program(view::PatchKind kind) const;

 private:
  void drawPatches();
  void peel(const view::RenderOptions& options, const GlOptions& gl, const OpaqueLayer* opaque);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// upload + draw + readBack: the GL counterpart of trace::render (same options, same
// buffers and meanings: rgba, depth = ray distance, viewZ, normal, kind, patchId, atomId).
// fb.seconds is the wall time of all three.
view::FrameBuffers renderGl(const GlContext& context, const build::PatchList& patches,
                             const view::RenderOptions& options, std::span<const glm::vec3> atomColors,
                             const GlOptions& gl = {}, const build::SphereBlockers* blockers = nullptr,
                             const build::BallStickModel* model = nullptr);
// The same with a renderer kept from frame to frame (its programs compiled once); each call
// uploads its own patches, blockers and model, so a frame does not depend on the one before.
view::FrameBuffers renderGl(GlRenderer& renderer, const build::PatchList& patches, const view::RenderOptions& options,
                             std::span<const glm::vec3> atomColors, const GlOptions& gl = {},
                             const build::SphereBlockers* blockers = nullptr,
                             const build::BallStickModel* model = nullptr);

// Frame times of `frames` frames after one warm-up frame, each waited for with glFinish.
struct GlTimings {
  int frames = 0;
  double medianFrameSeconds = 0.0;   // upload + draw
  double medianDrawSeconds = 0.0;    // draw only (patches uploaded once)
  double minDrawSeconds = 0.0;
  std::string renderer;              // GlContext::description()
  int peelPasses = 1;                // of the last frame (GlRenderer::peelPasses)
};
GlTimings benchmarkGl(const GlContext& context, const build::PatchList& patches, const view::RenderOptions& options,
                      std::span<const glm::vec3> atomColors, const GlOptions& gl, int frames,
                      const build::SphereBlockers* blockers = nullptr);

}  // namespace surftrace::gl
