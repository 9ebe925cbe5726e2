// The patch list as an Embree 3 scene of user geometry: one geometry per patch kind.
#include "trace/patch_scene.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

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

// Embree drops a primitive whose box is empty or not finite (accelset.h), which would
// leave a hole; the intersectors promise finite boxes, and we round them outward.
template <class Patch> void boundsFn(const RTCBoundsFunctionArguments* args) {
  const auto* patches = static_cast<const Patch*>(args->geometryUserPtr);
  const Bounds3d b = bounds(patches[args->primID]);
  RTCBounds* o = args->bounds_o;
  o->lower_x = roundDown(b.lower.x);
  o->lower_y = roundDown(b.lower.y);
  o->lower_z = roundDown(b.lower.z);
  o->upper_x = roundUp(b.upper.x);
  o->upper_y = roundUp(b.upper.y);
  o->upper_z = roundUp(b.upper.z);
}

// The double-precision hits travel beside Embree's float ones: Embree only keeps a float
// tfar, and re-intersecting the found patch afterwards is not the same computation (at a
// seam between two patches the re-run can land on the other side of the trimming edge).
// Each ray's id indexes `hits`.
struct HitContext {
  RTCIntersectContext embree;  // first member: Embree hands this pointer back to the callbacks
  PatchHit* hits;
};

Ray rayOf(RTCRayN* ray, unsigned N, unsigned i) {
  return Ray{{RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i), RTCRayN_org_z(ray, N, i)},
             {RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i), RTCRayN_dir_z(ray, N, i)}};
}

// Embree calls these from C and from its TBB workers for packets of N = 1, 4, 8 or 16
// rays, honouring valid[] (STYLE §3.7). The intersectors neither throw nor allocate.
template <class Patch> void intersectFn(const RTCIntersectFunctionNArguments* args) {
  const Patch& patch = static_cast<const Patch*>(args->geometryUserPtr)[args->primID];
  const auto* context = reinterpret_cast<const HitContext*>(args->context);
  const unsigned N = args->N;
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, N);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, N);
  for (unsigned i = 0; i < N; ++i) {
    if (args->valid[i] == 0) continue;
    float& tfar = RTCRayN_tfar(ray, N, i);
    PatchHit& best = context->hits[RTCRayN_id(ray, N, i)];
    // The nearest hit so far, in double; Embree's tfar is only its float upper bound.
    const auto h = intersect(patch, rayOf(ray, N, i), RTCRayN_tnear(ray, N, i), std::min(static_cast<double>(tfar), best.t));
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

// Embree 3 runs no filter functions for user geometry and marks an occluded ray by
// tfar = −inf.
template <class Patch> void occludedFn(const RTCOccludedFunctionNArguments* args) {
  const Patch& patch = static_cast<const Patch*>(args->geometryUserPtr)[args->primID];
  const unsigned N = args->N;
  for (unsigned i = 0; i < N; ++i) {
    if (args->valid[i] == 0) continue;
    float& tfar = RTCRayN_tfar(args->ray, N, i);
    if (intersect(patch, rayOf(args->ray, N, i), RTCRayN_tnear(args->ray, N, i), tfar)) tfar = -kInfF;
  }
}

}  // namespace

const char* patchKindName(PatchKind kind) {
  switch (kind) {
    case PatchKind::None: return "none";
    case PatchKind::Convex: return "convex";
    case PatchKind::Toroidal: return "toroidal";
    case PatchKind::Concave: return "concave";
  }
  return "?";
}

// ---------------------------------------------------------------------------------------
// ScenePatches

ScenePatches ScenePatches::fromPatchList(const build::PatchList& list) {
  ScenePatches s;
  const double rp = list.params.probeRadius;
  s.spheres.reserve(list.convex.size());
  for (std::size_t i = 0; i < list.convex.size(); ++i) s.spheres.push_back({list.convex.center[i], list.convex.radius[i]});
  s.sphereAtom = list.convex.atom;
  s.tori.reserve(list.tori.size());
  for (std::size_t i = 0; i < list.tori.size(); ++i) s.tori.push_back(torusPatch(list.tori, i, rp));
  s.torusAtomI = list.tori.atomI;
  s.torusAtomJ = list.tori.atomJ;
  s.clipPlanes = list.clipPlanes;
  s.concave.reserve(list.concave.size());
  for (std::size_t i = 0; i < list.concave.size(); ++i) {
    ConcavePatch c = concavePatch(list, i);
    // Re-point the clipping planes at this object's own copy.
    c.clipPlanes = std::span<const build::Plane>(s.clipPlanes).subspan(list.concave.clipBegin[i], list.concave.clipCount[i]);
    s.concave.push_back(c);
    s.concaveAtoms.emplace_back(list.concave.atomI[i], list.concave.atomJ[i], list.concave.atomK[i]);
  }
  return s;
}

std::uint32_t ScenePatches::globalId(PatchKind kind, std::uint32_t patch) const {
  switch (kind) {
    case PatchKind::Convex: return patch;
    case PatchKind::Toroidal: return static_cast<std::uint32_t>(spheres.size()) + patch;
    case PatchKind::Concave: return static_cast<std::uint32_t>(spheres.size() + tori.size()) + patch;
    case PatchKind::None: break;
  }
  return ~0u;
}

std::uint32_t ScenePatches::atomOf(const SceneHit& h, const glm::dvec3& x) const {
  switch (h.kind) {
    case PatchKind::Convex: return sphereAtom[h.patch];
    case PatchKind::Toroidal: {
      // The saddle meets atom i at θ_i and atom j at θ_j; the axial coordinate decides.
      const TorusPatch& t = tori[h.patch];
      const double a = glm::dot(x - t.center, t.axis);
      const double aI = t.probeRadius * std::sin(t.thetaI), aJ = t.probeRadius * std::sin(t.thetaJ);
      return a - aI <= aJ - a ? torusAtomI[h.patch] : torusAtomJ[h.patch];
    }
    case PatchKind::Concave: {
      const ConcavePatch& c = concave[h.patch];
      const glm::dvec3 u = x - c.probe;
      const double di = glm::dot(u, c.dirI), dj = glm::dot(u, c.dirJ), dk = glm::dot(u, c.dirK);
      const glm::uvec3& atoms = concaveAtoms[h.patch];
      return di >= dj && di >= dk ? atoms.x : (dj >= dk ? atoms.y : atoms.z);
    }
    case PatchKind::None: break;
  }
  return ~0u;
}

Bounds3d ScenePatches::bounds() const {
  Bounds3d b;
  for (const auto& s : spheres) b.extend(trace::bounds(s));
  for (const auto& t : tori) b.extend(trace::bounds(t));
  for (const auto& c : concave) b.extend(trace::bounds(c));
  return b;
}

SceneHit ScenePatches::intersectPatch(PatchKind kind, std::uint32_t patch, const Ray& ray, double tMin, double tMax) const {
  std::optional<PatchHit> h;
  switch (kind) {
    case PatchKind::Convex: h = intersect(spheres[patch], ray, tMin, tMax); break;
    case PatchKind::Toroidal: h = intersect(tori[patch], ray, tMin, tMax); break;
    case PatchKind::Concave: h = intersect(concave[patch], ray, tMin, tMax); break;
    case PatchKind::None: break;
  }
  if (!h) return {};
  return SceneHit{kind, patch, *h};
}

SceneHit ScenePatches::intersectAll(const Ray& ray, double tMin, double tMax) const {
  SceneHit best;
  auto consider = [&](PatchKind kind, std::uint32_t i, const std::optional<PatchHit>& h) {
    if (h && h->t <= tMax) {
      best = SceneHit{kind, i, *h};
      tMax = h->t;
    }
  };
  for (std::uint32_t i = 0; i < spheres.size(); ++i) consider(PatchKind::Convex, i, intersect(spheres[i], ray, tMin, tMax));
  for (std::uint32_t i = 0; i < tori.size(); ++i) consider(PatchKind::Toroidal, i, intersect(tori[i], ray, tMin, tMax));
  for (std::uint32_t i = 0; i < concave.size(); ++i) consider(PatchKind::Concave, i, intersect(concave[i], ray, tMin, tMax));
  return best;
}

// ---------------------------------------------------------------------------------------
// PatchScene

struct PatchScene::Embree {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  PatchKind kindOfGeometry[3] = {PatchKind::None, PatchKind::None, PatchKind::None};
  std::mutex errorMutex;
  std::string error;

  ~Embree() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
  // Embree reports errors through this callback; the owner checks after each commit.
  static void onError(void* self, RTCError code, const char* message) {
    auto* e = static_cast<Embree*>(self);
    std::lock_guard lock(e->errorMutex);
    if (e->error.empty()) e->error = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
  }
  void check(const char* what) {
    std::lock_guard lock(errorMutex);
    if (!error.empty()) throw std::runtime_error(std::string(what) + ": " + error);
  }
  template <class Patch> void add(const std::vector<Patch>& patches, PatchKind kind) {
    if (patches.empty()) return;
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(patches.size()));
    rtcSetGeometryUserData(g, const_cast<Patch*>(patches.data()));
    rtcSetGeometryBoundsFunction(g, boundsFn<Patch>, nullptr);
    rtcSetGeometryIntersectFunction(g, intersectFn<Patch>);
    rtcSetGeometryOccludedFunction(g, occludedFn<Patch>);
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    check("creating the Embree geometry");
    kindOfGeometry[id] = kind;
  }
};

PatchScene::PatchScene(ScenePatches patches) : patches_(std::move(patches)), embree_(std::make_unique<Embree>()) {
  const auto start = std::chrono::steady_clock::now();
  if (patches_.size() >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("scene: too many patches for 32-bit ids");
  embree_->device = rtcNewDevice(nullptr);
  if (!embree_->device) throw std::runtime_error("Embree: cannot create a device (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
  rtcSetDeviceErrorFunction(embree_->device, &Embree::onError, embree_.get());
  embree_->scene = rtcNewScene(embree_->device);
  rtcSetSceneBuildQuality(embree_->scene, RTC_BUILD_QUALITY_HIGH);
  embree_->add(patches_.spheres, PatchKind::Convex);
  embree_->add(patches_.tori, PatchKind::Toroidal);
  embree_->add(patches_.concave, PatchKind::Concave);
  rtcCommitScene(embree_->scene);
  embree_->check("building the Embree scene");
  buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

PatchScene::~PatchScene() = default;

namespace {
// GCC 12.2 at -O2/-O3 miscompiles six double→float→double round trips written side by side:
// its SLP vectoriser converted org and dir.x and copied dir.y, dir.z through unrounded
// (seen in the assembly; caught by PatchScene.MatchesAPlainLoopOverAllPatches as 7e-7 Å
// depth differences). The empty asm makes each rounding opaque to the vectoriser; the
// build also passes -fno-tree-slp-vectorize to GCC 12 (CMakeLists.txt).
double toFloatPrecision(double v) {
  float f = static_cast<float>(v);
  asm("" : "+x"(f));
  return static_cast<double>(f);
}
}  // namespace

Ray PatchScene::embreeRay(const Ray& r) {
  Ray out;
  for (int k = 0; k < 3; ++k) {
    out.org[k] = toFloatPrecision(r.org[k]);
    out.dir[k] = toFloatPrecision(r.dir[k]);
  }
  return out;
}

void PatchScene::intersect16(const Ray (&rays)[16], const bool (&valid)[16], double tMin, SceneHit (&hits)[16]) const {
  alignas(64) int mask[16];
  alignas(64) RTCRayHit16 rh;
  for (int i = 0; i < 16; ++i) {
    mask[i] = valid[i] ? -1 : 0;
    rh.ray.org_x[i] = static_cast<float>(rays[i].org.x);
    rh.ray.org_y[i] = static_cast<float>(rays[i].org.y);
    rh.ray.org_z[i] = static_cast<float>(rays[i].org.z);
    rh.ray.dir_x[i] = static_cast<float>(rays[i].dir.x);
    rh.ray.dir_y[i] = static_cast<float>(rays[i].dir.y);
    rh.ray.dir_z[i] = static_cast<float>(rays[i].dir.z);
    rh.ray.tnear[i] = static_cast<float>(tMin);
    rh.ray.tfar[i] = kInfF;
    rh.ray.time[i] = 0.0f;
    rh.ray.mask[i] = ~0u;
    rh.ray.id[i] = static_cast<unsigned>(i);
    rh.ray.flags[i] = 0;
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
  PatchHit exact[16];
  HitContext context;
  rtcInitIntersectContext(&context.embree);
  context.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  context.hits = exact;
  rtcIntersect16(mask, embree_->scene, &context.embree, &rh);
  for (int i = 0; i < 16; ++i) {
    hits[i] = {};
    if (!valid[i] || rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
    hits[i] = SceneHit{embree_->kindOfGeometry[rh.hit.geomID[i]], rh.hit.primID[i], exact[i]};
  }
}

SceneHit PatchScene::intersect1(const Ray& ray, double tMin, double tMax) const {
  RTCRayHit rh;
  rh.ray.org_x = static_cast<float>(ray.org.x);
  rh.ray.org_y = static_cast<float>(ray.org.y);
  rh.ray.org_z = static_cast<float>(ray.org.z);
  rh.ray.dir_x = static_cast<float>(ray.dir.x);
  rh.ray.dir_y = static_cast<float>(ray.dir.y);
  rh.ray.dir_z = static_cast<float>(ray.dir.z);
  rh.ray.tnear = static_cast<float>(tMin);
  rh.ray.tfar = tMax >= static_cast<double>(std::numeric_limits<float>::max()) ? kInfF : static_cast<float>(tMax);
  rh.ray.time = 0.0f;
  rh.ray.mask = ~0u;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  PatchHit exact;
  HitContext context;
  rtcInitIntersectContext(&context.embree);
  context.hits = &exact;
  rtcIntersect1(embree_->scene, &context.embree, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {};
  return SceneHit{embree_->kindOfGeometry[rh.hit.geomID], rh.hit.primID, exact};
}

bool PatchScene::occluded(const Ray& ray, double tMin, double tMax) const {
  RTCRay r;
  r.org_x = static_cast<float>(ray.org.x);
  r.org_y = static_cast<float>(ray.org.y);
  r.org_z = static_cast<float>(ray.org.z);
  r.dir_x = static_cast<float>(ray.dir.x);
  r.dir_y = static_cast<float>(ray.dir.y);
  r.dir_z = static_cast<float>(ray.dir.z);
  r.tnear = static_cast<float>(tMin);
  r.tfar = tMax >= static_cast<double>(std::numeric_limits<float>::max()) ? kInfF : static_cast<float>(tMax);
  r.time = 0.0f;
  r.mask = ~0u;
  r.id = 0;
  r.flags = 0;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcOccluded1(embree_->scene, &context, &r);
  return r.tfar == -kInfF;
}

}  // namespace surftrace::trace
