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

namespace surftrace::trace {
namespace {

using view::Camera;
using view::ColorMode;
using view::FrameBuffers;
using view::RenderOptions;

constexpr int kTile = 16;    // pixels per tile side: 16 packets of 4×4 rays
constexpr int kPacket = 4;   // 4×4 = 16 rays, Embree's widest packet
constexpr double kPi = 3.14159265358979323846;

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

// Point i of n of a rank-1 (Fibonacci) lattice in the unit square, shifted by `rotation`
// modulo 1 (a Cranley–Patterson rotation): stratified in u, low-discrepancy in (u, v).
glm::dvec2 latticePoint(int i, int n, const glm::dvec2& rotation) {
  constexpr double kGoldenFraction = 0.6180339887498948482;
  const double u = (i + 0.5) / n + rotation.x, v = i * kGoldenFraction + rotation.y;
  return {u - std::floor(u), v - std::floor(v)};
}

// A unit vector perpendicular to unit n, and the third of the right-handed frame.
void tangentFrame(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
  t = std::abs(n.x) < 0.9 ? glm::normalize(glm::cross(n, glm::dvec3(1, 0, 0)))
                          : glm::normalize(glm::cross(n, glm::dvec3(0, 1, 0)));
  b = glm::cross(n, t);
}

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

  glm::vec3 color(const Ray& ray, const SceneHit& h, std::uint32_t atom, std::uint64_t pixel) const {
    const glm::vec3 base = o_.color == ColorMode::Patch ? view::kindColor(h.kind)
                           : atom < atomColors_.size()  ? atomColors_[atom]
                                                        : glm::vec3(1.0f, 0.0f, 1.0f);
    const glm::dvec3 toEye = -glm::normalize(ray.dir);
    const glm::dvec3 x = ray.org + h.hit.t * ray.dir;
    const glm::dvec3 start = x + offset_ * h.hit.normal;
    if (o_.lighting.keyFill()) {
      // The key light's visibility matters only where the key light shines (n·k > 0).
      const float keyVisible = keyRays_ > 0 && glm::dot(h.hit.normal, lights_.key) > 0.0
                                   ? static_cast<float>(keyVisibility(start, h.hit.normal, pixel))
                                   : 1.0f;
      const float ambientVisible =
          occlusionRays_ > 0 ? static_cast<float>(openFraction(start, h.hit.normal, pixel, occlusionRays_)) : 1.0f;
      return view::shade(base, h.hit.normal, toEye, o_.lighting, lights_, keyVisible, ambientVisible);
    }
    glm::vec3 c = view::shade(base, h.hit.normal, toEye, o_.lighting);
    if (o_.shadows && scene_.occluded(Ray{start, keyLight_}, 0.0, std::numeric_limits<double>::infinity()))
      c *= 0.6f;
    if (o_.aoSamples > 0) c *= static_cast<float>(ambientVisibility(start, h.hit.normal, pixel));
    return c;
  }

 private:
  static double sceneScale(const PatchScene& scene) {
    const Bounds3d b = scene.patches().bounds();
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
  // keyRays_ rays to a lattice on the disc of angular radius keyRadius, rotated per pixel as
  // above. A ray below the surface's tangent plane counts as blocked (by the surface itself).
  double keyVisibility(const glm::dvec3& x, const glm::dvec3& n, std::uint64_t pixel) const {
    const double inf = std::numeric_limits<double>::infinity();
    if (o_.lighting.shadowRays == 0) return scene_.occluded(Ray{x, lights_.key}, 0.0, inf) ? 0.0 : 1.0;
    PixelRng rng(pixel ^ 0xE7037ED1A0B428DBull);
    const glm::dvec2 rotation(rng.next(), rng.next());
    int open = 0;
    for (int s = 0; s < keyRays_; ++s) {
      const glm::dvec2 q = latticePoint(s, keyRays_, rotation);
      const double r = std::tan(o_.lighting.keyRadius) * std::sqrt(q.x), phi = 2.0 * kPi * q.y;
      const glm::dvec3 d = glm::normalize(lights_.key + r * std::cos(phi) * keyT_ + r * std::sin(phi) * keyB_);
      if (glm::dot(d, n) > 0.0 && !scene_.occluded(Ray{x, d}, 0.0, inf)) ++open;
    }
    return static_cast<double>(open) / keyRays_;
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
// progress callback; makeState() gives each tile its scratch space (passed as packet's third argument).
template <class MakeState, class Packet>
void forEachPacket(const Camera& cam, const RenderOptions& o, MakeState makeState, Packet packet) {
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
          o.progress(static_cast<double>(done) / (tilesX * tilesY));
      }
  });
}

// The rays of sample s of the packet at (px, py): s = 0 is the pixel centre, 1..k² the stratified grid.
void packetRays(const Camera& cam, const Camera::Frame& view, int px, int py, int s, int k, Ray (&rays)[16],
                bool (&valid)[16]) {
  for (int j = 0; j < 16; ++j) {
    const int x = px + j % kPacket, y = py + j / kPacket;
    valid[j] = x < cam.width && y < cam.height;
    double sx = x + 0.5, sy = y + 0.5;
    if (s > 0) {
      sx = x + ((s - 1) % k + 0.5) / k;
      sy = y + ((s - 1) / k + 0.5) / k;
    }
    rays[j] = view.ray(sx, sy);
  }
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
          color += (through * a) * shader.color(rays[j], h, atom, seed);
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

  forEachPacket(cam, o, [] { return 0; }, [&](int px, int py, int) {
    for (int s = 0; s <= extraSamples; ++s) {
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
        const glm::vec3 c = shader.color(rays[j], h, atom, p * 1024u + static_cast<std::uint64_t>(s));
        for (int ch = 0; ch < 3; ++ch) fb.rgba[4 * p + ch] += weight * c[ch];
        fb.rgba[4 * p + 3] += weight;
      }
    }
  });
  // Background pixels: colour only, alpha 0 stays.
  if (seam) markPixelEdges(scene, cam, fb);
  fb.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fb.rays = n * static_cast<std::size_t>(1 + extraSamples) + (seam ? cornerRays(cam) : 0);
  return fb;
}

}  // namespace surftrace::trace
