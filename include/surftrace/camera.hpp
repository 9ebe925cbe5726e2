// Stage "camera": a camera framed on a surface (or on spheres that hold it, piece by piece
// along a trajectory), or given whole (GL matrices, the JSON of `--camera-out`).
#pragma once

#include <optional>
#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "surftrace/molecule.hpp"
#include "surftrace/surface.hpp"
#include "view/camera.hpp"

namespace surftrace {

using view::Camera;
using view::Projection;
using view::SphereFraming;
using view::cameraFromJson;       // the JSON of `--camera-out` -> a camera
using view::cameraFromMatrices;   // GL view and projection matrices -> a camera
using view::cameraToJson;
using view::namedViewDirection;   // "front", "back", "left", ... -> a view direction

// How a camera is framed. The base camera given with it holds the image size, the projection
// and the field of view; framing chooses the eye, the look-at point and the depth range.
struct Framing {
  glm::dvec3 direction{0.0, 0.0, -1.0};  // the view direction (namedViewDirection)
  // Overrides applied after framing (--eye, --look-at, --up).
  std::optional<glm::dvec3> eye, lookAt, up;
  // A camera given whole (--camera): used as it is, no framing; only a depth range it lacks
  // is taken from what the scene reaches.
  std::optional<Camera> fixed;
};

// The camera framed on what `patches` can reach (build::SurfaceRequest::reach about the atoms
// of `molecule`; the skin also by its patches' balls, the tighter along each axis). `molecule`
// may be empty (a patch list alone): the skin is then framed by its patches, the SES, SAS and
// vdW spheres by their convex patches (their atoms reach furthest). Throws
// std::invalid_argument when there is nothing to frame.
Camera frameSurface(const Camera& base, const Framing& framing, const PatchList& patches, const Molecule& molecule);
// The camera framed on spheres (`centers`, `reach`: how far the surface reaches from each).
Camera frameSpheres(const Camera& base, const Framing& framing, std::span<const glm::dvec3> centers,
                    std::span<const double> reach);
// Spheres that come in pieces (every frame of a trajectory): add them to sphereFraming(...) or
// to copies of it, merge, and frame the camera on the result.
SphereFraming sphereFraming(const Camera& base, const Framing& framing);
Camera frameSpheres(const Camera& base, const Framing& framing, const SphereFraming& spheres);

// A camera from the JSON file `path` (`--camera-out`'s); errors name `name` (default: the path).
Camera readCamera(const std::string& path, const std::string& name = {});
// The camera's JSON to `path`, whole or not at all.
void writeCamera(const std::string& path, const Camera& camera);

}  // namespace surftrace
