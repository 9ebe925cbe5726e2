// surftrace.Camera, surftrace.render -> surftrace.Image, surftrace.compare: the stages "camera",
// "render", "write" and "compare" of the public API (include/surftrace/), as `surftrace render`
// and `surftrace compare` run them, so that an image and a report from Python are the CLI's.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"

namespace surftrace::python {
namespace {

using namespace pybind11::literals;

// ---- Arguments: Python values checked with the CLI's limits, errors naming the keyword -------

[[noreturn]] void raise(PyObject* type, const std::string& message) {
  PyErr_SetString(type, message.c_str());
  throw py::error_already_set();
}

std::string reprOf(py::handle value) { return py::repr(value).cast<std::string>(); }

// A path given as str or os.PathLike; nullopt for anything else.
std::optional<std::string> pathOf(py::handle value) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::hasattr(value, "__fspath__")) {
    const py::object path = py::module_::import("os").attr("fspath")(value);
    if (py::isinstance<py::str>(path)) return path.cast<std::string>();
  }
  return std::nullopt;
}

// An existing file, or FileNotFoundError naming `what` and the path.
std::string existingFile(const std::string& path, const std::string& what) {
  if (!std::filesystem::is_regular_file(path)) raise(PyExc_FileNotFoundError, what + ": no such file: " + path);
  return path;
}

// Runs `read` on a file; a file it cannot read (std::runtime_error: bad content, missing
// channels) is a ValueError naming it.
template <class Read>
auto readingFile(Read&& read) {
  try {
    return read();
  } catch (const std::invalid_argument&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw py::value_error(e.what());
  }
}

double realOf(py::handle value, const std::string& name) {
  if (py::isinstance<py::bool_>(value) || !PyNumber_Check(value.ptr()) || py::isinstance<py::str>(value))
    throw py::value_error(name + "=" + reprOf(value) + ": expected a number");
  const double v = py::float_(py::reinterpret_borrow<py::object>(value)).cast<double>();
  if (!std::isfinite(v)) throw py::value_error(name + "=" + reprOf(value) + ": expected a finite number");
  return v;
}

double realIn(py::handle value, const std::string& name, double lo, double hi, bool openLo = false) {
  const double v = realOf(value, name);
  if (v < lo || v > hi || (openLo && v == lo)) {
    std::ostringstream range;
    range << (openLo ? "(" : "[") << lo << ", ";
    if (std::isinf(hi)) range << "inf)";
    else range << hi << "]";
    throw py::value_error(name + "=" + reprOf(value) + ": must be in " + range.str());
  }
  return v;
}

int wholeIn(py::handle value, const std::string& name, int lo, int hi) {
  if (py::isinstance<py::bool_>(value) || !PyIndex_Check(value.ptr()))
    throw py::value_error(name + "=" + reprOf(value) + ": expected a whole number in [" + std::to_string(lo) + ", " +
                          std::to_string(hi) + "]");
  const long long v = py::int_(py::reinterpret_borrow<py::object>(value)).cast<long long>();
  if (v < lo || v > hi)
    throw py::value_error(name + "=" + reprOf(value) + ": must be in [" + std::to_string(lo) + ", " +
                          std::to_string(hi) + "]");
  return static_cast<int>(v);
}

bool flagOf(py::handle value, const std::string& name) {
  if (!py::isinstance<py::bool_>(value) && !py::isinstance(value, py::module_::import("numpy").attr("bool_")))
    throw py::value_error(name + "=" + reprOf(value) + ": expected True or False");
  return value.cast<bool>();
}

std::string textOf(py::handle value, const std::string& name) {
  if (!py::isinstance<py::str>(value)) throw py::value_error(name + "=" + reprOf(value) + ": expected a string");
  return value.cast<std::string>();
}

std::string choiceOf(py::handle value, const std::string& name, const std::vector<std::string>& choices) {
  const std::string text = textOf(value, name);
  if (std::find(choices.begin(), choices.end(), text) != choices.end()) return text;
  std::string known;
  for (const std::string& c : choices) known += (known.empty() ? "" : ", ") + c;
  throw py::value_error(name + "=" + reprOf(value) + ": choose one of " + known);
}

// Three finite numbers (a tuple, a list, a numpy array).
glm::dvec3 vectorOf(py::handle value, const std::string& name) {
  if (py::isinstance<py::str>(value) || !PySequence_Check(value.ptr()) || PySequence_Size(value.ptr()) != 3) {
    PyErr_Clear();
    throw py::value_error(name + "=" + reprOf(value) + ": expected three numbers (x, y, z)");
  }
  const py::sequence s = py::reinterpret_borrow<py::sequence>(value);
  return {realOf(s[0], name), realOf(s[1], name), realOf(s[2], name)};
}

glm::dvec3 colorOf(py::handle value, const std::string& name) {
  const glm::dvec3 c = vectorOf(value, name);
  if (c.x < 0 || c.y < 0 || c.z < 0 || c.x > 1 || c.y > 1 || c.z > 1)
    throw py::value_error(name + "=" + reprOf(value) + ": colour components must be in [0, 1]");
  return c;
}

py::tuple tupleOf(const glm::dvec3& v) { return py::make_tuple(v.x, v.y, v.z); }

// Keyword options taken one by one; what is left over is a keyword nobody knows.
class Keywords {
 public:
  explicit Keywords(const py::kwargs& kwargs) {
    for (const auto& [key, value] : kwargs) given_.emplace_back(key.cast<std::string>(), value);
  }
  // The value of `name`, or nullopt when not given (None counts as not given).
  std::optional<py::object> take(const std::string& name) {
    known_.push_back(name);
    for (auto it = given_.begin(); it != given_.end(); ++it)
      if (it->first == name) {
        py::object v = py::reinterpret_borrow<py::object>(it->second);
        given_.erase(it);
        if (v.is_none()) return std::nullopt;
        return v;
      }
    return std::nullopt;
  }
  // TypeError naming the first keyword not taken and those known (Python's own error for a
  // keyword a function lacks).
  void finish(const std::string& function) const {
    if (given_.empty()) return;
    std::string known;
    for (const std::string& k : known_) known += (known.empty() ? "" : ", ") + k;
    raise(PyExc_TypeError, function + "() got an unexpected keyword argument '" + given_.front().first +
                               "'; its options are " + known);
  }

 private:
  std::vector<std::pair<std::string, py::handle>> given_;
  std::vector<std::string> known_;
};

// ---- Camera --------------------------------------------------------------------------------

// A glm matrix (column-major, m[column][row]) as the (4, 4) array of its rows and columns as
// written on paper: a[row, col] = m[col][row], so that clip = P @ V @ (x, y, z, 1).
py::array_t<double> matrixArray(const glm::dmat4& m) {
  py::array_t<double> a({4, 4});
  auto r = a.mutable_unchecked<2>();
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) r(row, col) = m[col][row];
  return a;
}

glm::dmat4 matrixOf(py::handle value, const std::string& name) {
  const py::array a = py::array::ensure(value);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) {
    PyErr_Clear();
    throw py::value_error(name + ": expected a (4, 4) array (rows as written on paper: clip = P @ V @ x), got " +
                          (a ? "shape " + reprOf(a.attr("shape")) : reprOf(value)));
  }
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::value_error(name + ": expected real numbers, got dtype " + reprOf(a.dtype()));
  const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  const auto r = d.unchecked<2>();
  glm::dmat4 m;
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) {
      if (!std::isfinite(r(row, col)))
        throw py::value_error(name + ": element [" + std::to_string(row) + ", " + std::to_string(col) + "] is " +
                              std::to_string(r(row, col)) + "; every element must be finite");
      m[col][row] = r(row, col);
    }
  return m;
}

const char* projectionName(Projection p) { return p == Projection::Orthographic ? "orthographic" : "perspective"; }

Projection projectionOf(py::handle value) {
  return choiceOf(value, "projection", {"perspective", "orthographic"}) == "orthographic" ? Projection::Orthographic
                                                                                        : Projection::Perspective;
}

// Camera.from_json: the JSON text itself, or the path of a file holding it.
Camera cameraFromJsonOrPath(py::handle value) {
  const std::optional<std::string> text = pathOf(value);
  if (!text) throw py::value_error("Camera.from_json: expected JSON text or a path, got " + reprOf(value));
  const auto first = text->find_first_not_of(" \t\r\n");
  if (first != std::string::npos && (*text)[first] == '{') return cameraFromJson(*text);
  return readingFile([&] { return readCamera(existingFile(*text, "Camera.from_json")); });
}

void bindCamera(py::module_& m) {
  py::class_<Camera>(m, "Camera", R"(A view: eye, look-at point, up, field of view (or orthographic height), image size
and depth range, as `surftrace render --camera-out` writes it. Pixel (x, y) has x to the right and y
down (row 0 is the top row); its centre ray is the one the image's buffers hold.
view_matrix and projection_matrix are OpenGL's (glm::lookAt and glm::perspective / glm::frustum /
glm::ortho, clip z in [-1, 1]) as (4, 4) float64 arrays written as on paper: clip = P @ V @ (x, y, z, 1);
give glUniformMatrix4fv their transpose (or transpose=GL_TRUE).)")
      .def(py::init([](py::object eye, py::object lookAt, py::object up, double fov, int width, int height,
                       py::object projection, double orthoHeight, double zNear, double zFar) {
             Camera c;
             c.eye = vectorOf(eye, "eye");
             c.lookAt = vectorOf(lookAt, "look_at");
             c.up = vectorOf(up, "up");
             c.fovY = fov;
             c.width = width;
             c.height = height;
             c.projection = projectionOf(projection);
             c.orthoHeight = orthoHeight;
             c.zNear = zNear;
             c.zFar = zFar;
             c.validate();
             return c;
           }),
           "eye"_a = py::make_tuple(0.0, 0.0, 10.0), "look_at"_a = py::make_tuple(0.0, 0.0, 0.0),
           "up"_a = py::make_tuple(0.0, 1.0, 0.0), "fov"_a = 30.0, "width"_a = 512, "height"_a = 512,
           "projection"_a = "perspective", "ortho_height"_a = 10.0, "near"_a = 0.0, "far"_a = 0.0)
      .def_static("from_json", &cameraFromJsonOrPath, "text_or_path"_a,
                  "The camera of `--camera-out`'s JSON (the text, or a file's path); another program's JSON with only "
                  "width, height, view_matrix and projection_matrix (column-major) works too")
      .def_static("load", [](py::handle path) {
        const std::optional<std::string> p = pathOf(path);
        if (!p) throw py::value_error("Camera.load: expected a path, got " + reprOf(path));
        return readingFile([&] { return readCamera(existingFile(*p, "Camera.load")); });
      }, "path"_a, "The camera in a JSON file written by `--camera-out` or Camera.save")
      .def("to_json", [](const Camera& c) { return cameraToJson(c); }, "The JSON `--camera-out` writes")
      .def("save", [](const Camera& c, py::handle path) {
        const std::optional<std::string> p = pathOf(path);
        if (!p) throw py::value_error("Camera.save: expected a path, got " + reprOf(path));
        writeCamera(*p, c);
      }, "path"_a, "Writes to_json() to `path`, whole or not at all")
      .def_static("from_matrices", [](int width, int height, py::handle view, py::handle projection) {
        if (width < 1 || height < 1)
          throw py::value_error("Camera.from_matrices: width and height must be at least 1, got " +
                                std::to_string(width) + "x" + std::to_string(height));
        return cameraFromMatrices(width, height, matrixOf(view, "view"), matrixOf(projection, "projection"));
      }, "width"_a, "height"_a, "view"_a, "projection"_a,
         "The camera of OpenGL view and projection matrices ((4, 4) arrays as on paper) for a width x height image; "
         "any rigid view and any glFrustum or glOrtho projection, off-centre too")
      .def_property("eye", [](const Camera& c) { return tupleOf(c.eye); },
                    [](Camera& c, py::handle v) { c.eye = vectorOf(v, "eye"); })
      .def_property("look_at", [](const Camera& c) { return tupleOf(c.lookAt); },
                    [](Camera& c, py::handle v) { c.lookAt = vectorOf(v, "look_at"); })
      .def_property("up", [](const Camera& c) { return tupleOf(c.up); },
                    [](Camera& c, py::handle v) { c.up = vectorOf(v, "up"); })
      .def_readwrite("fov", &Camera::fovY, "Vertical field of view in degrees (perspective)")
      .def_readwrite("ortho_height", &Camera::orthoHeight, "Height of the view in Å (orthographic)")
      .def_readwrite("width", &Camera::width)
      .def_readwrite("height", &Camera::height)
      .def_property("projection", [](const Camera& c) { return projectionName(c.projection); },
                    [](Camera& c, py::handle v) { c.projection = projectionOf(v); })
      .def_readwrite("near", &Camera::zNear, "Depth range of the projection, Å from the eye (0, 0: none)")
      .def_readwrite("far", &Camera::zFar)
      .def_property_readonly("window", [](const Camera& c) -> py::object {
        if (!c.window) return py::none();
        return py::make_tuple(c.window->left, c.window->right, c.window->bottom, c.window->top);
      }, "An off-centre window (left, right, bottom, top) of an imported camera, else None")
      .def_property_readonly("view_matrix", [](const Camera& c) { return matrixArray(c.viewMatrix()); },
                             "glm::lookAt(eye, look_at, up) as a (4, 4) array, rows as on paper")
      .def_property_readonly("projection_matrix", [](const Camera& c) {
        if (!c.hasDepthRange())
          throw py::value_error("the camera has no depth range (near " + std::to_string(c.zNear) + ", far " +
                                std::to_string(c.zFar) + "): set near < far, or take the camera of a rendered Image");
        return matrixArray(c.projectionMatrix());
      }, "OpenGL's projection for near..far as a (4, 4) array, rows as on paper")
      .def("validate", &Camera::validate, "ValueError naming the field that is wrong")
      .def("__eq__", [](const Camera& a, const Camera& b) { return cameraToJson(a) == cameraToJson(b); })
      .def("__repr__", [](const Camera& c) {
        std::ostringstream s;
        s.precision(6);
        s << "surftrace.Camera(" << c.width << "x" << c.height << ", " << projectionName(c.projection) << ", eye=("
          << c.eye.x << ", " << c.eye.y << ", " << c.eye.z << "), look_at=(" << c.lookAt.x << ", " << c.lookAt.y << ", "
          << c.lookAt.z << "), near=" << c.zNear << ", far=" << c.zFar << ")";
        return s.str();
      });
}

// ---- Image ---------------------------------------------------------------------------------

// A rendered (or loaded) frame: its buffers shared with every numpy array handed out, the camera
// and the metadata its files carry. `record` is how it was rendered (none for a loaded EXR).
struct PyImage {
  std::shared_ptr<const FrameBuffers> frame;
  Camera camera;
  ImageMetadata metadata;
  std::optional<ImageRecord> record;
};

// A view of `frame`'s memory as an array of `shape` (elements of T, strides in elements), read
// only, kept alive by a capsule that holds the frame: no copy.
template <class T>
py::object bufferArray(const std::shared_ptr<const FrameBuffers>& frame, const std::vector<T>& data, std::size_t offset,
                       std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides) {
  if (data.empty()) return py::none();
  for (py::ssize_t& s : strides) s *= static_cast<py::ssize_t>(sizeof(T));
  auto* keep = new std::shared_ptr<const FrameBuffers>(frame);
  py::capsule base(keep, [](void* p) { delete static_cast<std::shared_ptr<const FrameBuffers>*>(p); });
  py::array a(py::dtype::of<T>(), std::move(shape), std::move(strides), data.data() + offset, base);
  a.attr("setflags")("write"_a = false);
  return a;
}

py::object plane(const PyImage& im, const std::vector<float>& data) {
  const py::ssize_t w = im.frame->width, h = im.frame->height;
  return bufferArray(im.frame, data, 0, {h, w}, {w, 1});
}

py::object idPlane(const PyImage& im, const std::vector<std::uint32_t>& data) {
  const py::ssize_t w = im.frame->width, h = im.frame->height;
  return bufferArray(im.frame, data, 0, {h, w}, {w, 1});
}

void saveImage(const PyImage& im, const std::string& path) {
  const bool exr = path.size() >= 4 && [&] {
    std::string ext = path.substr(path.size() - 4);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
    return ext == ".exr";
  }();
  view::checkImageOutputName(path, "Image.save", exr ? ImageContent::Buffers : ImageContent::Colour);
  py::gil_scoped_release release;
  const std::string png = exr ? "" : path, exrPath = exr ? path : "";
  if (im.record) {
    writeImage(png, exrPath, *im.frame, *im.record, im.camera);
  } else if (exr) {
    view::writeExr(path, *im.frame, im.metadata);
  } else {
    view::writePng(path, *im.frame, im.metadata);
  }
}

py::bytes pngBytes(const PyImage& im) {
  EncodedImage bytes;
  {
    py::gil_scoped_release release;
    bytes = im.record ? encodeImage("image.png", "", *im.frame, *im.record, im.camera).pngBytes
                      : view::encodePng("image.png", *im.frame, im.metadata);
  }
  return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

PyImage loadImage(const std::string& path) {
  PyImage im;
  ImageMetadata meta;
  auto frame = std::make_shared<FrameBuffers>(readingFile([&] { return readExr(existingFile(path, "Image.load"), &meta); }));
  const auto c = meta.find("surftrace:camera");
  if (c == meta.end()) throw py::value_error(path + ": records no camera (surftrace:camera): not an EXR of `surftrace render`");
  im.camera = cameraFromJson(c->second);
  im.frame = std::move(frame);
  im.metadata = std::move(meta);
  return im;
}

void bindImage(py::module_& m) {
  py::class_<PyImage>(m, "Image", R"(A rendered frame: colour and the buffers of each pixel's centre ray, as numpy arrays
that share the image's memory (read only; .copy() one to change it). Rows run from the top of the
image down (row 0 is the top row, as in the PNG; glReadPixels' rows run the other way), columns left
to right: rgb (h, w, 3) float32 linear colour (the EXR's; a PNG holds its sRGB encoding), alpha (h, w) coverage, depth_t (h, w) ray
distance in Å and depth_z view depth in Å (+inf: background), normal (h, w, 3) world-space unit
normals (0 on background), patch_kind, patch_id, atom_id, flags (h, w) uint32 (ids 2**32-1 on
background), seam_distance (h, w) Å to the edge of the hit's patch (None when not recorded).)")
      .def_static("load", [](py::handle path) {
        const std::optional<std::string> p = pathOf(path);
        if (!p) throw py::value_error("Image.load: expected a path, got " + reprOf(path));
        return loadImage(*p);
      }, "path"_a, "An EXR written by `surftrace render --exr` or Image.save")
      .def_property_readonly("width", [](const PyImage& im) { return im.frame->width; })
      .def_property_readonly("height", [](const PyImage& im) { return im.frame->height; })
      .def_property_readonly("rgb", [](const PyImage& im) {
        const py::ssize_t w = im.frame->width, h = im.frame->height;
        return bufferArray(im.frame, im.frame->rgba, 0, {h, w, 3}, {4 * w, 4, 1});
      })
      .def_property_readonly("rgba", [](const PyImage& im) {
        const py::ssize_t w = im.frame->width, h = im.frame->height;
        return bufferArray(im.frame, im.frame->rgba, 0, {h, w, 4}, {4 * w, 4, 1});
      })
      .def_property_readonly("alpha", [](const PyImage& im) {
        const py::ssize_t w = im.frame->width, h = im.frame->height;
        return bufferArray(im.frame, im.frame->rgba, 3, {h, w}, {4 * w, 4});
      })
      .def_property_readonly("depth_t", [](const PyImage& im) { return plane(im, im.frame->depth); })
      .def_property_readonly("depth_z", [](const PyImage& im) { return plane(im, im.frame->viewZ); })
      .def_property_readonly("normal", [](const PyImage& im) {
        const py::ssize_t w = im.frame->width, h = im.frame->height;
        return bufferArray(im.frame, im.frame->normal, 0, {h, w, 3}, {3 * w, 3, 1});
      })
      .def_property_readonly("patch_kind", [](const PyImage& im) { return idPlane(im, im.frame->kind); })
      .def_property_readonly("patch_id", [](const PyImage& im) { return idPlane(im, im.frame->patchId); })
      .def_property_readonly("atom_id", [](const PyImage& im) { return idPlane(im, im.frame->atomId); })
      .def_property_readonly("flags", [](const PyImage& im) { return idPlane(im, im.frame->flags); })
      .def_property_readonly("seam_distance", [](const PyImage& im) { return plane(im, im.frame->seamDistance); })
      .def_property_readonly("camera", [](const PyImage& im) { return im.camera; })
      .def_property_readonly("metadata", [](const PyImage& im) { return im.metadata; },
                             "What the image's files record (surftrace:* keys)")
      .def_property_readonly("engine", [](const PyImage& im) {
        const auto e = im.metadata.find("surftrace:engine");
        return e == im.metadata.end() ? std::string() : e->second;
      })
      .def_property_readonly("seconds", [](const PyImage& im) { return im.frame->seconds; },
                             "Wall time of the frame (0 for a loaded image)")
      .def("save", [](const PyImage& im, py::handle path) {
        const std::optional<std::string> p = pathOf(path);
        if (!p) throw py::value_error("Image.save: expected a path, got " + reprOf(path));
        saveImage(im, *p);
      }, "path"_a,
         "Writes the image as `surftrace render` does: .exr with every buffer and the metadata `compare` reads, "
         "any other extension (.png, ...) the colour")
      .def("_repr_png_", &pngBytes)
      .def("__repr__", [](const PyImage& im) {
        const auto e = im.metadata.find("surftrace:engine");
        return "surftrace.Image(" + std::to_string(im.frame->width) + "x" + std::to_string(im.frame->height) +
               (e == im.metadata.end() ? std::string() : ", engine " + e->second) + ")";
      });
}

// ---- render --------------------------------------------------------------------------------

struct RenderRequest {
  RenderOptions render;
  Framing framing;
  EngineOptions engine;
  std::string colorName = "patch";
  glm::dvec3 uniformColor{0.8}, background{1.0};
  bool ballAndStick = false;
  double ballScale = 0.25, stickRadius = 0.15;
};

// The image-space effects from the keywords, as resolveEffects takes them from the CLI's.
ImageEffects effectsOf(Keywords& k) {
  ImageEffects e;
  if (auto v = k.take("silhouettes")) e.silhouettes = flagOf(*v, "silhouettes");
  if (auto v = k.take("silhouette_width")) e.lineWidth = realIn(*v, "silhouette_width", 0, 0.25, true);
  if (auto v = k.take("silhouette_color")) e.lineColor = glm::vec3(colorOf(*v, "silhouette_color"));
  if (auto v = k.take("silhouette_depth_jump")) e.silhouetteJump = realIn(*v, "silhouette_depth_jump", 0, HUGE_VAL);
  if (auto v = k.take("crease_angle")) e.creaseAngle = realIn(*v, "crease_angle", 0, 179);
  if (auto v = k.take("depth_darkening")) e.depthDarkening = flagOf(*v, "depth_darkening");
  if (auto v = k.take("depth_darkening_sigma")) {
    e.darkeningSigma = realIn(*v, "depth_darkening_sigma", 0, HUGE_VAL);
    if (!(e.darkeningSigma > 0.0 && e.darkeningSigma < 0.1))
      throw py::value_error("depth_darkening_sigma is a fraction of the image height in (0, 0.1), e.g. 0.015; for a "
                            "sigma in pixels give depth_darkening_sigma_px");
  }
  if (auto v = k.take("depth_darkening_sigma_px"))
    e.darkeningSigmaPx = realIn(*v, "depth_darkening_sigma_px", 0.1, 256);
  if (auto v = k.take("depth_darkening_strength"))
    e.darkeningStrength = realIn(*v, "depth_darkening_strength", 0, HUGE_VAL);
  if (auto v = k.take("depth_darkening_range")) {
    e.darkeningRange = realIn(*v, "depth_darkening_range", 0, HUGE_VAL);
    if (!(*e.darkeningRange > 0.0)) throw py::value_error("depth_darkening_range must be > 0 Å");
  }
  if (auto v = k.take("depth_cue")) e.depthCue = flagOf(*v, "depth_cue");
  if (auto v = k.take("depth_cue_strength")) e.depthCueStrength = realIn(*v, "depth_cue_strength", 0, 1);
  if (auto v = k.take("depth_cue_start")) e.depthCueStart = realIn(*v, "depth_cue_start", 0, HUGE_VAL);
  if (auto v = k.take("depth_cue_end")) e.depthCueEnd = realIn(*v, "depth_cue_end", 0, HUGE_VAL);
  if (e.depthCueStart && e.depthCueEnd && !(*e.depthCueEnd > *e.depthCueStart))
    throw py::value_error("depth_cue_end must lie beyond depth_cue_start");
  e.validate();
  return e;
}

// What render()'s arguments ask for, checked before any work as `surftrace render` checks its
// options (the same limits and the same errors, named by keyword).
RenderRequest requestOf(const PySurface& surface, const std::optional<Camera>& camera, py::object size,
                        const std::string& engine, py::object view, py::object eye, py::object lookAt, py::object up,
                        py::object fov, bool ortho, const py::kwargs& kwargs) {
  RenderRequest q;
  RenderOptions& ro = q.render;
  int width = 1024, height = 1024;
  if (!size.is_none()) {
    if (py::isinstance<py::str>(size) || !PySequence_Check(size.ptr()) || PySequence_Size(size.ptr()) != 2) {
      PyErr_Clear();
      throw py::value_error("size=" + reprOf(size) + ": expected (width, height)");
    }
    const py::sequence s = py::reinterpret_borrow<py::sequence>(size);
    width = wholeIn(s[0], "size[0] (width)", 1, 32768);
    height = wholeIn(s[1], "size[1] (height)", 1, 32768);
  }
  ro.camera.width = width;
  ro.camera.height = height;
  ro.camera.projection = ortho ? Projection::Orthographic : Projection::Perspective;
  if (!fov.is_none()) ro.camera.fovY = realIn(fov, "fov", 0, 180, true);
  if (!(ro.camera.fovY < 180.0)) throw py::value_error("fov=" + reprOf(fov) + ": the field of view must be in (0, 180) degrees");
  // A named view ("front", "x,y,z") or the direction itself as three numbers.
  if (view.is_none()) q.framing.direction = namedViewDirection("front");
  else if (py::isinstance<py::str>(view)) q.framing.direction = namedViewDirection(view.cast<std::string>());
  else if ((q.framing.direction = vectorOf(view, "view")) == glm::dvec3(0.0))
    throw py::value_error("view=" + reprOf(view) + ": the view direction must not be zero");
  if (!eye.is_none()) q.framing.eye = vectorOf(eye, "eye");
  if (!lookAt.is_none()) q.framing.lookAt = vectorOf(lookAt, "look_at");
  if (!up.is_none()) {
    q.framing.up = vectorOf(up, "up");
    if (*q.framing.up == glm::dvec3(0.0)) throw py::value_error("up=" + reprOf(up) + ": the up vector must not be zero");
  }
  if (camera) {
    const std::pair<const char*, bool> framing[] = {{"view", !view.is_none()},   {"eye", !eye.is_none()},
                                                    {"look_at", !lookAt.is_none()}, {"up", !up.is_none()},
                                                    {"fov", !fov.is_none()},     {"ortho", ortho}};
    for (const auto& [name, given] : framing)
      if (given)
        throw py::value_error(std::string(name) + " cannot be combined with camera=, which fixes the whole view "
                              "(change the Camera, or leave camera out)");
    if (!size.is_none() && (camera->width != width || camera->height != height))
      throw py::value_error("size=" + reprOf(size) + " disagrees with the camera (" + std::to_string(camera->width) +
                            "x" + std::to_string(camera->height) + "): leave size out, the camera fixes it");
    camera->validate();
    q.framing.fixed = *camera;
    ro.camera = *camera;
  }

  Keywords k(kwargs);
  if (auto v = k.take("color"))
    q.colorName = choiceOf(*v, "color", {"patch", "element", "chain", "bfactor", "uniform"});
  ro.color = parseColorMode(q.colorName);
  if (auto v = k.take("uniform_color")) q.uniformColor = colorOf(*v, "uniform_color");
  if (auto v = k.take("background")) q.background = colorOf(*v, "background");
  ro.background = view::srgbToLinear(glm::vec3(q.background));  // given in sRGB, as the CLI's; shaded linear
  if (auto v = k.take("spp")) ro.samplesPerPixel = wholeIn(*v, "spp", 1, 1024);
  if (auto v = k.take("lighting"))
    ro.lighting = view::lightingFor(view::parseLightingPreset(choiceOf(*v, "lighting", {"headlight", "simple", "soft", "full"})));
  if (auto v = k.take("shadows")) ro.shadows = flagOf(*v, "shadows");
  if (auto v = k.take("ao")) ro.aoSamples = wholeIn(*v, "ao", 0, 4096);
  if (auto v = k.take("ao_distance")) ro.aoDistance = realIn(*v, "ao_distance", 0, HUGE_VAL, true);
  if (auto v = k.take("opacity")) ro.opacity = realIn(*v, "opacity", 0, 1);
  if (auto v = k.take("max_layers")) ro.maxLayers = wholeIn(*v, "max_layers", 1, 1024);
  if (auto v = k.take("ball_and_stick")) q.ballAndStick = flagOf(*v, "ball_and_stick");
  if (auto v = k.take("ball_scale")) q.ballScale = realIn(*v, "ball_scale", 0, HUGE_VAL, true);
  if (auto v = k.take("stick_radius")) q.stickRadius = realIn(*v, "stick_radius", 0, HUGE_VAL, true);
  // Where `compare` may let another renderer disagree (one more ray per pixel, Embree): on by
  // default, as `render --exr` records them, so that an Image serves as a reference.
  ro.referenceMasks = true;
  if (auto v = k.take("masks")) ro.referenceMasks = flagOf(*v, "masks");
  if (auto v = k.take("gl_torus")) q.engine.glTorus = choiceOf(*v, "gl_torus", {"quartic", "sphere-tracing"});
  if (auto v = k.take("gl_primitive")) q.engine.glPrimitive = choiceOf(*v, "gl_primitive", {"box", "cylinder"});
  if (auto v = k.take("gl_steps")) q.engine.glSteps = wholeIn(*v, "gl_steps", 1, 10000);
  ro.effects = effectsOf(k);
  k.finish("render");

  if (ro.opacity == 0.0 && !q.ballAndStick)
    throw py::value_error("opacity=0 draws no surface, and nothing else was asked for: add ball_and_stick=True or "
                          "give an opacity above 0");
  q.engine.kind = parseEngineKind(engine);
  checkEngineCanDraw(q.engine, ro);
  if (!surface.molecule) {
    if (q.ballAndStick)
      throw py::value_error("ball_and_stick needs the atoms and their records, which a loaded surface does not hold: "
                            "render a surface built from a Molecule");
    if (ro.color != ColorMode::Patch && ro.color != ColorMode::Uniform)
      throw py::value_error("color='" + q.colorName + "' needs the atoms' records, which a loaded surface does not "
                            "hold: render a surface built from a Molecule, or use color='patch' or 'uniform'");
  }
  return q;
}

// What the image records, as `surftrace render` records it (tools/pipeline.cpp recordOf and
// recordOfRender); the surface, probe and shrink factor are the patch list's own.
ImageRecord recordOf(const RenderRequest& q, const PySurface& surface, const Engine& engine, std::size_t bonds) {
  ImageRecord r;
  const PatchList& p = *surface.patches;
  r.surface = surfaceKindName(p.params.surface);
  r.probeRadius = p.params.probeRadius;
  if (p.params.surface == SurfaceKind::Mss) r.shrinkFactor = p.params.shrinkFactor;
  r.input = surface.molecule ? surface.molecule->source : std::string();
  r.color = q.colorName;
  r.uniformColor = q.uniformColor;
  r.background = q.background;
  r.lighting = q.render.lighting;
  r.shadows = q.render.shadows;
  r.aoSamples = q.render.aoSamples;
  r.aoDistance = q.render.aoDistance;
  const int side = q.render.sampleGridSide();
  r.samplesPerPixel = side * side;
  r.commandLine = "surftrace.render (Python)";
  r.opacity = q.render.opacity;
  r.maxLayers = q.render.maxLayers;
  r.effects = q.render.effects;
  r.ballAndStick = q.ballAndStick;
  r.ballScale = q.ballScale;
  r.stickRadius = q.stickRadius;
  r.bonds = bonds;
  EngineDescription d = engine.describe();
  r.engine = std::move(d.name);
  r.renderer = std::move(d.renderer);
  r.engineSettings = std::move(d.settings);
  return r;
}

PyImage render(const PySurface& surface, const std::optional<Camera>& camera, py::object size,
               const std::string& engineName, py::object view, py::object eye, py::object lookAt, py::object up,
               py::object fov, bool ortho, const py::kwargs& kwargs) {
  if (!surface.patches) throw py::value_error("render: the Surface holds no patch list");
  RenderRequest q = requestOf(surface, camera, size, engineName, view, eye, lookAt, up, fov, ortho, kwargs);
  const std::shared_ptr<const Molecule> keepMolecule = surface.molecule;
  const std::shared_ptr<const PatchList> keepPatches = surface.patches;
  PyImage im;
  py::gil_scoped_release release;
  const Molecule none;
  const Molecule& molecule = keepMolecule ? *keepMolecule : none;
  const PatchList& list = *keepPatches;
  q.render.camera = frameSurface(q.render.camera, q.framing, list, molecule);
  const glm::vec3 uniform(q.uniformColor);  // sRGB: atomColors decodes its colours, as here
  const std::vector<glm::vec3> colors =
      keepMolecule ? atomColors(molecule, q.render.color, uniform)
                   : std::vector<glm::vec3>(list.params.atomCount, view::srgbToLinear(uniform));
  std::vector<glm::uvec2> bonds;
  if (q.ballAndStick) bonds = surftrace::moleculeBonds(molecule);
  const BallStickModel model = q.ballAndStick
                                   ? surftrace::ballStickModel(molecule.centers, molecule.radii, bonds, q.ballScale, q.stickRadius)
                                   : BallStickModel();
  const std::unique_ptr<Engine> engine = makeEngine(q.engine);
  const Frame request{&list, molecule.centers, molecule.radii, colors, &model, q.render};
  im.frame = std::make_shared<const FrameBuffers>(engine->render(request));
  im.camera = q.render.camera;
  im.record = recordOf(q, surface, *engine, bonds.size());
  im.metadata = imageMetadata(*im.record, im.camera);
  return im;
}

// ---- compare -------------------------------------------------------------------------------

// One buffer of another renderer's, held in a numpy array: (h, w) or (h, w, 1) for depth,
// (h, w, 3) for normals, floating point; copied into the float32 values compare reads.
ImageChannels memoryBuffer(py::handle value, const std::string& name, int components) {
  const py::array a = py::array::ensure(value);
  if (!a) {
    PyErr_Clear();
    throw py::value_error(name + ": expected a numpy array, got " + reprOf(py::type::handle_of(value)));
  }
  const char kind = a.dtype().kind();
  if (kind != 'f')
    throw py::value_error(name + ": dtype " + py::str(a.dtype()).cast<std::string>() +
                          "; give floating-point values (integer depth from glReadPixels: divide by its maximum, e.g. "
                          "depth.astype(numpy.float32) / 65535 for GL_UNSIGNED_SHORT)");
  const bool plain = components == 1 && a.ndim() == 2;
  const bool shaped = a.ndim() == 3 && a.shape(2) == components;
  if (!plain && !shaped)
    throw py::value_error(name + ": shape " + reprOf(a.attr("shape")) + "; expected " +
                          (components == 1 ? "(height, width) or (height, width, 1)" : "(height, width, 3)"));
  if (a.shape(0) < 1 || a.shape(1) < 1) throw py::value_error(name + ": an empty buffer, shape " + reprOf(a.attr("shape")));
  // float32, rows in order (a copy only when it is not already).
  const auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
  const float* data = f.data();
  std::vector<float> values(data, data + f.size());
  std::vector<std::string> channels = components == 1 ? std::vector<std::string>{"Z"}
                                                      : std::vector<std::string>{"N.X", "N.Y", "N.Z"};
  return memoryChannels(name, static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)), std::move(channels),
                        std::move(values));
}

// The foreign-buffer keywords, given or not.
struct ForeignKeywords {
  std::optional<std::string> depthConvention, origin, normalSpace, normalEncoding, depthChannel, normalPath;
  bool any() const { return depthConvention || origin || normalSpace || normalEncoding || depthChannel || normalPath; }
  ForeignBufferOptions options() const {
    ForeignBufferOptions f;
    if (depthChannel) f.depthChannel = *depthChannel;
    if (depthConvention) f.depthConvention = depthConventionNamed(*depthConvention);
    if (origin) f.origin = rowOriginNamed(*origin);
    if (normalSpace) f.normalSpace = normalSpaceNamed(*normalSpace);
    if (normalEncoding) f.normalEncoding = normalEncodingNamed(*normalEncoding);
    return f;
  }
};

std::optional<std::string> optionalText(const py::object& value, const std::string& name) {
  if (value.is_none()) return std::nullopt;
  return textOf(value, name);
}

CompareTest testOf(py::handle test, const ForeignKeywords& fk) {
  if (py::isinstance<PyImage>(test)) {
    if (fk.any())
      throw py::value_error("depth_convention, origin, normal_space, normal_encoding, depth_channel and normal apply "
                            "to another renderer's buffers; the test is a surftrace.Image");
    const PyImage& im = test.cast<const PyImage&>();
    return CompareTest{"test (Image)", *im.frame, im.metadata, std::nullopt, std::nullopt};
  }
  if (py::isinstance<py::dict>(test)) {
    if (fk.depthChannel || fk.normalPath)
      throw py::value_error("depth_channel and normal apply to a test file; a dict holds its buffers under 'depth' "
                            "and 'normal'");
    const py::dict d = py::reinterpret_borrow<py::dict>(test);
    for (const auto& [key, value] : d) {
      const std::string name = py::str(key).cast<std::string>();
      if (name != "depth" && name != "normal")
        throw py::value_error("test['" + name + "']: unknown buffer; a test dict holds 'depth' (h, w) and optionally "
                              "'normal' (h, w, 3)");
    }
    if (!d.contains("depth") || d["depth"].is_none())
      throw py::value_error("the test dict has no 'depth': give {'depth': (h, w) array, 'normal': (h, w, 3) array}");
    CompareTest t;
    t.name = "test";
    t.foreign = ForeignBuffers{memoryBuffer(d["depth"], "test['depth']", 1), std::nullopt, fk.options()};
    if (d.contains("normal") && !d["normal"].is_none()) {
      t.foreign->normals = memoryBuffer(d["normal"], "test['normal']", 3);
      const ImageChannels &depth = t.foreign->depth, &normal = *t.foreign->normals;
      if (normal.width != depth.width || normal.height != depth.height)
        throw py::value_error("test['normal'] is " + std::to_string(normal.width) + "x" + std::to_string(normal.height) +
                              " pixels, test['depth'] " + std::to_string(depth.width) + "x" +
                              std::to_string(depth.height) + ": give both buffers of one image");
    }
    return t;
  }
  const std::optional<std::string> path = pathOf(test);
  if (!path)
    throw py::value_error("test: expected a surftrace.Image, a dict of numpy arrays {'depth': ..., 'normal': ...} or a "
                          "file path, got " + reprOf(py::type::handle_of(test)));
  existingFile(*path, "compare test");
  return readingFile([&] {
    // As `surftrace compare` reads TEST: SurfTrace's own EXR unless a foreign keyword is given or
    // the file lacks SurfTrace's channels.
    if (!fk.any() && hasFrameBufferChannels(*path)) return readSurfTraceTest(*path);
    CompareTest t;
    t.name = *path;
    t.foreign = ForeignBuffers{readImageChannels(*path), std::nullopt, fk.options()};
    if (fk.normalPath) t.foreign->normals = readImageChannels(existingFile(*fk.normalPath, "compare normal"));
    return t;
  });
}

CompareReference referenceOf(py::handle reference) {
  if (py::isinstance<PyImage>(reference)) {
    const PyImage& im = reference.cast<const PyImage&>();
    return compareReference("reference (Image)", *im.frame, im.metadata);
  }
  const std::optional<std::string> path = pathOf(reference);
  if (!path)
    throw py::value_error("reference: expected a surftrace.Image or the path of an EXR from `surftrace render --exr`, "
                          "got " + reprOf(py::type::handle_of(reference)));
  existingFile(*path, "compare reference");
  return readingFile([&] { return readCompareReference(*path); });
}

// The CLI's limit options (--max-coverage ...) as keywords, with their ranges.
CompareThresholds limitsOf(Keywords& k) {
  CompareThresholds t;
  if (auto v = k.take("max_coverage")) t.maxCoverageFraction = realIn(*v, "max_coverage", 0, 1);
  if (auto v = k.take("max_depth_p99")) t.maxDepthP99Relative = realIn(*v, "max_depth_p99", 0, HUGE_VAL);
  if (auto v = k.take("min_kind")) t.minKindAgreement = realIn(*v, "min_kind", 0, 1);
  if (auto v = k.take("min_patch")) t.minPatchAgreement = realIn(*v, "min_patch", 0, 1);
  if (auto v = k.take("max_normal_p99")) t.maxNormalP99Degrees = realIn(*v, "max_normal_p99", 0, HUGE_VAL);
  if (auto v = k.take("max_color_p99")) t.maxColorP99 = realIn(*v, "max_color_p99", 0, 1);
  k.finish("compare");
  return t;
}

py::list linesOf(const std::string& text) {
  py::list lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.append(line);
  return lines;
}

py::dict compareImages(py::handle test, py::handle reference, py::object depthConvention, py::object origin,
                       py::object normalSpace, py::object normalEncoding, py::object depthChannel, py::object normal,
                       py::object preset, bool ignoreCamera, bool ignoreSettings, const py::kwargs& kwargs) {
  ForeignKeywords fk;
  fk.depthConvention = optionalText(depthConvention, "depth_convention");
  fk.origin = optionalText(origin, "origin");
  fk.normalSpace = optionalText(normalSpace, "normal_space");
  fk.normalEncoding = optionalText(normalEncoding, "normal_encoding");
  fk.depthChannel = optionalText(depthChannel, "depth_channel");
  if (!normal.is_none()) {
    fk.normalPath = pathOf(normal);
    if (!fk.normalPath) throw py::value_error("normal: expected the path of the test's normal buffer, got " + reprOf(normal));
  }
  (void)fk.options();  // the names checked (ValueError naming the value and the names known)
  CompareSettings settings;
  if (!preset.is_none()) {
    settings.preset = choiceOf(preset, "preset", std::vector<std::string>(std::begin(kComparePresets), std::end(kComparePresets)));
  }
  Keywords k(kwargs);
  settings.limits = limitsOf(k);
  settings.ignoreCamera = ignoreCamera;
  settings.ignoreSettings = ignoreSettings;
  settings.report = true;
  CompareTest t = testOf(test, fk);
  const CompareReference ref = referenceOf(reference);
  std::optional<CompareResult> r;
  try {
    py::gil_scoped_release release;
    r = surftrace::compare(std::move(t), ref, settings);
  } catch (const std::invalid_argument&) {
    throw;
  } catch (const std::runtime_error& e) {
    // A buffer that does not fit the reference (its size, a missing channel): the caller's values.
    throw py::value_error(e.what());
  }
  py::dict report = py::module_::import("json").attr("loads")(r->json()).cast<py::dict>();
  report["passed"] = r->passed();
  report["verdict"] = r->verdict();
  report["preset"] = r->preset;
  report["preset_choice"] = r->presetChoice;
  report["violations"] = r->violations;
  report["hints"] = r->hints;
  report["notes"] = linesOf(r->notes);
  report["not_compared"] = r->notCompared;
  report["settings"] = linesOf(r->settingsLines);
  report["summary"] = r->figures.summary();
  report["test"] = r->testDescription;
  report["reference"] = r->referenceDescription;
  return report;
}

}  // namespace

void bindImages(py::module_& m) {
  bindCamera(m);
  bindImage(m);
  m.def("render", &render, "surface"_a, "camera"_a = py::none(), "size"_a = py::none(), "engine"_a = "embree",
        "view"_a = py::none(), "eye"_a = py::none(), "look_at"_a = py::none(), "up"_a = py::none(),
        "fov"_a = py::none(), "ortho"_a = false,
        R"(Ray-traces `surface` as `surftrace render` does -> Image (the same pixels and buffers).

camera: a Camera used as it is (its depth range filled when it has none); None frames the surface
as the CLI does, looking along `view` ("front", "back", "left", "right", "top", "bottom" or (x, y, z)
as "x,y,z") with `fov` degrees (default 30) or `ortho`, then eye/look_at/up override the framing.
size: (width, height), default (1024, 1024) or the camera's. engine: "embree" (exact) or "gl".
Options, as the CLI's: color ("patch", "element", "chain", "bfactor", "uniform"), uniform_color,
background ((r, g, b) in [0, 1], sRGB as every colour given), spp, lighting ("headlight", "simple", "soft", "full"), shadows, ao, ao_distance, opacity, max_layers, ball_and_stick,
ball_scale, stick_radius, silhouettes, silhouette_width, silhouette_color, silhouette_depth_jump,
crease_angle, depth_darkening, depth_darkening_sigma (a fraction of the image height),
depth_darkening_sigma_px, depth_darkening_strength, depth_darkening_range, depth_cue,
depth_cue_strength, depth_cue_start, depth_cue_end, gl_torus, gl_primitive, gl_steps;
masks (default True): record where another renderer may honestly disagree, for compare.)");
  m.def("compare", &compareImages, "test"_a, "reference"_a, "depth_convention"_a = py::none(), "origin"_a = py::none(),
        "normal_space"_a = py::none(), "normal_encoding"_a = py::none(), "depth_channel"_a = py::none(),
        "normal"_a = py::none(), "preset"_a = py::none(), "ignore_camera"_a = false, "ignore_settings"_a = false,
        R"(Compares a rendering with a reference of the same view, as `surftrace compare` does -> the report.

test: an Image, a file (an EXR of `surftrace render`, or another renderer's depth buffer in any
format OpenImageIO reads; its normals in the file `normal`), or another renderer's buffers held in
numpy: {"depth": (h, w), "normal": (h, w, 3)} floating point, read with depth_convention ("window",
the default: GL depth in [0, 1] for the reference camera's near and far; "view-z"; "ray"), origin
("bottom-left", glReadPixels' row order and the default; "top-left"), normal_space ("view", the
default; "world") and normal_encoding ("signed", the default; "unorm"). NaN is never background: it
counts as a mismatch. reference: an Image or an EXR path (it must record its camera).
preset: "gl-vs-embree", "exact", "foreign", "effects", "transparency" or "none" (default: chosen as
the CLI chooses); limits as the CLI's options: max_coverage, max_depth_p99, min_kind, min_patch,
max_normal_p99, max_color_p99.
Returns the CLI's --report JSON as a dict, with "passed", "verdict" (the CLI's last lines), "preset",
"preset_choice", "violations", "hints", "notes", "not_compared", "settings", "summary".)");
}

}  // namespace surftrace::python
