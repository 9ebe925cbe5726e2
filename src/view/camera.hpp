// The camera: pixel-centre rays in double precision, automatic framing, named views.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
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
// up' = right × forward, aspect = W/H; an off-centre `window` (a foreign camera's glFrustum
// or glOrtho) replaces the centred ±tan(fovY/2)·(aspect, 1) or ±orthoHeight/2·(aspect, 1).
//
// The same camera in OpenGL's conventions (viewMatrix, projectionMatrix; README "Cameras and
// buffers"): column-major matrices, the eye looks down −z of the view frame, clip z in [−1, 1]
// for depths zNear..zFar, window y up (image row 0 is the top row, glReadPixels' last).

// The image window in the view frame: tangents at unit distance in front of the eye
// (perspective) or Å (orthographic), x to the right, y up.
struct ViewWindow {
  double left = -1.0, right = 1.0, bottom = -1.0, top = 1.0;
};

struct Camera {
  Projection projection = Projection::Perspective;
  glm::dvec3 eye{0.0, 0.0, 10.0};
  glm::dvec3 lookAt{0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  double fovY = 30.0;         // degrees, perspective
  double orthoHeight = 10.0;  // Å, orthographic
  int width = 512;
  int height = 512;
  // Set only for a window that is not centred on the view direction (or whose pixels are not
  // square): a camera imported from another program's projection matrix.
  std::optional<ViewWindow> window;
  // The depth range of the GL projection, measured from the eye along forward (Å); 0 and 0
  // until withDepthRange (or an imported camera) sets it. Rays do not depend on it.
  double zNear = 0.0, zFar = 0.0;

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
    double centreX = 0.0, centreY = 0.0;  // the window's centre, off-centre cameras only
    bool perspective;
    bool offCentre = false;
    // Bit-identical to Camera::ray(sx, sy).
    Ray ray(double sx, double sy) const;
  };
  Frame frame() const;
  // The window: `window` if set, else the centred one of fovY (or orthoHeight) and W/H.
  ViewWindow viewWindow() const;
  bool hasDepthRange() const { return zFar > zNear; }
  // glm::lookAt(eye, lookAt, up).
  glm::dmat4 viewMatrix() const;
  // glm::perspective (centred), glm::frustum (off-centre) or glm::ortho, for zNear..zFar, all
  // right-handed with clip z in [−1, 1]. std::logic_error without a depth range.
  glm::dmat4 projectionMatrix() const;
  // Throws std::invalid_argument naming the bad field (zero size, eye == lookAt, up
  // parallel to the view direction, fov outside (0, 180), non-finite values, an empty
  // window, a depth range with zNear >= zFar or, in perspective, zNear <= 0).
  void validate() const;
};


// The camera that a pair of OpenGL matrices (column-major, as glm and glUniformMatrix4fv keep
// them) defines for a width x height image: any rigid view matrix, and any perspective
// (glFrustum form, bottom row (0, 0, −w, 0), w > 0) or orthographic (glOrtho form, bottom row
// (0, 0, 0, w)) projection with finite near and far, off-centre or not. Its rays are those of
// the matrices at pixel centres (to rounding). std::invalid_argument naming what is wrong.
Camera cameraFromMatrices(int width, int height, const glm::dmat4& view, const glm::dmat4& projection);

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
  // The corners of the box, in the view frame of the framing direction, that holds every
  // sphere added (for a depth range: withDepthRange over them, with radius 0).
  std::vector<glm::dvec3> boxCorners() const;

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

// The camera as JSON (format "surftrace-camera", version 1): width, height, projection, eye,
// look_at, up, fov_y_degrees, ortho_height, pixel_centre, and when it has a depth range near,
// far, view_matrix and projection_matrix (16 numbers each, column-major); `window` when
// off-centre. Numbers round-trip exactly.
// The camera with zNear and zFar tight around the spheres (what the scene can reach), with a
// small margin, so that a float32 window depth resolves the scene finely: perspective near is
// kept above 1e-4 of far (the eye may be inside the spheres' hull).
Camera withDepthRange(Camera camera, std::span<const glm::dvec3> centers, std::span<const double> radii);
// The same for a scene that lies in each of `covers`: the tightest range any of them proves
// along the view direction, intersected.
Camera withDepthRange(Camera camera, std::span<const SphereCover> covers);

std::string cameraToJson(const Camera& camera);
// Reads cameraToJson's form, or one with only width, height, view_matrix and
// projection_matrix (another program's camera: cameraFromMatrices). When both forms are
// there they must agree. std::invalid_argument naming the key that is missing or wrong.
Camera cameraFromJson(const std::string& json);

}  // namespace surftrace::view
