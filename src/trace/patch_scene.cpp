// The patch list as an Embree 3 scene of user geometry: one geometry per patch kind.
#include "trace/patch_scene.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <tuple>
#include <type_traits>

#include "build/core/assert.hpp"

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include "trace/layers.hpp"

namespace surftrace::trace {
namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();

float roundDown(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -kInfF) : f;
}
float roundUp(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? std::nextafter(f, kInfF) : f;
}

// What each Embree geometry's callbacks see: its patches and the box padding.
template <class Kind> struct GeometryData {
  using Row = Kind;
  const typename Kind::Patch* patches = nullptr;
  double pad = 0.0;
};
template <class Kinds> struct GeometryDataOf;
template <class... Kind> struct GeometryDataOf<std::tuple<Kind...>> {
  using type = std::tuple<GeometryData<Kind>...>;
};

// The box traversal culls with: the skin's is cut by its cell planes (cellBounds), the others'
// is their own bounds(). The scene's box (enterBox) stays the union of bounds().
template <class Patch> Bounds3d traversalBounds(const Patch& p) {
  if constexpr (std::is_same_v<Patch, MssPatch>)
    return cellBounds(p);
  else
    return bounds(p);
}

// Embree drops a primitive whose box is empty or not finite (accelset.h), which would
// leave a hole; the intersectors promise finite boxes. Embree traverses with the float
// rounding of a ray whose callbacks then use the double ray: the boxes are padded by more
// than the distance between the two (PatchScene's constructor) and rounded outward.
template <class Kind> void boundsFn(const RTCBoundsFunctionArguments* args) {
  const auto* data = static_cast<const GeometryData<Kind>*>(args->geometryUserPtr);
  const Bounds3d b = traversalBounds(data->patches[args->primID]);
  RTCBounds* o = args->bounds_o;
  o->lower_x = roundDown(b.lower.x - data->pad);
  o->lower_y = roundDown(b.lower.y - data->pad);
  o->lower_z = roundDown(b.lower.z - data->pad);
  o->upper_x = roundUp(b.upper.x + data->pad);
  o->upper_y = roundUp(b.upper.y + data->pad);
  o->upper_z = roundUp(b.upper.z + data->pad);
}

// Double precision travels beside Embree's float rays: the callbacks intersect the double
// ray (`rays`, indexed by the ray id), so a ray's answer does not depend on how its origin
// rounds to float (at 1e4 Å from the origin a float step is 1e-3 Å), and they keep the
// nearest hit in double (`hits`): Embree only keeps a float tfar, and re-intersecting the
// found patch afterwards is not the same computation (at a seam the re-run can land on the
// other side of the trimming edge).
struct HitContext {
  RTCIntersectContext embree;  // first member: Embree hands this pointer back to the callbacks
  const UnitRay* rays = nullptr;  // with their unit directions, made once per ray
  PatchHit* hits = nullptr;    // null for occlusion queries
  // Transparency (PatchScene::intersectLayers16): every crossing goes into the ray's list.
  LayerList* layers = nullptr;
  const SphereClip* clip = nullptr;
  // Occlusion queries (one ray): the end of the range in double, as intersect1's best.t starts.
  double occlusionTMax = std::numeric_limits<double>::infinity();
};

// The layers' callback: every root of the patch on the ray that is on the patch (whole
// spheres: SphereClip) goes into the ray's LayerList. Once the list is full the ray ends at
// its farthest crossing, so that traversal culls what lies beyond.
template <class Kind>
void collectLayers(const typename Kind::Patch& patch, std::uint32_t primID, const HitContext& context, unsigned id,
                   float& tfar) {
  LayerList& layers = context.layers[id];
  const UnitRay& ray = context.rays[id];
  const double tMax = layers.full() ? layers.back().hit.t : static_cast<double>(tfar);
  if constexpr (isModelRow<Kind>()) {
    // The model is opaque: only where a ray enters it matters (render.cpp stops there).
    if (const auto h = intersect(patch, ray, 0.0, tMax)) layers.insert(SceneHit{Kind::kind, primID, *h});
    if (layers.full()) tfar = std::min(tfar, roundUp(layers.back().hit.t));
    return;
  }
  forEachRoot(patch, ray, 0.0, tMax, [&](const PatchHit& h) {
    if constexpr (std::is_same_v<Kind, SphereKind>)
      if (!context.clip->onPatch(primID, ray.org + h.t * ray.dir)) return;
    layers.insert(SceneHit{Kind::kind, primID, h});
  });
  if (layers.full()) tfar = std::min(tfar, roundUp(layers.back().hit.t));
}

// Embree calls these from C and from its TBB workers for packets of N = 1, 4, 8 or 16
// rays, honouring valid[] (STYLE §3.7). The intersectors neither throw nor allocate.
template <class Kind> void intersectFn(const RTCIntersectFunctionNArguments* args) {
  const auto& patch = static_cast<const GeometryData<Kind>*>(args->geometryUserPtr)->patches[args->primID];
  const auto* context = reinterpret_cast<const HitContext*>(args->context);
  const unsigned N = args->N;
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, N);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, N);
  for (unsigned i = 0; i < N; ++i) {
    if (args->valid[i] == 0) continue;
    float& tfar = RTCRayN_tfar(ray, N, i);
    const unsigned id = RTCRayN_id(ray, N, i);
    if (context->layers) {
      collectLayers<Kind>(patch, args->primID, *context, id, tfar);
      continue;
    }
    PatchHit& best = context->hits[id];
    // The nearest hit so far, in double; Embree's tfar is only its float upper bound.
    const auto h = intersect(patch, context->rays[id], 0.0, std::min(static_cast<double>(tfar), best.t));
    if (!h) continue;
    best = *h;
    tfar = roundUp(h->t);  // rounded up, so that traversal culls no box that could still hold a nearer root
    RTCHitN_Ng_x(hit, N, i) = static_cast<float>(h->normal.x);
    RTCHitN_Ng_y(hit, N, i) = static_cast<float>(h->normal.y);
    RTCHitN_Ng_z(hit, N, i) = static_cast<float>(h->normal.z);
    RTCHitN_u(hit, N, i) = 0.0f;
    RTCHitN_v(hit, N, i) = 0.0f;
    RTCHitN_primID(hit, N, i) = args->primID;
    RTCHitN_geomID(hit, N, i) = args->geomID;
    RTCHitN_instID(hit, N, i, 0) = args->context->instID[0];
  }
}

// Whether a patch blocks the ray within (tMin, tMax]: the kind's any-hit test where it has one
// (it answers as intersect() would, doing only what that answer needs), else intersect().
template <class Patch> bool blocks(const Patch& patch, const UnitRay& ray, double tMin, double tMax) {
  if constexpr (requires { occludes(patch, ray, tMin, tMax); })
    return occludes(patch, ray, tMin, tMax);
  else
    return intersect(patch, ray, tMin, tMax).has_value();
}

// Embree 3 runs no filter functions for user geometry and marks an occluded ray by
// tfar = −inf. The range is the query's own, in double (occlusionTMax): the float tfar is
// rounded up from it, and a hit between the two would be a hit intersect1() does not find.
template <class Kind> void occludedFn(const RTCOccludedFunctionNArguments* args) {
  const auto& patch = static_cast<const GeometryData<Kind>*>(args->geometryUserPtr)->patches[args->primID];
  const auto* context = reinterpret_cast<const HitContext*>(args->context);
  const unsigned N = args->N;
  for (unsigned i = 0; i < N; ++i) {
    if (args->valid[i] == 0) continue;
    float& tfar = RTCRayN_tfar(args->ray, N, i);
    const double tMax = std::min(static_cast<double>(tfar), context->occlusionTMax);
    if (blocks(patch, context->rays[RTCRayN_id(args->ray, N, i)], 0.0, tMax)) tfar = -kInfF;
  }
}

// Moves a ray's origin to where it enters the scene's box (in double) before it is rounded
// to float for Embree, so the float ray stays within a few ulps of scene coordinates of the
// double one whatever the camera distance (ORACLES B.1's origin shift, for the traversal).
// Returns false when the ray misses the box within [tMin, tMax]; `t0` is the shift.
bool enterBox(const Bounds3d& box, const Ray& ray, double tMin, double tMax, Ray& shifted, double& t0) {
  double lo = tMin, hi = tMax;
  for (int k = 0; k < 3; ++k) {
    const double inv = 1.0 / ray.dir[k];
    double a = (box.lower[k] - ray.org[k]) * inv, b = (box.upper[k] - ray.org[k]) * inv;
    if (a > b) std::swap(a, b);
    if (!(a <= b)) continue;  // dir[k] == 0 and org inside the slab gives NaN·0 cases: no limit
    lo = std::max(lo, a);
    hi = std::min(hi, b);
  }
  if (!(lo <= hi)) return false;
  t0 = lo;
  shifted = Ray{ray.org + t0 * ray.dir, ray.dir};
  return true;
}

void setFloatRay(RTCRay& r, const Ray& ray, double tFar, unsigned id) {
  r.org_x = static_cast<float>(ray.org.x);
  r.org_y = static_cast<float>(ray.org.y);
  r.org_z = static_cast<float>(ray.org.z);
  r.dir_x = static_cast<float>(ray.dir.x);
  r.dir_y = static_cast<float>(ray.dir.y);
  r.dir_z = static_cast<float>(ray.dir.z);
  r.tnear = 0.0f;
  r.tfar = tFar >= static_cast<double>(std::numeric_limits<float>::max()) ? kInfF : roundUp(tFar);
  r.time = 0.0f;
  r.mask = ~0u;
  r.id = id;
  r.flags = 0;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// ScenePatches

ScenePatches ScenePatches::fromPatchList(const build::PatchList& list, std::span<const glm::dvec3> centers,
                                         std::span<const double> radii, const build::BallStickModel* model) {
  if (centers.size() != radii.size()) throw std::invalid_argument("scene: as many atom radii as centres are needed");
  ScenePatches s;
  s.params = list.params;
  s.atoms.reserve(centers.size());
  for (std::size_t i = 0; i < centers.size(); ++i) s.atoms.push_back(glm::dvec4(centers[i], radii[i]));
  s.planes.clip = list.clipPlanes;
  s.planes.cell = list.cellPlanes;
  if (list.skinAtoms.size() > 0) s.planes.skinAtoms = std::make_unique<const SkinAtomBalls>(skinAtomBalls(list));
  std::apply(
      [&](auto&... k) {
        auto load = [&](auto& kp) {
          using Kind = typename std::remove_reference_t<decltype(kp)>::Row;
          if constexpr (isModelRow<Kind>()) {
            const std::size_t n = model ? Kind::count(*model) : 0;
            kp.patches.reserve(n);
            kp.atoms.reserve(n);
            for (std::size_t i = 0; i < n; ++i) {
              kp.patches.push_back(Kind::patch(*model, i));
              kp.atoms.push_back(Kind::atoms(*model, i));
            }
          } else {
            const std::size_t n = view::patchCount(list, Kind::kind);
            kp.patches.reserve(n);
            kp.atoms.reserve(n);
            for (std::size_t i = 0; i < n; ++i) {
              kp.patches.push_back(Kind::patch(list, i, s.planes));
              kp.atoms.push_back(Kind::atoms(list, i));
            }
          }
        };
        (load(k), ...);
      },
      s.kinds);
  std::array<std::size_t, view::kPatchKindCount> counts{};
  std::size_t row = 0;
  s.forEachKind([&](const auto& k) { counts[row++] = k.patches.size(); });
  s.ids = view::PatchIdOrder(counts);
  return s;
}

std::uint32_t ScenePatches::atomOf(const SceneHit& h, const glm::dvec3& x) const {
  std::uint32_t atom = ~0u;
  forEachKind([&](const auto& k) {
    if (std::remove_reference_t<decltype(k)>::Row::kind == h.kind) atom = trace::atomOf(k.patches[h.patch], k.atoms[h.patch], x);
  });
  return atom;
}

Bounds3d ScenePatches::bounds() const {
  Bounds3d b;
  forEachKind([&](const auto& k) {
    for (const auto& p : k.patches) b.extend(trace::bounds(p));
  });
  return b;
}

SceneHit ScenePatches::intersectPatch(PatchKind kind, std::uint32_t patch, const Ray& ray, double tMin, double tMax) const {
  std::optional<PatchHit> h;
  forEachKind([&](const auto& k) {
    if (std::remove_reference_t<decltype(k)>::Row::kind == kind) h = intersect(k.patches[patch], ray, tMin, tMax);
  });
  if (!h) return {};
  return SceneHit{kind, patch, *h};
}

SceneHit ScenePatches::intersectAll(const Ray& ray, double tMin, double tMax) const {
  SceneHit best;
  forEachKind([&](const auto& k) {
    constexpr PatchKind kind = std::remove_reference_t<decltype(k)>::Row::kind;
    for (std::uint32_t i = 0; i < k.patches.size(); ++i) {
      const std::optional<PatchHit> h = intersect(k.patches[i], ray, tMin, tMax);
      if (h && h->t <= tMax) {
        best = SceneHit{kind, i, *h};
        tMax = h->t;
      }
    }
  });
  return best;
}

// ---------------------------------------------------------------------------------------
// PatchScene

struct EmbreeDevice::Impl {
  RTCDevice device = nullptr;
  std::mutex errorMutex;
  std::string error;

  Impl() {
    device = rtcNewDevice(nullptr);
    if (!device) throw std::runtime_error("Embree: cannot create a device (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
    rtcSetDeviceErrorFunction(device, &Impl::onError, this);
  }
  ~Impl() { rtcReleaseDevice(device); }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  // Embree reports errors through this callback; the scene checks after each commit.
  static void onError(void* self, RTCError code, const char* message) {
    auto* e = static_cast<Impl*>(self);
    std::lock_guard lock(e->errorMutex);
    if (e->error.empty()) e->error = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
  }
  // Throws the first error since the last check, and forgets it.
  void check(const char* what) {
    std::lock_guard lock(errorMutex);
    if (error.empty()) return;
    const std::string message = std::string(what) + ": " + error;
    error.clear();
    throw std::runtime_error(message);
  }
};

EmbreeDevice::EmbreeDevice() : impl_(std::make_shared<Impl>()) {}

struct PatchScene::Embree {
  std::shared_ptr<EmbreeDevice::Impl> shared;  // keeps the device alive as long as the scene
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  PatchKind kindOfGeometry[view::kPatchKindCount] = {};  // by Embree geometry id
  // The spheres' clipping for transparency, made by the first query that needs it.
  std::once_flag clipOnce;
  SphereClip clip;
  const SphereClip& sphereClip(const ScenePatches& patches) {
    std::call_once(clipOnce, [&] { clip = SphereClip(patches); });
    return clip;
  }

  ~Embree() {
    if (scene) rtcReleaseScene(scene);
  }
  void check(const char* what) { shared->check(what); }
  // What each kind's geometry callbacks see, one per row of SceneKinds.
  GeometryDataOf<SceneKinds>::type geometryData;
  Bounds3d box;  // the scene's patches, padded like each patch's box

  template <class Kind> void add(const KindPatches<Kind>& kp, GeometryData<Kind>& slot, double pad) {
    using Patch = typename Kind::Patch;
    const std::vector<Patch>& patches = kp.patches;
    if (patches.empty()) return;
    slot = GeometryData<Kind>{patches.data(), pad};
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(patches.size()));
    rtcSetGeometryUserData(g, &slot);
    rtcSetGeometryBoundsFunction(g, boundsFn<Kind>, nullptr);
    rtcSetGeometryIntersectFunction(g, intersectFn<Kind>);
    rtcSetGeometryOccludedFunction(g, occludedFn<Kind>);
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    check("creating the Embree geometry");
    kindOfGeometry[id] = Kind::kind;
  }
};

PatchScene::PatchScene(ScenePatches patches, const EmbreeDevice& device)
    : patches_(std::move(patches)), embree_(std::make_unique<Embree>()) {
  const auto start = std::chrono::steady_clock::now();
  if (patches_.size() >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("scene: too many patches for 32-bit ids");
  embree_->shared = device.impl();
  embree_->device = embree_->shared->device;
  embree_->scene = rtcNewScene(embree_->device);
  rtcSetSceneBuildQuality(embree_->scene, RTC_BUILD_QUALITY_HIGH);
  // A float ray shifted to the scene's box (enterBox) strays from its double original by at
  // most √3·2⁻²⁴·(|origin| + t) <= 2·2⁻²⁴·(largest coordinate + diagonal); pad by 2⁻²⁰ of that.
  bounds_ = patches_.bounds();
  const Bounds3d& box = bounds_;
  double pad = 0.0;
  if (!box.empty()) {
    const double largest = std::max(glm::length(glm::abs(box.lower)), glm::length(glm::abs(box.upper)));
    pad = 0x1.0p-20 * (largest + glm::length(box.upper - box.lower));
    embree_->box = Bounds3d{box.lower - pad, box.upper + pad};
  }
  // One geometry per kind that has patches, attached in row order.
  std::apply([&](auto&... data) { (embree_->add(patches_.of<typename std::remove_reference_t<decltype(data)>::Row>(), data, pad), ...); },
             embree_->geometryData);
  rtcCommitScene(embree_->scene);
  embree_->check("building the Embree scene");
  buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

PatchScene::~PatchScene() = default;

namespace {

// A packet of 16 rays for Embree, each moved to where it enters the scene's box (enterBox).
// Returns whether any lane is active.
bool preparePacket(const Bounds3d& box, const Ray (&rays)[16], const bool (&valid)[16], double tMin, int (&mask)[16],
                   RTCRayHit16& rh, Ray (&shifted)[16], double (&shift)[16]) {
  bool any = false;
  for (int i = 0; i < 16; ++i) {
    const bool active = valid[i] && enterBox(box, rays[i], tMin, std::numeric_limits<double>::infinity(), shifted[i], shift[i]);
    any = any || active;
    mask[i] = active ? -1 : 0;
    RTCRay r;
    setFloatRay(r, active ? shifted[i] : rays[i], std::numeric_limits<double>::infinity(), static_cast<unsigned>(i));
    rh.ray.org_x[i] = r.org_x;
    rh.ray.org_y[i] = r.org_y;
    rh.ray.org_z[i] = r.org_z;
    rh.ray.dir_x[i] = r.dir_x;
    rh.ray.dir_y[i] = r.dir_y;
    rh.ray.dir_z[i] = r.dir_z;
    rh.ray.tnear[i] = r.tnear;
    rh.ray.tfar[i] = r.tfar;
    rh.ray.time[i] = r.time;
    rh.ray.mask[i] = r.mask;
    rh.ray.id[i] = r.id;
    rh.ray.flags[i] = r.flags;
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
  return any;
}

}  // namespace

void PatchScene::intersectLayers16(const Ray (&rays)[16], const bool (&valid)[16], std::size_t maxLayers,
                                   std::span<SceneHit> layers, std::size_t (&count)[16]) const {
  SURFTRACE_ASSERT(maxLayers >= 1 && layers.size() >= 16 * maxLayers);
  alignas(64) int mask[16];
  alignas(64) RTCRayHit16 rh;
  Ray shifted[16];
  double shift[16];
  for (std::size_t& c : count) c = 0;
  if (!preparePacket(embree_->box, rays, valid, 0.0, mask, rh, shifted, shift)) return;
  // Each lane's list merges in its own units of t (the shifted ray has the original's direction).
  LayerList lanes[16];
  for (std::size_t i = 0; i < 16; ++i)
    lanes[i] = LayerList(layers.subspan(i * maxLayers, maxLayers), kLayerMergeDistance / glm::length(rays[i].dir));
  HitContext context;
  rtcInitIntersectContext(&context.embree);
  context.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  UnitRay unitRays[16];
  for (int i = 0; i < 16; ++i)
    if (mask[i] != 0) unitRays[i] = UnitRay(shifted[i]);
  context.rays = unitRays;
  context.layers = lanes;
  context.clip = &embree_->sphereClip(patches_);
  rtcIntersect16(mask, embree_->scene, &context.embree, &rh);
  for (int i = 0; i < 16; ++i) {
    count[i] = mask[i] == 0 ? 0 : lanes[i].size();
    for (std::size_t k = 0; k < count[i]; ++k) layers[i * maxLayers + k].hit.t += shift[i];
  }
}

std::vector<SceneHit> PatchScene::intersectLayers1(const Ray& ray, std::size_t maxLayers) const {
  Ray rays[16];
  bool valid[16] = {};
  rays[0] = ray;
  valid[0] = true;
  std::vector<SceneHit> layers(16 * maxLayers);
  std::size_t count[16];
  intersectLayers16(rays, valid, maxLayers, layers, count);
  layers.resize(count[0]);
  return layers;
}

void PatchScene::intersect16(const Ray (&rays)[16], const bool (&valid)[16], double tMin, SceneHit (&hits)[16]) const {
  alignas(64) int mask[16];
  alignas(64) RTCRayHit16 rh;
  Ray shifted[16];
  double shift[16];
  PatchHit exact[16];
  for (SceneHit& h : hits) h = {};
  if (!preparePacket(embree_->box, rays, valid, tMin, mask, rh, shifted, shift)) return;
  HitContext context;
  rtcInitIntersectContext(&context.embree);
  context.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  UnitRay unitRays[16];
  for (int i = 0; i < 16; ++i)
    if (mask[i] != 0) unitRays[i] = UnitRay(shifted[i]);
  context.rays = unitRays;
  context.hits = exact;
  rtcIntersect16(mask, embree_->scene, &context.embree, &rh);
  for (int i = 0; i < 16; ++i) {
    if (mask[i] == 0 || rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
    exact[i].t += shift[i];
    hits[i] = SceneHit{embree_->kindOfGeometry[rh.hit.geomID[i]], rh.hit.primID[i], exact[i]};
  }
}

SceneHit PatchScene::intersect1(const Ray& ray, double tMin, double tMax) const {
  Ray shifted;
  double shift = 0.0;
  if (!enterBox(embree_->box, ray, tMin, tMax, shifted, shift)) return {};
  RTCRayHit rh;
  setFloatRay(rh.ray, shifted, tMax - shift, 0);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  PatchHit exact;
  exact.t = tMax - shift;
  HitContext context;
  rtcInitIntersectContext(&context.embree);
  const UnitRay unitRay(shifted);
  context.rays = &unitRay;
  context.hits = &exact;
  rtcIntersect1(embree_->scene, &context.embree, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {};
  exact.t += shift;
  return SceneHit{embree_->kindOfGeometry[rh.hit.geomID], rh.hit.primID, exact};
}

bool PatchScene::occluded(const Ray& ray, double tMin, double tMax) const {
  Ray shifted;
  double shift = 0.0;
  if (!enterBox(embree_->box, ray, tMin, tMax, shifted, shift)) return false;
  RTCRay r;
  setFloatRay(r, shifted, tMax - shift, 0);
  HitContext context;
  rtcInitIntersectContext(&context.embree);
  const UnitRay unitRay(shifted);
  context.rays = &unitRay;
  context.occlusionTMax = tMax - shift;
  rtcOccluded1(embree_->scene, &context.embree, &r);
  return r.tfar == -kInfF;
}

}  // namespace surftrace::trace
