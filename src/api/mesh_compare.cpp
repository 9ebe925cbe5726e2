// Meshes as `compare`'s test (surftrace/compare.hpp): one reference's view, or the exact surface
// all around from views spread over the sphere, with each hit's distance to the other surface.
#include "surftrace/compare.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include "surftrace/camera.hpp"
#include "surftrace/engine.hpp"
#include "build/mesh/surface_distance.hpp"
#include "trace/mesh_scene.hpp"
#include "view/shading.hpp"

namespace surftrace {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string meshDescription(const TriangleMesh& mesh) {
  return "a mesh of " + std::to_string(mesh.vertexCount()) + " vertices and " + std::to_string(mesh.triangleCount()) +
         " triangles (" + (mesh.normals.empty() ? "face normals" : "its vertex normals") +
         "), drawn along the reference's rays (Embree triangles, distances in double)";
}

view::DrawnTest drawn(const trace::MeshScene& scene, const view::Camera& camera) {
  view::DrawnTest t;
  t.frame = trace::drawMesh(scene, camera);
  t.frame.patchId.assign(t.frame.pixels(), ~0u);  // triangles are no patches: not compared, not shown as ids
  t.carried = view::TestChannels{true, false, false, false};
  t.description = meshDescription(scene.mesh());
  return t;
}

// `n` directions spread evenly over the sphere: the Fibonacci lattice (González, "Measurement of
// areas on a sphere using Fibonacci and latitude–longitude lattices") that ambient occlusion uses.
std::vector<glm::dvec3> sphereDirections(int n) {
  std::vector<glm::dvec3> d;
  for (int i = 0; i < n; ++i) d.push_back(view::fibonacciSphere(i, n));
  return d;
}

// The squared Euclidean distance (pixels) from every pixel to the nearest `site` pixel, and which
// one (index; ~0 where there is none): Felzenszwalb and Huttenlocher, "Distance Transforms of
// Sampled Functions", by columns and then by rows, each a lower envelope of parabolas.
struct NearestSite {
  std::vector<double> d2;
  std::vector<std::size_t> site;
};
void envelope1d(const std::vector<double>& f, std::vector<double>& d, std::vector<int>& arg) {
  const int n = static_cast<int>(f.size());
  std::vector<int> v(static_cast<std::size_t>(n));
  std::vector<double> z(static_cast<std::size_t>(n) + 1);
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (!std::isfinite(f[static_cast<std::size_t>(q)])) continue;
    double s = -kInf;
    while (k >= 0) {
      const int p = v[static_cast<std::size_t>(k)];
      s = ((f[static_cast<std::size_t>(q)] + double(q) * q) - (f[static_cast<std::size_t>(p)] + double(p) * p)) / (2.0 * (q - p));
      if (s > z[static_cast<std::size_t>(k)]) break;
      --k;
    }
    ++k;
    v[static_cast<std::size_t>(k)] = q;
    z[static_cast<std::size_t>(k)] = k == 0 ? -kInf : s;
    z[static_cast<std::size_t>(k) + 1] = kInf;
  }
  d.assign(static_cast<std::size_t>(n), kInf);
  arg.assign(static_cast<std::size_t>(n), -1);
  if (k < 0) return;
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z[static_cast<std::size_t>(j) + 1] < q) ++j;
    const int p = v[static_cast<std::size_t>(j)];
    d[static_cast<std::size_t>(q)] = double(q - p) * (q - p) + f[static_cast<std::size_t>(p)];
    arg[static_cast<std::size_t>(q)] = p;
  }
}
NearestSite nearestSites(const std::vector<std::uint8_t>& isSite, int w, int h) {
  const auto at = [w](int x, int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x); };
  std::vector<double> colD(isSite.size(), kInf);
  std::vector<int> colArg(isSite.size(), -1);
  std::vector<double> f, d;
  std::vector<int> arg;
  for (int x = 0; x < w; ++x) {
    f.assign(static_cast<std::size_t>(h), kInf);
    for (int y = 0; y < h; ++y)
      if (isSite[at(x, y)]) f[static_cast<std::size_t>(y)] = 0.0;
    envelope1d(f, d, arg);
    for (int y = 0; y < h; ++y) colD[at(x, y)] = d[static_cast<std::size_t>(y)], colArg[at(x, y)] = arg[static_cast<std::size_t>(y)];
  }
  NearestSite out{std::vector<double>(isSite.size(), kInf), std::vector<std::size_t>(isSite.size(), ~std::size_t{0})};
  for (int y = 0; y < h; ++y) {
    f.assign(static_cast<std::size_t>(w), kInf);
    for (int x = 0; x < w; ++x) f[static_cast<std::size_t>(x)] = colD[at(x, y)];
    envelope1d(f, d, arg);
    for (int x = 0; x < w; ++x) {
      const int sx = arg[static_cast<std::size_t>(x)];
      if (sx < 0) continue;
      out.d2[at(x, y)] = d[static_cast<std::size_t>(x)];
      out.site[at(x, y)] = at(sx, colArg[at(sx, y)]);
    }
  }
  return out;
}

double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0.0;
  const std::size_t k = static_cast<std::size_t>(std::llround(q * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}
DistanceFigures figuresOf(std::vector<double>& v) {
  DistanceFigures f;
  f.samples = v.size();
  if (v.empty()) return f;
  f.max = *std::max_element(v.begin(), v.end());
  f.median = quantile(v, 0.5);
  f.p99 = quantile(v, 0.99);
  return f;
}

// A candidate for the worst places: kept per view, the largest few.
struct Candidate {
  double distance;
  int view;
  std::size_t pixel;
  int what;  // 0 mesh -> exact, 1 exact -> mesh, 2 mesh -> exact (silhouette), 3 exact -> mesh (silhouette)
  glm::dvec3 point;
  std::uint32_t atom;
};
constexpr const char* kWhat[] = {"mesh -> exact", "exact -> mesh", "mesh -> exact (silhouette)", "exact -> mesh (silhouette)"};
constexpr std::size_t kCandidatesPerView = 64;
constexpr std::size_t kWorstPlaces = 10;
constexpr double kPlaceSeparation = 1.0;  // Å between two places reported: one spot is one place
// The distance estimates take rays within 45° of the normal (MeshViewsResult), which sample a
// surface at nearly even spacing; 26 views spread over the sphere see every outward normal
// within 31° of one (14 views: 42°).
constexpr double kEstimateCosine = 0.70710678118654752;

}  // namespace

CompareTest meshTest(const std::string& name, const TriangleMesh& mesh, const CompareReference& reference) {
  if (!reference.camera)
    throw std::invalid_argument(reference.name + " records no camera (surftrace:camera metadata), and a mesh is drawn along "
                                "the reference camera's rays: render the reference with surftrace render --exr");
  const trace::MeshScene scene(mesh);
  CompareTest t;
  t.name = name;
  t.drawn = drawn(scene, *reference.camera);
  return t;
}

CompareTest readMeshTest(const std::string& path, const CompareReference& reference, const std::optional<glm::dmat4>& transform) {
  TriangleMesh mesh = readMesh(path);
  if (transform) transformMesh(mesh, *transform);
  CompareTest t = meshTest(path, mesh, reference);
  if (transform) t.drawn->details = "          moved by --mesh-transform\n";
  return t;
}

MeshViewsResult compareMeshViews(const TriangleMesh& mesh, const PatchList& patches, const Molecule& molecule,
                                 const MeshViewsSettings& settings) {
  if (settings.views < 1) throw std::invalid_argument("--views must be at least 1");
  if (settings.width < 1 || settings.height < 1) throw std::invalid_argument("the views' image size must be at least 1x1");
  const auto start = std::chrono::steady_clock::now();
  MeshViewsResult r;
  r.views = settings.views, r.width = settings.width, r.height = settings.height;
  r.directions = sphereDirections(settings.views);
  const trace::MeshScene scene(mesh);
  const std::unique_ptr<build::mesh::SurfaceDistance> field = build::mesh::makeSurfaceDistance(patches, molecule.centers, molecule.radii);
  const std::unique_ptr<Engine> engine = makeEngine({});
  std::vector<std::size_t> pixelsPerKind(view::kPatchKindCount + 1, 0);
  std::vector<view::KindValue> kindDepth, kindNormal;
  std::vector<double> alongRay, meshToExact, exactToMesh;
  std::vector<Candidate> candidates;
  for (int v = 0; v < settings.views; ++v) {
    Camera base;
    base.projection = Projection::Orthographic;
    base.width = settings.width, base.height = settings.height;
    Framing framing;
    framing.direction = r.directions[static_cast<std::size_t>(v)];
    const Camera camera = frameSurface(base, framing, patches, molecule);
    RenderOptions options;
    options.camera = camera;
    options.referenceMasks = true;  // exact silhouette and seam masks, as a reference EXR records them
    const FrameBuffers ref = engine->render(Frame{&patches, molecule.centers, molecule.radii, {}, nullptr, options});
    const FrameBuffers test = trace::drawMesh(scene, camera);
    view::FrameSamples samples;
    const view::TestChannels carried{true, false, false, false};
    const view::FrameComparison c = view::compareFrames(test, ref, &camera, carried, &samples);
    r.pixels += c.pixels, r.referenceHits += c.referenceHits, r.silhouette += c.silhouette;
    r.coverageMismatch += c.coverageMismatch;
    for (const std::uint32_t k : ref.kind)
      if (k != 0 && k <= view::kPatchKindCount) ++pixelsPerKind[k];
    const Camera::Frame f = camera.frame();
    const auto rayOf = [&](std::size_t p) {
      return f.ray(static_cast<double>(p % static_cast<std::size_t>(ref.width)) + 0.5,
                   static_cast<double>(p / static_cast<std::size_t>(ref.width)) + 0.5);
    };
    std::vector<Candidate> mine;
    // Each sample's two distances (−1: not estimated), projected in parallel: the exact
    // surface's nearest point and the mesh's nearest triangle are the costly part.
    const std::size_t n = samples.depth.size();
    std::vector<double> m2e(n, -1.0), e2m(n, -1.0);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      const view::FrameSamples::Depth& s = samples.depth[i];
      const view::Ray ray = rayOf(s.pixel);
      const glm::dvec3 nExact(ref.normal[3 * s.pixel], ref.normal[3 * s.pixel + 1], ref.normal[3 * s.pixel + 2]);
      const glm::uvec3 tri = mesh.triangles[test.patchId[s.pixel]];
      const glm::dvec3 face = glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x], mesh.positions[tri.z] - mesh.positions[tri.x]);
      const double faceLength = glm::length(face), exactLength = glm::length(nExact);
      const double d = std::abs(s.signedError);
      const double cosExact = exactLength > 0.0 ? std::abs(glm::dot(nExact / exactLength, ray.dir)) : 0.0;
      const double cosFace = faceLength > 0.0 ? std::abs(glm::dot(face / faceLength, ray.dir)) : 0.0;
      // Only rays within 45° of the normal give estimates: they sample each surface at about
      // even spacing, and with views spread over the sphere every part of it is seen so in some view.
      const bool exactFacing = cosExact >= kEstimateCosine, meshFacing = cosFace >= kEstimateCosine;
      if (!exactFacing && !meshFacing) return;
      const glm::dvec3 xExact = ray.org + static_cast<double>(ref.depth[s.pixel]) * ray.dir;
      const glm::dvec3 xMesh = ray.org + static_cast<double>(test.depth[s.pixel]) * ray.dir;
      // Each point's distance to the other surface, by projecting it there rather than along the
      // ray (a depth difference at a slant is no distance): |d| bounds both, as the other point
      // lies on the other surface, and keeps the mesh's search local. The exact surface's nearest
      // point is exact within the field's reach (an upper bound beyond), the nearest triangle exact.
      if (exactFacing) m2e[i] = std::min(d, glm::length(field->closest(xMesh).point - xMesh));
      if (meshFacing) e2m[i] = std::min(d, scene.distance(xExact, d));
    });
    for (std::size_t i = 0; i < n; ++i) {
      const view::FrameSamples::Depth& s = samples.depth[i];
      alongRay.push_back(std::abs(s.signedError));
      kindDepth.push_back({ref.kind[s.pixel], s.signedError});
      if (m2e[i] < 0.0 && e2m[i] < 0.0) continue;
      const view::Ray ray = rayOf(s.pixel);
      const glm::dvec3 xExact = ray.org + static_cast<double>(ref.depth[s.pixel]) * ray.dir;
      if (m2e[i] >= 0.0) {
        meshToExact.push_back(m2e[i]);
        mine.push_back({m2e[i], v, s.pixel, 0, xExact, ref.atomId[s.pixel]});
      }
      if (e2m[i] >= 0.0) {
        exactToMesh.push_back(e2m[i]);
        mine.push_back({e2m[i], v, s.pixel, 1, xExact, ref.atomId[s.pixel]});
      }
    }
    for (const view::FrameSamples::Depth& s : samples.normal) kindNormal.push_back({ref.kind[s.pixel], s.signedError});
    // Where one is hit and the other not (outside the band), a point's distance to the other
    // surface is at least its distance across the image to the other's outline (an orthographic
    // projection never lengthens a distance), which the nearest hit pixel centre gives to within
    // half a pixel's diagonal.
    if (!samples.coverage.empty()) {
      std::vector<std::uint8_t> refHit(ref.pixels()), meshHit(ref.pixels());
      for (std::size_t p = 0; p < ref.pixels(); ++p) refHit[p] = ref.kind[p] != 0, meshHit[p] = std::isfinite(test.depth[p]);
      const NearestSite toRef = nearestSites(refHit, ref.width, ref.height);
      const NearestSite toMesh = nearestSites(meshHit, ref.width, ref.height);
      const double footprint = camera.pixelFootprint(1.0), slack = 0.5 * std::sqrt(2.0) * footprint;
      for (const std::size_t p : samples.coverage) {
        const view::Ray ray = rayOf(p);
        if (meshHit[p]) {
          ++r.meshOnly;
          if (!std::isfinite(toRef.d2[p])) continue;
          const double lower = std::max(0.0, std::sqrt(toRef.d2[p]) * footprint - slack);
          meshToExact.push_back(lower);
          mine.push_back({lower, v, p, 2, ray.org + static_cast<double>(test.depth[p]) * ray.dir, ref.atomId[toRef.site[p]]});
        } else {
          ++r.exactOnly;
          if (!std::isfinite(toMesh.d2[p])) continue;
          const double lower = std::max(0.0, std::sqrt(toMesh.d2[p]) * footprint - slack);
          exactToMesh.push_back(lower);
          mine.push_back({lower, v, p, 3, ray.org + static_cast<double>(ref.depth[p]) * ray.dir, ref.atomId[p]});
        }
      }
    }
    const std::size_t keep = std::min(kCandidatesPerView, mine.size());
    std::partial_sort(mine.begin(), mine.begin() + static_cast<std::ptrdiff_t>(keep), mine.end(),
                      [](const Candidate& a, const Candidate& b) { return a.distance > b.distance; });
    candidates.insert(candidates.end(), mine.begin(), mine.begin() + static_cast<std::ptrdiff_t>(keep));
    if (settings.progress) settings.progress(static_cast<std::size_t>(v) + 1, static_cast<std::size_t>(settings.views));
  }
  r.depthSamples = alongRay.size();
  r.alongRay = figuresOf(alongRay);
  r.meshToExact = figuresOf(meshToExact);
  r.exactToMesh = figuresOf(exactToMesh);
  r.perKind = view::kindErrors(pixelsPerKind, kindDepth, kindNormal);
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) { return a.distance > b.distance; });
  for (const Candidate& c : candidates) {
    if (r.worst.size() >= kWorstPlaces || !(c.distance > 0.0)) break;
    bool near = false;
    for (const MeshPlace& w : r.worst) near = near || glm::length(w.point - c.point) < kPlaceSeparation;
    if (near) continue;
    r.worst.push_back({c.point, c.atom, c.distance, kWhat[c.what], c.view, static_cast<int>(c.pixel % static_cast<std::size_t>(r.width)),
                       static_cast<int>(c.pixel / static_cast<std::size_t>(r.width))});
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

double MeshViewsResult::error(bool useMax) const {
  return useMax ? std::max(meshToExact.max, exactToMesh.max) : std::max(meshToExact.p99, exactToMesh.p99);
}

std::string MeshViewsResult::summary() const {
  char text[640];
  std::string out;
  std::snprintf(text, sizeof text, "views     %d directions spread over the sphere, orthographic %dx%d, framed tightly (%.1f s)\n",
                views, width, height, seconds);
  out += text;
  const std::size_t judged = pixels - silhouette;
  std::snprintf(text, sizeof text,
                "coverage  mismatch %zu of %zu px (%.4f%%): mesh only %zu, exact only %zu (silhouette bands, %zu px, masked)\n",
                coverageMismatch, judged, judged > 0 ? 100.0 * static_cast<double>(coverageMismatch) / static_cast<double>(judged) : 0.0,
                meshOnly, exactOnly, silhouette);
  out += text;
  auto row = [&](const char* name, const DistanceFigures& f, const char* what) {
    if (f.samples == 0) {
      std::snprintf(text, sizeof text, "%s none measured\n", name);
    } else {
      std::snprintf(text, sizeof text, "%s median %.4g  p99 %.4g  max %.4g Å (%zu rays; %s)\n", name, f.median, f.p99, f.max,
                    f.samples, what);
    }
    out += text;
  };
  row("along ray    ", alongRay, "|t_mesh − t_exact| where both are hit: an upper bound of each point's distance");
  row("mesh -> exact", meshToExact, "to the exact surface's nearest point, rays within 45° of it; or across the outline");
  row("exact -> mesh", exactToMesh, "to the mesh's nearest triangle, rays within 45° of it; or across the outline");
  out += view::kindTableText(perKind, true, "exact surface", "mesh − exact");
  if (!worst.empty()) {
    out += "\nworst places (x, y, z Å; atom index from 0 in file order; view and pixel):";
    for (const MeshPlace& w : worst) {
      std::snprintf(text, sizeof text, "\n  %.4g Å  %-27s (%.3f, %.3f, %.3f)  atom %s  view %d (%d, %d)", w.distance, w.what.c_str(),
                    w.point.x, w.point.y, w.point.z, w.atom == ~0u ? "?" : std::to_string(w.atom).c_str(), w.view, w.x, w.y);
      out += text;
    }
  }
  return out;
}

std::string MeshViewsResult::json() const {
  nlohmann::json j;
  j["views"] = {{"count", views}, {"width", width}, {"height", height}, {"projection", "orthographic"}};
  nlohmann::json dirs = nlohmann::json::array();
  for (const glm::dvec3& d : directions) dirs.push_back({d.x, d.y, d.z});
  j["views"]["directions"] = dirs;
  j["pixels"] = pixels;
  j["reference_hits"] = referenceHits;
  j["silhouette_band"] = silhouette;
  j["coverage"] = {{"mismatch", coverageMismatch}, {"mesh_only", meshOnly}, {"exact_only", exactOnly}};
  auto fig = [](const DistanceFigures& f) {
    return nlohmann::json{{"samples", f.samples}, {"median", f.median}, {"p99", f.p99}, {"max", f.max}, {"unit", "Å"}};
  };
  j["along_ray"] = fig(alongRay);
  j["mesh_to_exact"] = fig(meshToExact);
  j["exact_to_mesh"] = fig(exactToMesh);
  j["per_kind"] = nlohmann::json::parse(view::kindTableJson(perKind, true, "mesh − exact"));
  nlohmann::json places = nlohmann::json::array();
  for (const MeshPlace& w : worst)
    places.push_back({{"point", {w.point.x, w.point.y, w.point.z}},
                      {"atom", w.atom == ~0u ? nlohmann::json(nullptr) : nlohmann::json(w.atom)},
                      {"distance", w.distance},
                      {"what", w.what},
                      {"view", w.view},
                      {"pixel", {w.x, w.y}}});
  j["worst_places"] = places;
  j["seconds"] = seconds;
  return j.dump(1);
}

}  // namespace surftrace
