// Tile-parallel rendering of a patch scene into colour and per-pixel buffers.
#include "trace/render.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>

#include <optional>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "trace/reference_masks.hpp"
#include "trace/visibility_filter.hpp"

namespace surftrace::trace {
namespace {

using view::Camera;
using view::ColorMode;
using view::FrameBuffers;
using view::RenderOptions;

constexpr int kTile = 16;    // pixels per tile side: 16 packets of 4×4 rays
constexpr int kPacket = 4;   // 4×4 = 16 rays, Embree's widest packet
constexpr double kPi = 3.14159265358979323846;
// The filtered visibilities' reach (filterVisibility) at 8 rays, a fraction of the occlusion
// distance: 0.4 Å by default. With more rays the reach shrinks (as 1/√rays, so the rays it
// averages stay as many) and with it the detail it smooths away.
constexpr double kFilterReach = 0.05;
// How many times the preset's rays a filtered render traces at the pixels where the filter
// finds few neighbours (silhouettes, creases, curved edges).
constexpr int kEdgeRays = 4;

// A small, fast, deterministic hash-based generator: AO samples depend only on the pixel
// and sample index, so images do not depend on the thread schedule.
struct PixelRng {
  std::uint64_t state;
  explicit PixelRng(std::uint64_t seed) : state(seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull) {}
  double next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }
};

using view::latticePoint;
using view::tangentFrame;

class Shader {
 public:
  Shader(const PatchScene& scene, const RenderOptions& o, std::span<const glm::vec3> atomColors)
      : scene_(scene), o_(o), atomColors_(atomColors), offset_(1e-6 * sceneScale(scene)) {
    const Camera& c = o.camera;
    keyLight_ = glm::normalize(-c.forward() + 0.5 * c.trueUp() - 0.5 * c.right());
    lights_ = view::lightDirections(c.right(), c.trueUp(), c.forward());
    tangentFrame(lights_.key, keyT_, keyB_);
    keyRays_ = o.lighting.shadowRays > 0 ? o.lighting.shadowRays : (o.shadows ? 1 : 0);
    occlusionRays_ = o.aoSamples > 0 ? o.aoSamples : o.lighting.occlusionRays;
  }

  // The key light's visibility S and the ambient visibility A at a hit, each NaN where it is
  // not traced (S where the key light is behind the surface or shadows are off, A without
  // occlusion rays): shading then takes 1.
  struct Visibility {
    float key = std::numeric_limits<float>::quiet_NaN(), open = std::numeric_limits<float>::quiet_NaN();
  };
  // `more` times the rays (a filtered render's edge pixels, which have few neighbours to share with).
  Visibility visibility(const Ray& ray, const SceneHit& h, std::uint64_t pixel, int more = 1) const {
    Visibility v;
    const glm::dvec3 start = ray.org + h.hit.t * ray.dir + offset_ * h.hit.normal;
    // The key light's visibility matters only where the key light shines (n·k > 0).
    if (keyRays_ > 0 && glm::dot(h.hit.normal, lights_.key) > 0.0)
      v.key = static_cast<float>(keyVisibility(start, h.hit.normal, pixel, more * keyRays_));
    if (occlusionRays_ > 0) v.open = static_cast<float>(openFraction(start, h.hit.normal, pixel, more * occlusionRays_));
    return v;
  }
  // Whether the key-fill model's S and A are traced with few rays into a VisibilityPlane,
  // filtered there, then shaded (Lighting::filterPasses).
  float filterReach() const {
    const int rays = std::max(keyRays_, occlusionRays_);
    return static_cast<float>(kFilterReach * o_.aoDistance * std::sqrt(8.0 / std::max(rays, 8)));
  }
  bool filters() const { return o_.lighting.keyFill() && o_.lighting.filterPasses > 0 && (keyRays_ > 0 || occlusionRays_ > 0); }

  // The colour of a hit; `given` the key-fill model's visibilities when they were traced (and
  // filtered) beforehand, else they are traced here (with `more` times the rays).
  glm::vec3 color(const Ray& ray, const SceneHit& h, std::uint32_t atom, std::uint64_t pixel,
                  const Visibility* given = nullptr, int more = 1) const {
    const glm::vec3 base = o_.color == ColorMode::Patch ? view::kindColor(h.kind)
                           : atom < atomColors_.size()  ? atomColors_[atom]
                                                        : glm::vec3(1.0f, 0.0f, 1.0f);
    const glm::dvec3 toEye = -glm::normalize(ray.dir);
    if (o_.lighting.keyFill()) {
      const Visibility v = given ? *given : visibility(ray, h, pixel, more);
      return view::shade(base, h.hit.normal, toEye, o_.lighting, lights_, std::isnan(v.key) ? 1.0f : v.key,
                         std::isnan(v.open) ? 1.0f : v.open);
    }
    const glm::dvec3 start = ray.org + h.hit.t * ray.dir + offset_ * h.hit.normal;
    glm::vec3 c = view::shade(base, h.hit.normal, toEye, o_.lighting);
    if (o_.shadows && scene_.occluded(Ray{start, keyLight_}, 0.0, std::numeric_limits<double>::infinity()))
      c *= 0.6f;
    if (o_.aoSamples > 0) c *= static_cast<float>(ambientVisibility(start, h.hit.normal, pixel));
    return c;
  }

 private:
  static double sceneScale(const PatchScene& scene) {
    const Bounds3d& b = scene.bounds();
    return b.empty() ? 1.0 : std::max(1.0, glm::length(b.upper - b.lower));
  }
  // The headlight model's ambient occlusion: 0.3 + 0.7 × the fraction of cosine-weighted
  // hemisphere rays (independent random per pixel) that escape within aoDistance.
  double ambientVisibility(const glm::dvec3& x, const glm::dvec3& n, std::uint64_t pixel) const {
    glm::dvec3 t, b;
    tangentFrame(n, t, b);
    PixelRng rng(pixel);
    int open = 0;
    for (int s = 0; s < o_.aoSamples; ++s) {
      const double u = rng.next(), v = rng.next();
      const double r = std::sqrt(u), phi = 2.0 * kPi * v;
      const glm::dvec3 d = r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1.0 - u)) * n;
      if (!scene_.occluded(Ray{x, d}, 0.0, o_.aoDistance)) ++open;
    }
    return 0.3 + 0.7 * static_cast<double>(open) / o_.aoSamples;
  }
  // The key-fill model's ambient visibility: the fraction of `rays` cosine-weighted hemisphere
  // rays that escape within aoDistance, their directions a rank-1 lattice (stratified in cos²θ)
  // rotated by a fixed amount per pixel (and sample, and layer): the same pattern every frame.
  double openFraction(const glm::dvec3& x, const glm::dvec3& n, std::uint64_t pixel, int rays) const {
    glm::dvec3 t, b;
    tangentFrame(n, t, b);
    PixelRng rng(pixel ^ 0xA0761D6478BD642Full);
    const glm::dvec2 rotation(rng.next(), rng.next());
    int open = 0;
    for (int s = 0; s < rays; ++s) {
      const glm::dvec2 q = latticePoint(s, rays, rotation);
      const double r = std::sqrt(q.x), phi = 2.0 * kPi * q.y;
      const glm::dvec3 d = r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1.0 - q.x)) * n;
      if (!scene_.occluded(Ray{x, d}, 0.0, o_.aoDistance)) ++open;
    }
    return static_cast<double>(open) / rays;
  }
  // The fraction of the key light that reaches x: one ray to its centre, or (soft shadows)
  // `rays` rays to a lattice on the disc of angular radius keyRadius, rotated per pixel as
  // above. A ray below the surface's tangent plane counts as blocked (by the surface itself).
  double keyVisibility(const glm::dvec3& x, const glm::dvec3& n, std::uint64_t pixel, int rays) const {
    const double inf = std::numeric_limits<double>::infinity();
    if (o_.lighting.shadowRays == 0) return scene_.occluded(Ray{x, lights_.key}, 0.0, inf) ? 0.0 : 1.0;
    PixelRng rng(pixel ^ 0xE7037ED1A0B428DBull);
    const glm::dvec2 rotation(rng.next(), rng.next());
    int open = 0;
    for (int s = 0; s < rays; ++s) {
      const glm::dvec3 d =
          view::keyDiscDirection(lights_.key, keyT_, keyB_, o_.lighting.keyRadius, latticePoint(s, rays, rotation));
      if (glm::dot(d, n) > 0.0 && !scene_.occluded(Ray{x, d}, 0.0, inf)) ++open;
    }
    return static_cast<double>(open) / rays;
  }

  const PatchScene& scene_;
  const RenderOptions& o_;
  std::span<const glm::vec3> atomColors_;
  double offset_;
  glm::dvec3 keyLight_;
  view::LightDirections lights_;
  glm::dvec3 keyT_, keyB_;
  int keyRays_ = 0, occlusionRays_ = 0;
};

// Runs packet(px, py) for the top-left pixel of every 4×4 packet, tile-parallel, with the
// progress callback (this run being the share `progress` of the frame, after `progressFrom`);
// makeState() gives each tile its scratch space (passed as packet's third argument).
template <class MakeState, class Packet>
void forEachPacket(const Camera& cam, const RenderOptions& o, MakeState makeState, Packet packet,
                   double progressFrom = 0.0, double progressShare = 1.0) {
  const int tilesX = (cam.width + kTile - 1) / kTile, tilesY = (cam.height + kTile - 1) / kTile;
  std::atomic<int> tilesDone{0};
  tbb::parallel_for(tbb::blocked_range2d<int>(0, tilesY, 1, 0, tilesX, 1), [&](const tbb::blocked_range2d<int>& r) {
    auto state = makeState();
    for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty)
      for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx) {
        for (int py = ty * kTile; py < std::min(cam.height, (ty + 1) * kTile); py += kPacket)
          for (int px = tx * kTile; px < std::min(cam.width, (tx + 1) * kTile); px += kPacket) packet(px, py, state);
        const int done = ++tilesDone;
        if (o.progress && done % std::max(1, tilesX * tilesY / 100) == 0)
          o.progress(progressFrom + progressShare * static_cast<double>(done) / (tilesX * tilesY));
      }
  });
}

// Where sample s of pixel (x, y) lies: s = 0 is the pixel centre, 1..k² the stratified grid.
glm::dvec2 samplePosition(int x, int y, int s, int k) {
  if (s == 0) return {x + 0.5, y + 0.5};
  return {x + ((s - 1) % k + 0.5) / k, y + ((s - 1) / k + 0.5) / k};
}

// The rays of sample s of the packet at (px, py).
void packetRays(const Camera& cam, const Camera::Frame& view, int px, int py, int s, int k, Ray (&rays)[16],
                bool (&valid)[16]) {
  for (int j = 0; j < 16; ++j) {
    const int x = px + j % kPacket, y = py + j / kPacket;
    valid[j] = x < cam.width && y < cam.height;
    const glm::dvec2 at = samplePosition(x, y, s, k);
    rays[j] = view.ray(at.x, at.y);
  }
}

// Records the hit of sample s at pixel p in `plane`: its geometry and its S and A traced with
// the preset's few rays (the same seeds as an unfiltered render's).
void recordVisibility(VisibilityPlane& plane, std::size_t p, const Shader& shader, const Camera::Frame& view,
                      const glm::dvec3& forward, const glm::dvec2& at, const Ray& ray, const SceneHit& h,
                      std::uint64_t seed, int more) {
  const glm::dvec3 x = ray.org + h.hit.t * ray.dir;
  // The ray through the next pixel, at the same depth along the view axis.
  const Ray next = view.ray(at.x + 1.0, at.y);
  const glm::dvec3 beside = next.org + (glm::dot(x - next.org, forward) / glm::dot(next.dir, forward)) * next.dir;
  plane.hit[p] = 1;
  plane.position[p] = glm::vec3(x);
  plane.normal[p] = glm::vec3(h.hit.normal);
  plane.footprint[p] = std::max(static_cast<float>(glm::length(beside - x)), std::numeric_limits<float>::min());
  const Shader::Visibility v = shader.visibility(ray, h, seed, more);
  plane.weight[p] = static_cast<float>(more);
  plane.key[p] = v.key;
  plane.open[p] = v.open;
}

// The centre ray's buffers from its nearest hit; its distance to the edge of its patch when
// `seam` is given (RenderOptions::referenceMasks).
void writeBuffers(FrameBuffers& fb, std::size_t p, const ScenePatches& patches, const Camera& cam,
                  const glm::dvec3& forward, const Ray& ray, const SceneHit& h, std::uint32_t atom,
                  const SeamDistance* seam) {
  const glm::dvec3 x = ray.org + h.hit.t * ray.dir;
  fb.depth[p] = static_cast<float>(h.hit.t);
  fb.viewZ[p] = static_cast<float>(glm::dot(x - cam.eye, forward));
  for (int c = 0; c < 3; ++c) fb.normal[3 * p + c] = static_cast<float>(h.hit.normal[c]);
  fb.kind[p] = static_cast<std::uint32_t>(h.kind);
  fb.patchId[p] = patches.globalId(h.kind, h.patch);
  fb.atomId[p] = atom;
  fb.flags[p] = h.hit.flags;
  if (seam) fb.seamDistance[p] = static_cast<float>((*seam)(h, x));
}

// The rays markPixelEdges traces: one through every pixel corner.
std::size_t cornerRays(const Camera& cam) {
  return static_cast<std::size_t>(cam.width + 1) * static_cast<std::size_t>(cam.height + 1);
}

// RenderOptions::referenceMasks: the seam distances (+inf for the misses) come with the
// buffers; the edge flags from the corner rays once the centre hits are all known.
std::optional<SeamDistance> startMasks(const PatchScene& scene, const RenderOptions& o, FrameBuffers& fb) {
  if (!o.referenceMasks) return std::nullopt;
  fb.seamDistance.assign(fb.pixels(), std::numeric_limits<float>::infinity());
  return SeamDistance(scene.patches());
}

// Transparency: every crossing of each ray, nearest first, composited front to back over the
// background, C = Σ_k α(1 − α)^k c_k + (1 − α)^n background, and alpha (coverage) 1 − (1 − α)^n
// for n crossings; the buffers are those of the nearest crossing. n = 0 gives the opaque
// render's miss and n = 1 with α = 1 its hit (render() takes the opaque path for α = 1).
// The ball-and-stick model is opaque: its first crossing ends the ray, with weight (1 − α)^k
// behind the k surface layers in front of it (alpha 1); the layers behind it are dropped, and
// the `layers` buffer counts the surface layers composited.
FrameBuffers renderTransparent(const PatchScene& scene, const RenderOptions& o, std::span<const glm::vec3> atomColors) {
  const auto start = std::chrono::steady_clock::now();
  const Camera& cam = o.camera;
  FrameBuffers fb;
  fb.reset(cam.width, cam.height);
  fb.layers.assign(fb.pixels(), 0u);
  const int k = o.sampleGridSide();
  const int extraSamples = k > 1 ? k * k : 0;
  const Shader shader(scene, o, atomColors);
  const glm::dvec3 forward = cam.forward();
  const Camera::Frame view = cam.frame();
  const ScenePatches& patches = scene.patches();
  const std::size_t maxLayers = static_cast<std::size_t>(o.maxLayers);
  const float alpha = static_cast<float>(o.opacity);
  const std::optional<SeamDistance> seam = startMasks(scene, o, fb);
  // Layers are not filtered (each pixel's would need its own planes): where the preset counts
  // on the filter, every layer traces kEdgeRays times its rays instead, as its edges do.
  const int unfilteredMore = shader.filters() ? kEdgeRays : 1;

  forEachPacket(cam, o, [&] { return std::vector<SceneHit>(16 * maxLayers); },
                [&](int px, int py, std::vector<SceneHit>& layers) {
    for (int s = 0; s <= extraSamples; ++s) {
      Ray rays[16];
      bool valid[16];
      packetRays(cam, view, px, py, s, k, rays, valid);
      std::size_t count[16];
      scene.intersectLayers16(rays, valid, maxLayers, layers, count);
      for (int j = 0; j < 16; ++j) {
        if (!valid[j]) continue;
        const std::size_t p = static_cast<std::size_t>(py + j / kPacket) * cam.width + (px + j % kPacket);
        const float weight = extraSamples == 0 ? 1.0f : (s == 0 ? 0.0f : 1.0f / static_cast<float>(extraSamples));
        std::size_t surfaceLayers = count[j];
        for (std::size_t l = 0; l < count[j]; ++l)
          if (view::isModelKind(layers[j * maxLayers + l].kind)) {
            surfaceLayers = l;
            break;
          }
        const bool opaqueBehind = surfaceLayers < count[j];
        if (s == 0) fb.layers[p] = static_cast<std::uint32_t>(surfaceLayers);
        glm::vec3 color(0.0f);
        float through = 1.0f;  // the fraction of light that passes the layers so far
        for (std::size_t l = 0; l < surfaceLayers + (opaqueBehind ? 1 : 0); ++l) {
          const SceneHit& h = layers[j * maxLayers + l];
          const std::uint32_t atom = patches.atomOf(h, rays[j].org + h.hit.t * rays[j].dir);
          if (s == 0 && l == 0) writeBuffers(fb, p, patches, cam, forward, rays[j], h, atom, seam ? &*seam : nullptr);
          if (weight == 0.0f) break;
          const std::uint64_t seed = (p * 1024u + static_cast<std::uint64_t>(s)) * kMaxLayers + l;
          const float a = l < surfaceLayers ? alpha : 1.0f;
          color += (through * a) * shader.color(rays[j], h, atom, seed, nullptr, unfilteredMore);
          through *= 1.0f - a;
        }
        if (weight == 0.0f) continue;
        color += through * o.background;
        for (int ch = 0; ch < 3; ++ch) fb.rgba[4 * p + ch] += weight * color[ch];
        fb.rgba[4 * p + 3] += weight * (1.0f - through);
      }
    }
  });
  if (seam) markPixelEdges(scene, cam, fb);
  fb.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fb.rays = fb.pixels() * static_cast<std::size_t>(1 + extraSamples) + (seam ? cornerRays(cam) : 0);
  return fb;
}

}  // namespace

FrameBuffers render(const PatchScene& scene, const RenderOptions& o, std::span<const glm::vec3> atomColors) {
  o.camera.validate();
  if (o.samplesPerPixel < 1 || o.samplesPerPixel > 1024)
    throw std::invalid_argument("samples per pixel " + std::to_string(o.samplesPerPixel) + " must be in [1, 1024]");
  if (o.aoSamples < 0 || o.aoSamples > 4096) throw std::invalid_argument("ambient-occlusion samples must be in [0, 4096]");
  if (o.lighting.shadowRays < 0 || o.lighting.shadowRays > 4096 || o.lighting.occlusionRays < 0 ||
      o.lighting.occlusionRays > 4096)
    throw std::invalid_argument("lighting: shadow and occlusion rays must be in [0, 4096]");
  if (o.lighting.filterPasses < 0 || o.lighting.filterPasses > 8)
    throw std::invalid_argument("lighting: filter passes " + std::to_string(o.lighting.filterPasses) + " must be in [0, 8]");
  if (!(o.opacity > 0.0 && o.opacity <= 1.0))
    throw std::invalid_argument("opacity " + std::to_string(o.opacity) + " must be in (0, 1]");
  if (o.maxLayers < 1 || o.maxLayers > kMaxLayers)
    throw std::invalid_argument("max layers " + std::to_string(o.maxLayers) + " must be in [1, " + std::to_string(kMaxLayers) + "]");
  if (o.opacity < 1.0) return renderTransparent(scene, o, atomColors);
  const auto start = std::chrono::steady_clock::now();
  const Camera& cam = o.camera;
  FrameBuffers fb;
  fb.reset(cam.width, cam.height);
  const std::size_t n = fb.pixels();

  const int k = o.sampleGridSide();
  const int extraSamples = k > 1 ? k * k : 0;  // centre ray always; a k×k grid on top when spp > 1
  const Shader shader(scene, o, atomColors);
  const glm::dvec3 forward = cam.forward();
  const Camera::Frame view = cam.frame();
  const ScenePatches& patches = scene.patches();
  const std::optional<SeamDistance> seam = startMasks(scene, o, fb);

  // Shades samples first..last of every pixel; `plane` holds sample `first`'s filtered S and A
  // when the shader filters (then first == last).
  auto shadeSamples = [&](int first, int last, const VisibilityPlane* plane, double progressFrom, double progressShare) {
    forEachPacket(cam, o, [] { return 0; }, [&](int px, int py, int) {
      for (int s = first; s <= last; ++s) {
        Ray rays[16];
        bool valid[16];
        packetRays(cam, view, px, py, s, k, rays, valid);
        SceneHit hits[16];
        scene.intersect16(rays, valid, 0.0, hits);
        for (int j = 0; j < 16; ++j) {
          if (!valid[j]) continue;
          const std::size_t p = static_cast<std::size_t>(py + j / kPacket) * cam.width + (px + j % kPacket);
          const SceneHit& h = hits[j];
          const float weight = extraSamples == 0 ? 1.0f : (s == 0 ? 0.0f : 1.0f / static_cast<float>(extraSamples));
          if (!h.valid()) {
            for (int c = 0; c < 3; ++c) fb.rgba[4 * p + c] += weight * o.background[c];
            continue;
          }
          const glm::dvec3 x = rays[j].org + h.hit.t * rays[j].dir;
          const std::uint32_t atom = patches.atomOf(h, x);
          if (s == 0) writeBuffers(fb, p, patches, cam, forward, rays[j], h, atom, seam ? &*seam : nullptr);
          if (weight == 0.0f) continue;
          const Shader::Visibility filtered = plane ? Shader::Visibility{plane->key[p], plane->open[p]} : Shader::Visibility{};
          const glm::vec3 c =
              shader.color(rays[j], h, atom, p * 1024u + static_cast<std::uint64_t>(s), plane ? &filtered : nullptr);
          for (int ch = 0; ch < 3; ++ch) fb.rgba[4 * p + ch] += weight * c[ch];
          fb.rgba[4 * p + 3] += weight;
        }
      }
    }, progressFrom, progressShare);
  };
  if (!shader.filters()) {
    shadeSamples(0, extraSamples, nullptr, 0.0, 1.0);
  } else {
    // Per sample position: its hits' S and A into a plane, filtered, then shaded. The shading
    // pass traces the primary rays again (cheap beside the visibility rays) rather than keep
    // every sample's hits. Sample 0 of a supersampled frame only writes the buffers.
    VisibilityPlane plane;
    plane.reset(cam.width, cam.height);
    const int first = extraSamples == 0 ? 0 : 1;
    const double share = 1.0 / (extraSamples + 1 - first);
    if (first == 1) shadeSamples(0, 0, nullptr, 0.0, 0.0);
    for (int s = first; s <= extraSamples; ++s) {
      if (s > first) plane.reset(cam.width, cam.height);
      const double from = (s - first) * share;
      // Every hit with the preset's rays, then again with kEdgeRays times as many where the
      // filter will find few neighbours on the same smooth surface (FilterEdges).
      std::vector<unsigned char> edge;
      for (const int more : {1, kEdgeRays}) {
        forEachPacket(cam, o, [] { return 0; }, [&](int px, int py, int) {
          Ray rays[16];
          bool valid[16];
          packetRays(cam, view, px, py, s, k, rays, valid);
          for (int j = 0; j < 16 && more > 1; ++j)
            valid[j] = valid[j] && edge[static_cast<std::size_t>(py + j / kPacket) * cam.width + (px + j % kPacket)];
          SceneHit hits[16];
          scene.intersect16(rays, valid, 0.0, hits);
          for (int j = 0; j < 16; ++j) {
            if (!valid[j] || !hits[j].valid()) continue;
            const int x = px + j % kPacket, y = py + j / kPacket;
            const std::size_t p = static_cast<std::size_t>(y) * cam.width + x;
            recordVisibility(plane, p, shader, view, forward, samplePosition(x, y, s, k), rays[j], hits[j],
                             p * 1024u + static_cast<std::uint64_t>(s), more);
          }
        }, from + (more == 1 ? 0.0 : 0.6 * share), (more == 1 ? 0.6 : 0.3) * share);
        if (more == 1) edge = filterEdges(plane);
      }
      filterVisibility(plane, o.lighting.filterPasses, shader.filterReach());
      shadeSamples(s, s, &plane, from + 0.9 * share, 0.1 * share);
    }
  }
  // Background pixels: colour only, alpha 0 stays.
  if (seam) markPixelEdges(scene, cam, fb);
  fb.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fb.rays = n * static_cast<std::size_t>(1 + extraSamples) + (seam ? cornerRays(cam) : 0);
  return fb;
}

}  // namespace surftrace::trace
