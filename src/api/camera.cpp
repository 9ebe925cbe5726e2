// Stage "camera" (surftrace/camera.hpp).
#include "surftrace/camera.hpp"

#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "build/io/output_file.hpp"
#include "build/io/text_fields.hpp"
#include "build/mss/mss_area.hpp"

namespace surftrace {
namespace {

// The end of every framing: the fixed camera, or the framed one with the explicit eye, look-at
// point and up vector; and a depth range from the spheres that hold the scene.
Camera finish(Camera camera, const Framing& framing, std::span<const view::SphereCover> covers) {
  if (framing.fixed) {
    camera = *framing.fixed;
  } else {
    if (framing.lookAt) camera.lookAt = *framing.lookAt;
    if (framing.eye) camera.eye = *framing.eye;
    if (framing.up) camera.up = *framing.up;
    camera.validate();
  }
  if (!camera.hasDepthRange()) camera = view::withDepthRange(camera, covers);
  camera.validate();
  return camera;
}

// The skin's patches' bounding balls, less those of sliver cells: a patch of a near-degenerate
// simplex whose cell is a sliver (build::mssPatchIsNegligible: four nearly co-spherical atoms)
// holds next to no skin, but its ball about a far, ill-conditioned orthocentre would move the
// view. A list of nothing but slivers (not one the builder writes) keeps them all.
void skinPatchBalls(const PatchList& list, std::vector<glm::dvec3>& centers, std::vector<double>& radii) {
  centers.reserve(list.mss.size());
  radii.reserve(list.mss.size());
  for (std::size_t k = 0; k < list.mss.size(); ++k) {
    if (build::mssPatchIsNegligible(list, k)) continue;
    centers.push_back(list.mss.center[k]);
    radii.push_back(list.mss.boundRadius[k]);
  }
  if (centers.empty()) {
    centers = list.mss.center;
    radii = list.mss.boundRadius;
  }
}

}  // namespace

Camera frameSurface(const Camera& base, const Framing& framing, const PatchList& list, const Molecule& molecule) {
  const SurfaceRequest request = SurfaceRequest::of(list.params);
  if (list.params.surface != SurfaceKind::Mss) {
    // The SES, SAS and vdW spheres reach request.reach(r) from their atoms; without the
    // structure, from the convex patches' atoms, which reach furthest (a buried atom's extended
    // sphere lies inside the others').
    const bool alone = molecule.centers.empty();
    if (alone && list.convex.size() == 0) throw std::invalid_argument("the patch list has no convex patches to frame");
    const std::span<const glm::dvec3> centers = alone ? std::span<const glm::dvec3>(list.convex.center) : molecule.centers;
    const std::vector<double> reach = request.reach(alone ? std::span<const double>(list.convex.radius) : molecule.radii);
    return frameSpheres(base, framing, centers, reach);
  }
  // Two bounds of the skin, each loose somewhere: its patches' balls (tight for s near 1, but
  // for small s a hyperboloid's ball grows as r/√s), and the hull of the atom centres grown by
  // the largest radius (SurfaceRequest::reach; tight as s -> 0). A patch list read without its
  // structure has the first alone. The tighter of the two is taken along each axis.
  std::vector<glm::dvec3> centers;
  std::vector<double> radii;
  skinPatchBalls(list, centers, radii);
  const view::SphereCover patches{centers, radii};
  Camera camera = base;
  if (molecule.centers.empty()) {
    if (!framing.fixed) camera = view::frameSphereCovers(camera, {&patches, 1}, framing.direction);
    return finish(camera, framing, {&patches, 1});
  }
  const std::vector<double> grown = request.reach(molecule.radii);
  const view::SphereCover covers[] = {patches, {molecule.centers, grown}};
  if (!framing.fixed) camera = view::frameSphereCovers(camera, covers, framing.direction);
  return finish(camera, framing, covers);
}

Camera frameSpheres(const Camera& base, const Framing& framing, std::span<const glm::dvec3> centers,
                    std::span<const double> reach) {
  Camera camera = base;
  if (!framing.fixed) camera = view::frameSpheres(camera, centers, reach, framing.direction);
  const view::SphereCover cover{centers, reach};
  return finish(camera, framing, {&cover, 1});
}

SphereFraming sphereFraming(const Camera& base, const Framing& framing) { return SphereFraming(base, framing.direction); }

Camera frameSpheres(const Camera& base, const Framing& framing, const SphereFraming& spheres) {
  Camera camera = base;
  if (!framing.fixed) camera = spheres.frame(camera);
  // Every sphere lies in the framing's box: its corners bound the depth range.
  const std::vector<glm::dvec3> corners = spheres.boxCorners();
  const std::vector<double> zero(corners.size(), 0.0);
  const view::SphereCover cover{corners, zero};
  return finish(camera, framing, {&cover, 1});
}

Camera readCamera(const std::string& path, const std::string& name) {
  const std::string text = build::text::readTextFile(path, path);
  try {
    return cameraFromJson(text);
  } catch (const std::exception& e) {
    throw std::invalid_argument((name.empty() ? path : name) + ": " + e.what());
  }
}

void writeCamera(const std::string& path, const Camera& camera) {
  const auto json = nlohmann::json::parse(cameraToJson(camera));
  build::writeFileAtomically(path, json.dump(2) + "\n");
}

}  // namespace surftrace
