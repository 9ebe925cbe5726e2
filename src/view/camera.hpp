// The camera: pixel-centre rays in double precision, automatic framing, named views.
#pragma once

#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "view/ray.hpp"

namespace surftrace::view {

enum class Projection { Perspective, Orthographic };

// Everything another renderer needs to reproduce a view exactly; written into every
// output's metadata (cameraToJson). Pixel (x, y), x to the right and y down, has its
// centre at (x + 0.5, y + 0.5); the ray through image point (sx, sy) is
//   perspective:  org = eye, dir = normalize(forward + (2 sx/W − 1)·tan(fovY/2)·aspect·right
//                                            − (2 sy/H − 1)·tan(fovY/2)·up')
//   orthographic: org = eye + (2 sx/W − 1)·(orthoHeight/2)·aspect·right
//                           − (2 sy/H − 1)·(orthoHeight/2)·up', dir = forward
// with forward = normalize(lookAt − eye), right = normalize(forward × up),
// up' = right × forward, aspect = W/H.
struct Camera {
  Projection projection = Projection::Perspective;
  glm::dvec3 eye{0.0, 0.0, 10.0};
  glm::dvec3 lookAt{0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  double fovY = 30.0;         // degrees, perspective
  double orthoHeight = 10.0;  // Å, orthographic
  int width = 512;
  int height = 512;

  glm::dvec3 forward() const;
  glm::dvec3 right() const;
  glm::dvec3 trueUp() const;
  // The ray through image point (sx, sy) in pixel units; its dir is unit.
  Ray ray(double sx, double sy) const;
  // Footprint of one pixel at ray distance t (ORACLES D.4): 2 t tan(fovY/2)/H or orthoHeight/H.
  double pixelFootprint(double t) const;
  // The view frame and scale factors, computed once per frame: ray() recomputes them on
  // every call, which costs a tan, three normalisations and two cross products per ray.
  struct Frame {
    glm::dvec3 eye, forward, right, up;
    double scaleX, scaleY, invWidth, invHeight;
    bool perspective;
    // Bit-identical to Camera::ray(sx, sy).
    Ray ray(double sx, double sy) const;
  };
  Frame frame() const;
  // Throws std::invalid_argument naming the bad field (zero size, eye == lookAt, up
  // parallel to the view direction, fov outside (0, 180), non-finite values).
  void validate() const;
};

// The view direction (from the eye towards the molecule) named by `view`: front (−z),
// back (+z), left (+x), right (−x), top (−y), bottom (+y), or "x,y,z". Throws
// std::invalid_argument with the accepted names on anything else.
glm::dvec3 namedViewDirection(const std::string& view);

// How much room automatic framing leaves around what it frames (frameSpheres).
inline constexpr double kFramingMargin = 1.05;

// What framing needs to know of spheres seen along one direction, gathered a sphere at a time
// (add) and from several sets (merge): their extent in the view frame, which fixes the look-at
// point, and per side of the image the largest (|offset| + r·sqrt(1 + h²))/h − depth of the
// perspective fit, kept relative to the origin so that the eye distance follows once the
// look-at point is known. Only min and max: the camera does not depend on the order in which
// the spheres come, so a parallel reduction over the frames of a trajectory is deterministic,
// and frames every sphere of every frame exactly as frameSpheres frames them all at once.
class SphereFraming {
 public:
  // The fit depends on the camera's projection, fovY and size, which frame() keeps.
  SphereFraming(const Camera& camera, const glm::dvec3& direction, double margin = kFramingMargin);
  void add(const glm::dvec3& center, double radius);
  void merge(const SphereFraming& other);
  bool empty() const { return !(lo_[0] <= hi_[0]); }
  // `camera` (the one given to the constructor) framed on every sphere added; see frameSpheres.
  // std::invalid_argument when none was.
  Camera frame(Camera camera) const;
  // The look-at point and up (and for an orthographic camera the window and the eye) of frame().
  Camera aim(Camera camera) const;

 private:
  glm::dvec3 right_, up_, forward_;
  double hx_ = 0.0, hy_ = 0.0;  // tangents of the half-angles, narrowed by the margin
  double margin_ = kFramingMargin;
  double lo_[3], hi_[3];  // extent along right, up, forward
  // Perspective fit: the max over spheres of (±s + r·sqrt(1 + h²))/h − z per axis and sign,
  // with s and z measured from the origin, and of r − z (the eye stays outside every sphere).
  double fit_[4], inside_;
};

// Frames the spheres (centres, radii) looking along `direction`: the look-at point is the
// centre of their extent in the view frame, and the eye is as close as it can be with every
// sphere inside the frustum (or the orthographic window), times `margin`. Keeps projection,
// fovY and size; sets eye, lookAt, up (world y, or z when looking along y), orthoHeight.
// SphereFraming does the same over spheres that come in pieces (to rounding: here each sphere
// is measured from the look-at point, which keeps a structure's camera as it always was).
Camera frameSpheres(Camera camera, std::span<const glm::dvec3> centers, std::span<const double> radii,
                    const glm::dvec3& direction, double margin = kFramingMargin);

// Spheres whose union holds the whole scene.
struct SphereCover {
  std::span<const glm::dvec3> centers;
  std::span<const double> radii;
};

// Frames a scene known to lie inside each of `covers` (every one holds all of it), as
// frameSpheres frames one cover: the look-at point is the centre of the intersection of the
// covers' boxes in the view frame, and the eye is at the nearest distance that any one cover
// proves enough. With one cover this is frameSpheres. Used where each bound alone is loose
// somewhere (the skin: its patches' balls, and the atoms' hull grown by the largest radius).
Camera frameSphereCovers(Camera camera, std::span<const SphereCover> covers, const glm::dvec3& direction,
                         double margin = 1.05);

std::string cameraToJson(const Camera& camera);
Camera cameraFromJson(const std::string& json);

}  // namespace surftrace::view
