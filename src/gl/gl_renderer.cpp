// The GL ray caster: the patch list drawn by geometry shaders and fragment ray casting (Lindow et al. 2010, Sect. 5).
#include "gl/gl_renderer.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include <glm/geometric.hpp>

#include "build/sphere_blockers.hpp"
#include "gl/gl_api.hpp"

namespace surftrace::gl {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The perspective boxes are clipped at this fraction of the scene's depth extent from the
// eye: far below a pixel footprint, far above float rounding of the clip coordinates.
constexpr double kNearFraction = 1e-5;

std::string shaderLog(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  return log.c_str();
}

std::string programLog(GLuint program) {
  GLint length = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetProgramInfoLog(program, length, nullptr, log.data());
  return log.c_str();
}

GLuint compileShader(GLenum stage, const std::string& source, const std::string& name) {
  const GLuint shader = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    const std::string log = shaderLog(shader);
    glDeleteShader(shader);
    throw std::runtime_error("OpenGL: compiling the " + name + " shader failed:\n" + log);
  }
  return shader;
}

// Links a kind's program (programSources) or, with imagePass, a full-screen pass (imagePassSources).
GLuint linkProgram(const std::string& name, bool imagePass = false) {
  const ProgramSources sources = imagePass ? imagePassSources(name) : programSources(name);
  std::vector<GLuint> stages = {compileShader(GL_VERTEX_SHADER, sources.vertex, name + " vertex")};
  if (!sources.geometry.empty()) stages.push_back(compileShader(GL_GEOMETRY_SHADER, sources.geometry, name + " geometry"));
  stages.push_back(compileShader(GL_FRAGMENT_SHADER, sources.fragment, name + " fragment"));
  const GLuint program = glCreateProgram();
  for (GLuint s : stages) glAttachShader(program, s);
  glLinkProgram(program);
  for (GLuint s : stages) {
    glDetachShader(program, s);
    glDeleteShader(s);
  }
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    const std::string log = programLog(program);
    glDeleteProgram(program);
    throw std::runtime_error("OpenGL: linking the " + name + " program failed:\n" + log);
  }
  return program;
}

template <class T> void bufferData(GLuint buffer, const std::vector<T>& data) {
  // A zero-sized store cannot be bound as a storage buffer; 16 bytes stand in for none.
  const std::size_t bytes = data.size() * sizeof(T);
  if (bytes == 0) {
    glNamedBufferData(buffer, 16, nullptr, GL_STREAM_DRAW);
  } else {
    glNamedBufferData(buffer, static_cast<GLsizeiptr>(bytes), data.data(), GL_STREAM_DRAW);
  }
}

glm::vec4 vec4Of(const glm::dvec3& v, double w) { return glm::vec4(glm::vec3(v), static_cast<float>(w)); }

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The per-frame block (GpuFrame): camera, shading, the kinds' colours and first ids, the
// depth mapping from the patches' bounding sphere.
GpuFrame frameBlock(const view::RenderOptions& o, const GlOptions& gl, std::size_t atomColorCount, const glm::dvec3& origin,
                    const glm::dvec3& boundsCenter, double boundsRadius, const view::PatchIdOrder& ids) {
  const view::Camera& cam = o.camera;
  GpuFrame f{};
  const bool ortho = cam.projection == view::Projection::Orthographic;
  f.eyeProjection = vec4Of(cam.eye - origin, ortho ? 1.0 : 0.0);
  f.forwardTan = vec4Of(cam.forward(), std::tan(0.5 * cam.fovY * kPi / 180.0));
  f.rightAspect = vec4Of(cam.right(), static_cast<double>(cam.width) / cam.height);
  f.upHalfHeight = vec4Of(cam.trueUp(), 0.5 * cam.orthoHeight);
  const double reach = glm::length(cam.eye - boundsCenter) + boundsRadius;
  f.viewport = glm::vec4(static_cast<float>(cam.width), static_cast<float>(cam.height),
                         static_cast<float>(kNearFraction * reach), static_cast<float>(1.0 / (1.001 * reach + 1e-3)));
  f.lighting = glm::vec4(o.lighting.ambient, o.lighting.diffuse, o.lighting.specular, o.lighting.shininess);
  f.background = glm::vec4(o.background, 0.0f);
  for (std::size_t row = 0; row < view::kPatchKindCount; ++row) {
    const view::PatchKind kind = view::kPatchKinds[row].kind;
    f.kinds[row].color = glm::vec4(view::kindColor(kind), 1.0f);  // linear, as Embree's
    f.kinds[row].first = glm::uvec4(ids.first(kind), 0u, 0u, 0u);
  }
  f.shading = glm::uvec4(o.color == view::ColorMode::Patch ? 0u : 1u, static_cast<unsigned>(atomColorCount),
                         o.lighting.keyFill() ? 1u : 0u, 0u);
  const view::LightDirections lights = view::lightDirections(cam.right(), cam.trueUp(), cam.forward());
  f.keyLight = vec4Of(lights.key, 0.0);
  f.fillLight = vec4Of(lights.fill, o.lighting.fill);
  f.torusTrace = glm::uvec4(gl.torus == TorusMethod::Quartic ? 0u : 1u, static_cast<unsigned>(gl.maxSteps),
                            gl.probeBallJumps ? 0u : 1u, 0u);
  f.traceParams = glm::vec4(static_cast<float>(gl.traceEpsilon), gl.primitive == Primitive::Cylinder ? 1.0f : 0.0f,
                            gl.countFragments ? 1.0f : 0.0f, 0.0f);
  return f;
}

}  // namespace

TorusMethod parseTorusMethod(const std::string& name) {
  if (name == "quartic") return TorusMethod::Quartic;
  if (name == "sphere-tracing") return TorusMethod::SphereTracing;
  throw std::invalid_argument("unknown torus method '" + name + "': use quartic or sphere-tracing");
}

const char* torusMethodName(TorusMethod method) {
  return method == TorusMethod::Quartic ? "quartic" : "sphere-tracing";
}

Primitive parsePrimitive(const std::string& name) {
  if (name == "cylinder") return Primitive::Cylinder;
  if (name == "box") return Primitive::Box;
  throw std::invalid_argument("unknown primitive '" + name + "': use cylinder or box");
}

const char* primitiveName(Primitive primitive) { return primitive == Primitive::Cylinder ? "cylinder" : "box"; }

LightMaps lightMapsFor(const view::Lighting& lighting) {
  if (!lighting.keyFill() || (lighting.shadowRays == 0 && lighting.occlusionRays == 0)) return {};
  // Measured against Embree's expected values on 1CRN at 96² (tests/gl/gl_lighting_test.cpp,
  // colour p99 with silhouettes and depth darkening; `compare --preset effects` allows 0.02):
  // the ambient term alone 0.021 with 64 maps, 0.017 with 128; the key term alone 0.018 with
  // 0.16 Å texels, 0.013 with 0.08 Å; more key maps than 16 change nothing. soft: 0.0224 (key
  // maps at 0.08 Å: 0.0204; and 256 ambient maps: 0.0179, but finer key maps hold every map at
  // the key maps' size, too large for a molecule of 40 Å on llvmpipe); full: 0.0199.
  if (lighting.preset == view::LightingPreset::Full) return LightMaps{32, 128, 0.12, 0};
  return LightMaps{16, 128, 0.16, 0};
}

namespace {

// Runs f(row, Kind{}) for each row of GpuKinds (gpu_kinds.hpp), in order.
template <class F> void forEachGpuKind(F&& f) {
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (f(I, std::tuple_element_t<I, GpuKinds>{}), ...);
  }(std::make_index_sequence<kGpuKindCount>{});
}

}  // namespace

struct GlRenderer::Impl {
  // Per row of GpuKinds: the kind's program, its record and atom buffers, its patch count.
  GLuint programs[kGpuKindCount] = {};
  GLuint peelProgram = 0;  // peel.glsl: composite a layer, resolve
  GLuint peelBuffer = 0;   // the uniform block Peel (GpuPeel)
  // The spheres' blockers (build/sphere_blockers.hpp), uploaded by the first transparent draw
  // after an upload; the spheres and surface they are made from until then.
  GLuint blockerBuffer = 0, blockerListBuffer = 0;
  bool blockersUploaded = false;
  double grow = 0.0;
  std::optional<build::SphereBlockers> givenBlockers;
  build::SurfaceParams params;
  std::vector<glm::dvec3> sphereCenters;
  std::vector<double> sphereRadii;
  std::vector<std::uint32_t> sphereAtoms;
  // Peeling targets: two layers (colour, t) in turn, the accumulated colour and layer count,
  // and the resolve's view of targets[0].
  GLuint peelFbo[2] = {}, peelColor[2] = {}, peelDepth[2] = {}, peelZ[2] = {};
  GLuint accumFbo = 0, accumColor = 0, accumLayers = 0, resolveFbo = 0;
  GLuint query = 0;
  bool transparent = false;  // the last draw peeled: readBack reports its layer counts
  int passes = 0;            // peeling passes the last draw ran
  GLuint records[kGpuKindCount] = {}, atoms[kGpuKindCount] = {};
  std::size_t counts[kGpuKindCount] = {};
  // The ball-and-stick model's balls and sticks (rows Ball, Stick): programs, buffers, counts.
  static constexpr const char* kModelShaders[2] = {"ball", "stick"};
  GLuint modelPrograms[2] = {};
  GLuint modelRecords[2] = {}, modelAtoms[2] = {};
  std::size_t modelCounts[2] = {};
  // The model's colour and (t, viewZ), copied aside for a transparent draw (OpaqueLayer).
  GLuint modelColor = 0, modelDepth = 0;
  view::PatchIdOrder ids;
  GLuint vao = 0;
  GLuint atomColorBuffer = 0;
  GLuint skinAtomBuffer = 0, skinGridBuffer = 0;  // GpuPatches::skinAtoms, skinGrid
  GLuint frameBuffer = 0;  // the uniform block
  GLuint clipBuffer = 0, clipTexture = 0;
  GLuint countBuffer = 0;  // (fragments, hits) per patch, GlOptions::countFragments
  bool counted = false;
  glm::dvec3 origin{0.0}, boundsCenter{0.0};
  double boundsRadius = 0.0;
  bool uploaded = false;
  // Render targets: colour, (t, viewZ), normal, (kind, patch id, atom, flags), depth.
  GLuint fbo = 0, targets[4] = {}, depth = 0;
  int width = 0, height = 0;
  // The light maps (LightMaps): a depth texture array of `lightLayers` layers of lightSize²,
  // the framebuffer that draws into one layer, the maps' records (GpuLightMap).
  GLuint lightTexture = 0, lightFbo = 0, lightBuffer = 0;
  int lightSize = 0, lightLayers = 0;

  ~Impl() {
    for (GLuint p : programs)
      if (p != 0) glDeleteProgram(p);
    for (GLuint p : modelPrograms)
      if (p != 0) glDeleteProgram(p);
    glDeleteBuffers(2, modelRecords);
    glDeleteBuffers(2, modelAtoms);
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(static_cast<GLsizei>(kGpuKindCount), records);
    glDeleteBuffers(static_cast<GLsizei>(kGpuKindCount), atoms);
    glDeleteBuffers(1, &atomColorBuffer);
    glDeleteBuffers(1, &skinAtomBuffer);
    glDeleteBuffers(1, &skinGridBuffer);
    glDeleteBuffers(1, &frameBuffer);
    glDeleteBuffers(1, &clipBuffer);
    glDeleteBuffers(1, &countBuffer);
    glDeleteTextures(1, &clipTexture);
    if (peelProgram != 0) glDeleteProgram(peelProgram);
    glDeleteBuffers(1, &peelBuffer);
    glDeleteBuffers(1, &blockerBuffer);
    glDeleteBuffers(1, &blockerListBuffer);
    glDeleteQueries(1, &query);
    glDeleteBuffers(1, &lightBuffer);
    releaseLightTargets();
    releaseTargets();
  }

  void releaseLightTargets() {
    glDeleteTextures(1, &lightTexture);
    glDeleteFramebuffers(1, &lightFbo);
    lightTexture = lightFbo = 0;
    lightSize = lightLayers = 0;
  }

  // One draw per kind, its records and atoms bound to the two slots every kind's program reads.
  void drawPatches() {
    for (std::size_t row = 0; row < kGpuKindCount; ++row) {
      if (counts[row] == 0) continue;
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kRecordBinding, records[row]);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kAtomBinding, atoms[row]);
      glUseProgram(programs[row]);
      glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(counts[row]));
    }
  }

  // The depth texture array of `layers` maps of size², read texel by texel (texelFetch): the
  // shading compares each texel of a lookup's footprint with the point's own tangent plane
  // there and filters the results itself (fragment_common.glsl, lightMapLit).
  void ensureLightTargets(int size, int layers) {
    if (size == lightSize && layers == lightLayers) return;
    releaseLightTargets();
    GLint maxSize = 0, maxLayers = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    if (size > maxSize || layers > maxLayers)
      throw std::invalid_argument("gl engine: " + std::to_string(layers) + " light maps of " + std::to_string(size) +
                                  "² exceed the driver's limits (" + std::to_string(maxLayers) +
                                  " layers of at most " + std::to_string(maxSize) + "²): use --engine embree");
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &lightTexture);
    glTextureStorage3D(lightTexture, 1, GL_DEPTH_COMPONENT32F, size, size, layers);
    glTextureParameteri(lightTexture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(lightTexture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(lightTexture, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    glCreateFramebuffers(1, &lightFbo);
    glNamedFramebufferDrawBuffer(lightFbo, GL_NONE);
    glNamedFramebufferReadBuffer(lightFbo, GL_NONE);
    checkGlError("creating the light maps");
    lightSize = size;
    lightLayers = layers;
  }

  // Draws the light maps of `o` (lightMapsFor, or gl.lightMaps) and binds them for the shading;
  // sets f.lightMaps and f.lightMapScale (both zero: none). Each map is the scene (patches and
  // ball-and-stick model) drawn by the kinds' own programs with a frame block of its own: an
  // orthographic camera looking at the bounding ball's centre along −d from outside the ball,
  // its square window the ball's width, writing the ray distance t times the frame's depth
  // scale (writeHit's gl_FragDepth) as depth. The key light's maps follow the camera; all share
  // one window size and depth scale.
  void drawLightMaps(const view::RenderOptions& o, const GlOptions& gl, GpuFrame& f) {
    glBindTextureUnit(kLightMapUnit, 0);  // never read while drawn into
    f.lightMaps = glm::uvec4(0u);
    f.lightMapScale = glm::vec4(0.0f);
    const LightMaps maps = gl.lightMaps ? *gl.lightMaps : lightMapsFor(o.lighting);
    if (!o.lighting.keyFill() || maps.key + maps.ambient == 0) return;
    // The window holds the ball with a texel to spare on each side (the bilinear footprint).
    // The key light's maps may have finer texels (keyTexel) than the ambient ones: each map is
    // drawn into the corner of its layer that its own side covers; the rest stays cleared (lit).
    const double radius = std::max(boundsRadius, 1e-3);
    auto sideOf = [&](double texel) {
      return maps.size > 0 ? maps.size
             : texel > 0.0 ? static_cast<int>(std::min<double>(kMaxLightMapSize, std::ceil(2.0 * radius / texel) + 2.0))
                           : 0;
    };
    const int ambientSide = sideOf(maps.texel);
    const int keySide = maps.keyTexel > 0.0 ? sideOf(maps.keyTexel) : ambientSide;
    const int side = std::max(maps.key > 0 ? keySide : 0, maps.ambient > 0 ? ambientSide : 0);
    if (maps.key < 0 || maps.ambient < 0 || maps.key > 4096 || maps.ambient > 4096 ||
        std::min(maps.key > 0 ? keySide : side, maps.ambient > 0 ? ambientSide : side) < 8 || side > kMaxLightMapSize)
      throw std::invalid_argument("gl engine: light maps " + std::to_string(maps.key) + " key of " +
                                  std::to_string(keySide) + "², " + std::to_string(maps.ambient) + " ambient of " +
                                  std::to_string(ambientSide) + "²: the counts must be in [0, 4096], the sides in [8, " +
                                  std::to_string(kMaxLightMapSize) + "]");
    const int layers = maps.key + maps.ambient;
    ensureLightTargets(side, layers);

    std::vector<glm::dvec3> directions;
    directions.reserve(static_cast<std::size_t>(layers));
    const view::Camera& cam = o.camera;
    const view::LightDirections lights = view::lightDirections(cam.right(), cam.trueUp(), cam.forward());
    // The key light's disc: the lattice of trace/render.cpp's keyVisibility without its
    // per-pixel rotation (a map serves every pixel), uniform in area on the disc.
    glm::dvec3 t, b;
    view::tangentFrame(lights.key, t, b);
    for (int i = 0; i < maps.key; ++i)
      directions.push_back(view::keyDiscDirection(lights.key, t, b, o.lighting.keyRadius, view::latticePoint(i, maps.key)));
    // The ambient maps: a Fibonacci sphere, equal areas, the same in every frame.
    for (int i = 0; i < maps.ambient; ++i) directions.push_back(view::fibonacciSphere(i, maps.ambient));

    const double distance = radius + std::max(1.0, 0.01 * radius);
    view::RenderOptions mapOptions;
    mapOptions.camera.projection = view::Projection::Orthographic;
    mapOptions.camera.lookAt = boundsCenter;
    GlOptions mapGl = gl;
    mapGl.countFragments = false;
    std::vector<GpuLightMap> mapRecords(directions.size());
    float depthScale = 0.0f;
    const float farDepth = 1.0f;
    glBindFramebuffer(GL_FRAMEBUFFER, lightFbo);
    for (std::size_t i = 0; i < directions.size(); ++i) {
      const glm::dvec3& d = directions[i];
      const int mapSide = static_cast<int>(i) < maps.key ? keySide : ambientSide;
      const double half = radius * (1.0 + 2.0 / mapSide);
      view::Camera& c = mapOptions.camera;
      c.width = c.height = mapSide;
      c.orthoHeight = 2.0 * half;
      c.eye = boundsCenter + distance * d;
      c.up = std::abs(d.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
      const GpuFrame mf = frameBlock(mapOptions, mapGl, 0, origin, boundsCenter, boundsRadius, ids);
      glNamedBufferData(frameBuffer, sizeof(mf), &mf, GL_STREAM_DRAW);
      glNamedFramebufferTextureLayer(lightFbo, GL_DEPTH_ATTACHMENT, lightTexture, 0, static_cast<GLint>(i));
      glClearNamedFramebufferfv(lightFbo, GL_DEPTH, 0, &farDepth);  // the whole layer
      glViewport(0, 0, mapSide, mapSide);
      drawModel();
      drawPatches();
      // (u, v, depth) of a point, as the map's camera rays see it (Camera::ray, writeHit): u and
      // v in the map's texels (texel k's centre at k + 0.5), depth in depth units.
      depthScale = mf.viewport.w;
      const glm::dvec3 eye = c.eye - origin, right = c.right(), up = c.trueUp(), forward = c.forward();
      const double toTexel = mapSide / (2.0 * half);
      mapRecords[i].toMapX = vec4Of(right * toTexel, 0.5 * mapSide - glm::dot(eye, right) * toTexel);
      mapRecords[i].toMapY = vec4Of(up * toTexel, 0.5 * mapSide - glm::dot(eye, up) * toTexel);
      mapRecords[i].toMapZ = vec4Of(forward * static_cast<double>(depthScale), -glm::dot(eye, forward) * depthScale);
      mapRecords[i].direction = glm::vec4(glm::vec3(d), static_cast<float>(2.0 * half / mapSide));
    }
    bufferData(lightBuffer, mapRecords);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kLightMapBinding, lightBuffer);
    glBindTextureUnit(kLightMapUnit, lightTexture);
    checkGlError("drawing the light maps");
    f.lightMaps = glm::uvec4(static_cast<unsigned>(maps.key), static_cast<unsigned>(maps.ambient), 0u, 0u);
    f.lightMapScale = glm::vec4(0.0f, depthScale, 0.0f, 0.0f);
  }

  // The model's records in float, shifted by −origin in double first (as packPatches does), and
  // the depth mapping's bounding ball grown to hold them (`alone`: there is no surface).
  void uploadModel(const build::BallStickModel* model, const glm::dvec3& shift, bool alone) {
    Impl& m = *this;
    std::vector<glm::vec4> balls, sticks;
    std::vector<std::uint32_t> ballAtoms;
    std::vector<glm::uvec2> stickAtoms;
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    if (model) {
      const double stick = model->stickRadius;
      for (std::size_t i = 0; i < model->centers.size(); ++i) {
        const glm::dvec3 c = model->centers[i] - shift;
        balls.emplace_back(glm::vec3(c), static_cast<float>(model->ballRadii[i]));
        ballAtoms.push_back(static_cast<std::uint32_t>(i));
        const double reach = std::max(model->ballRadii[i], stick);
        lo = glm::min(lo, c - reach);
        hi = glm::max(hi, c + reach);
      }
      for (const glm::uvec2& b : model->bonds) {
        sticks.emplace_back(glm::vec3(model->centers[b.x] - shift), static_cast<float>(stick));
        sticks.emplace_back(glm::vec3(model->centers[b.y] - shift), 0.0f);
        stickAtoms.push_back(b);
      }
    }
    bufferData(m.modelRecords[0], balls);
    bufferData(m.modelAtoms[0], ballAtoms);
    bufferData(m.modelRecords[1], sticks);
    bufferData(m.modelAtoms[1], stickAtoms);
    checkGlError("uploading the ball-and-stick model");
    m.modelCounts[0] = balls.size();
    m.modelCounts[1] = stickAtoms.size();
    if (balls.empty()) return;
    const glm::dvec3 center = shift + 0.5 * (lo + hi);
    const double radius = 0.5 * glm::length(hi - lo);
    if (alone) {
      m.boundsCenter = center;
      m.boundsRadius = radius;
    } else {  // the ball around both
      const double d = glm::length(center - m.boundsCenter);
      const double grown = std::max(m.boundsRadius, d + radius);
      m.boundsRadius = grown;
    }
  }

  void releaseTargets() {
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(4, targets);
    glDeleteRenderbuffers(1, &depth);
    fbo = depth = 0;
    std::fill(std::begin(targets), std::end(targets), 0u);
    width = height = 0;
    releasePeelTargets();
  }

  void releasePeelTargets() {
    glDeleteTextures(1, &modelColor);
    glDeleteTextures(1, &modelDepth);
    modelColor = modelDepth = 0;
    glDeleteFramebuffers(2, peelFbo);
    glDeleteTextures(2, peelColor);
    glDeleteTextures(2, peelDepth);
    glDeleteRenderbuffers(2, peelZ);
    glDeleteFramebuffers(1, &accumFbo);
    glDeleteFramebuffers(1, &resolveFbo);
    glDeleteTextures(1, &accumColor);
    glDeleteTextures(1, &accumLayers);
    for (int i = 0; i < 2; ++i) peelFbo[i] = peelColor[i] = peelDepth[i] = peelZ[i] = 0;
    accumFbo = resolveFbo = accumColor = accumLayers = 0;
  }

  static void checkComplete(GLuint framebuffer, const char* what) {
    const GLenum status = glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER);
    checkGlError(what);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error(std::string("OpenGL: ") + what + " are not complete, status 0x" + std::to_string(status));
  }

  // Draws the ball-and-stick model, opaque, into the bound targets; whether there was one.
  bool drawModel() {
    bool drawn = false;
    for (int k = 0; k < 2; ++k) {
      if (modelCounts[k] == 0) continue;
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kRecordBinding, modelRecords[k]);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kAtomBinding, modelAtoms[k]);
      glUseProgram(modelPrograms[k]);
      glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(modelCounts[k]));
      drawn = true;
    }
    return drawn;
  }

  // The drawn model's colour and (t, viewZ) targets, copied into textures of their own.
  OpaqueLayer copyModelLayer() {
    if (modelColor == 0) {
      glCreateTextures(GL_TEXTURE_2D, 1, &modelColor);
      glCreateTextures(GL_TEXTURE_2D, 1, &modelDepth);
      glTextureStorage2D(modelColor, 1, GL_RGBA32F, width, height);
      glTextureStorage2D(modelDepth, 1, GL_RG32F, width, height);
    }
    glCopyImageSubData(targets[0], GL_TEXTURE_2D, 0, 0, 0, 0, modelColor, GL_TEXTURE_2D, 0, 0, 0, 0, width, height, 1);
    glCopyImageSubData(targets[1], GL_TEXTURE_2D, 0, 0, 0, 0, modelDepth, GL_TEXTURE_2D, 0, 0, 0, 0, width, height, 1);
    checkGlError("copying the ball-and-stick model's layer");
    return OpaqueLayer{modelColor, modelDepth};
  }

  // The peeling targets at the size of the main ones (ensureTargets first).
  void ensurePeelTargets() {
    if (accumFbo != 0) return;
    glCreateFramebuffers(2, peelFbo);
    glCreateTextures(GL_TEXTURE_2D, 2, peelColor);
    glCreateTextures(GL_TEXTURE_2D, 2, peelDepth);
    glCreateRenderbuffers(2, peelZ);
    const GLenum layerDraw[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_NONE, GL_NONE};
    for (int i = 0; i < 2; ++i) {
      glTextureStorage2D(peelColor[i], 1, GL_RGBA32F, width, height);
      glTextureStorage2D(peelDepth[i], 1, GL_RG32F, width, height);
      glNamedRenderbufferStorage(peelZ[i], GL_DEPTH_COMPONENT32F, width, height);
      glNamedFramebufferTexture(peelFbo[i], GL_COLOR_ATTACHMENT0, peelColor[i], 0);
      glNamedFramebufferTexture(peelFbo[i], GL_COLOR_ATTACHMENT1, peelDepth[i], 0);
      glNamedFramebufferRenderbuffer(peelFbo[i], GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, peelZ[i]);
      glNamedFramebufferDrawBuffers(peelFbo[i], 4, layerDraw);
      checkComplete(peelFbo[i], "the peeling layer targets (RGBA32F, RG32F, depth 32F)");
    }
    glCreateTextures(GL_TEXTURE_2D, 1, &accumColor);
    glCreateTextures(GL_TEXTURE_2D, 1, &accumLayers);
    glTextureStorage2D(accumColor, 1, GL_RGBA32F, width, height);
    glTextureStorage2D(accumLayers, 1, GL_R32F, width, height);
    glCreateFramebuffers(1, &accumFbo);
    glNamedFramebufferTexture(accumFbo, GL_COLOR_ATTACHMENT0, accumColor, 0);
    glNamedFramebufferTexture(accumFbo, GL_COLOR_ATTACHMENT1, accumLayers, 0);
    const GLenum accumDraw[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(accumFbo, 2, accumDraw);
    checkComplete(accumFbo, "the peeling accumulation targets (RGBA32F, R32F)");
    glCreateFramebuffers(1, &resolveFbo);
    glNamedFramebufferTexture(resolveFbo, GL_COLOR_ATTACHMENT0, targets[0], 0);
    const GLenum resolveDraw[2] = {GL_COLOR_ATTACHMENT0, GL_NONE};
    glNamedFramebufferDrawBuffers(resolveFbo, 2, resolveDraw);
    checkComplete(resolveFbo, "the peeling resolve target");
  }

  // Uploads the spheres' blockers (origin-shifted), computing them from the spheres alone when
  // upload was given none.
  void ensureBlockers() {
    if (blockersUploaded) return;
    const build::SphereBlockers b = givenBlockers ? std::move(*givenBlockers)
                                                  : build::sphereBlockers(params, sphereCenters, sphereRadii, sphereAtoms, {});
    givenBlockers.reset();
    std::vector<glm::vec4> blockers;
    blockers.reserve(b.blockers.size());
    for (const glm::dvec4& o : b.blockers) blockers.push_back(vec4Of(glm::dvec3(o) - origin, o.w));
    // The saddle arcs (three vec4 each: centre and radius, e1 and extent, e2) after the
    // blockers; their CSR, as indices into the blockers' array, after the blockers' CSR.
    const std::uint32_t arcBase = static_cast<std::uint32_t>(blockers.size());
    for (const build::SaddleArc& a : b.arcs) {
      blockers.push_back(vec4Of(a.center - origin, a.radius));
      blockers.push_back(vec4Of(a.e1, a.extent));
      blockers.push_back(vec4Of(a.e2, 0.0));
    }
    const std::uint32_t offset = static_cast<std::uint32_t>(2 * b.begin.size());
    std::vector<std::uint32_t> list;
    list.reserve(2 * b.begin.size() + b.list.size());
    for (std::uint32_t i : b.begin) list.push_back(offset + i);
    for (std::size_t i = 0; i < b.begin.size(); ++i)
      list.push_back(arcBase + 3 * (b.arcBegin.empty() ? 0u : b.arcBegin[i]));
    list.insert(list.end(), b.list.begin(), b.list.end());
    bufferData(blockerBuffer, blockers);
    bufferData(blockerListBuffer, list);
    grow = b.grow;
    blockersUploaded = true;
    checkGlError("uploading the spheres' blockers");
  }

  void ensureTargets(int w, int h) {
    if (w == width && h == height) return;
    releaseTargets();
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    if (w > maxSize || h > maxSize)
      throw std::invalid_argument("gl engine: image " + std::to_string(w) + "x" + std::to_string(h) +
                                  " exceeds the driver's largest render target, " + std::to_string(maxSize));
    const GLenum formats[4] = {GL_RGBA32F, GL_RG32F, GL_RGBA32F, GL_RGBA32UI};
    glCreateTextures(GL_TEXTURE_2D, 4, targets);
    glCreateFramebuffers(1, &fbo);
    for (int i = 0; i < 4; ++i) {
      glTextureStorage2D(targets[i], 1, formats[i], w, h);
      glNamedFramebufferTexture(fbo, static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i), targets[i], 0);
    }
    glCreateRenderbuffers(1, &depth);
    glNamedRenderbufferStorage(depth, GL_DEPTH_COMPONENT32F, w, h);
    glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    const GLenum draw[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
    glNamedFramebufferDrawBuffers(fbo, 4, draw);
    const GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
    checkGlError("creating the render targets");
    if (status != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("OpenGL: the render targets (RGBA32F, RG32F, RGBA32F, RGBA32UI, depth 32F) are not "
                               "complete, status 0x" + std::to_string(status));
    width = w;
    height = h;
  }
};

GlRenderer::GlRenderer(const GlContext& context) : impl_(std::make_unique<Impl>()) {
  context.makeCurrent();
  Impl& m = *impl_;
  forEachGpuKind([&](std::size_t row, auto kind) { m.programs[row] = linkProgram(decltype(kind)::shader); });
  for (int k = 0; k < 2; ++k) m.modelPrograms[k] = linkProgram(Impl::kModelShaders[k]);
  glCreateBuffers(2, m.modelRecords);
  glCreateBuffers(2, m.modelAtoms);
  glCreateVertexArrays(1, &m.vao);
  glCreateBuffers(static_cast<GLsizei>(kGpuKindCount), m.records);
  glCreateBuffers(static_cast<GLsizei>(kGpuKindCount), m.atoms);
  glCreateBuffers(1, &m.atomColorBuffer);
  glCreateBuffers(1, &m.skinAtomBuffer);
  glCreateBuffers(1, &m.skinGridBuffer);
  glCreateBuffers(1, &m.frameBuffer);
  glCreateBuffers(1, &m.clipBuffer);
  glCreateBuffers(1, &m.countBuffer);
  glCreateTextures(GL_TEXTURE_BUFFER, 1, &m.clipTexture);
  m.peelProgram = linkProgram("peel", true);
  glCreateBuffers(1, &m.peelBuffer);
  glCreateBuffers(1, &m.blockerBuffer);
  glCreateBuffers(1, &m.blockerListBuffer);
  glCreateQueries(GL_ANY_SAMPLES_PASSED, 1, &m.query);
  glCreateBuffers(1, &m.lightBuffer);
  checkGlError("creating the GL renderer");
}

GlRenderer::~GlRenderer() = default;

unsigned GlRenderer::program(view::PatchKind kind) const { return impl_->programs[view::kindRow(kind)]; }

void GlRenderer::upload(const build::PatchList& patches, const glm::dvec3& origin, const build::SphereBlockers* blockers,
                        const build::BallStickModel* model) {
  Impl& m = *impl_;
  if (blockers && blockers->begin.size() != patches.convex.center.size() + 1)
    throw std::invalid_argument("GlRenderer::upload: the sphere blockers are of " +
                                std::to_string(blockers->begin.size() - std::min<std::size_t>(blockers->begin.size(), 1)) +
                                " spheres, the patch list has " + std::to_string(patches.convex.center.size()));
  m.givenBlockers.reset();
  if (blockers) m.givenBlockers = *blockers;
  m.blockersUploaded = false;
  m.params = patches.params;
  m.sphereCenters = patches.convex.center;
  m.sphereRadii = patches.convex.radius;
  m.sphereAtoms = patches.convex.atom;
  const GpuPatches g = packPatches(patches, origin);
  std::array<std::size_t, view::kPatchKindCount> counts{};
  forEachGpuKind([&](std::size_t row, auto kind) {
    const auto& k = g.of<decltype(kind)>();
    bufferData(m.records[row], k.records);
    bufferData(m.atoms[row], k.atoms);
    counts[row] = k.records.size();
  });
  bufferData(m.clipBuffer, g.clipPlanes);
  bufferData(m.skinAtomBuffer, g.skinAtoms);
  bufferData(m.skinGridBuffer, g.skinGrid);
  // Re-attach: the buffer's data store was just re-specified.
  glTextureBuffer(m.clipTexture, GL_RGBA32F, m.clipBuffer);
  checkGlError("uploading the patches");
  std::copy(counts.begin(), counts.begin() + kGpuKindCount, m.counts);
  m.origin = origin;
  m.boundsCenter = g.boundsCenter;
  m.boundsRadius = g.boundsRadius;
  m.uploadModel(model, origin, patches.patchCount() == 0);
  counts[view::kindRow(view::PatchKind::Ball)] = m.modelCounts[0];
  counts[view::kindRow(view::PatchKind::Stick)] = m.modelCounts[1];
  m.ids = view::PatchIdOrder(counts);
  m.uploaded = true;
}

void GlRenderer::draw(const view::RenderOptions& o, std::span<const glm::vec3> atomColors, const GlOptions& gl,
                      const OpaqueLayer* opaque) {
  Impl& m = *impl_;
  if (!m.uploaded) throw std::logic_error("GlRenderer::draw before upload");
  const view::Camera& cam = o.camera;
  cam.validate();
  if (cam.window)
    throw std::invalid_argument(
        "gl engine: draws centred windows with square pixels; this camera's window is off-centre (a foreign "
        "projection matrix): use --engine embree");
  if (o.samplesPerPixel != 1 || o.shadows || o.aoSamples != 0)
    throw std::invalid_argument(
        "gl engine: renders one sample per pixel, and shadows and ambient occlusion only as --lighting soft or "
        "full (from light maps); drop --spp/--shadows/--ao or use --engine embree");
  if (!(o.opacity > 0.0 && o.opacity <= 1.0))
    throw std::invalid_argument("gl engine: opacity " + std::to_string(o.opacity) + " must be in (0, 1]");
  if (o.maxLayers < 1 || o.maxLayers > kMaxPeelLayers)
    throw std::invalid_argument("gl engine: max layers " + std::to_string(o.maxLayers) + " must be in [1, " +
                                std::to_string(kMaxPeelLayers) + "]");
  if (gl.maxSteps < 1 || gl.maxSteps > 10000) throw std::invalid_argument("gl engine: sphere-tracing steps must be in [1, 10000]");
  if (!(gl.traceEpsilon > 0.0)) throw std::invalid_argument("gl engine: sphere-tracing epsilon must be > 0");
  if (!(gl.mergeDistance >= 0.0 && gl.mergeRelative >= 0.0))
    throw std::invalid_argument("gl engine: the peeling merge distances must be >= 0");
  if (opaque && (opaque->color == 0 || opaque->depth == 0))
    throw std::invalid_argument("gl engine: an opaque layer needs both its colour and its depth texture");
  m.ensureTargets(cam.width, cam.height);
  const bool transparent = o.opacity < 1.0;

  GpuFrame f = frameBlock(o, gl, atomColors.size(), m.origin, m.boundsCenter, m.boundsRadius, m.ids);
  glNamedBufferData(m.frameBuffer, sizeof(f), &f, GL_STREAM_DRAW);
  std::vector<glm::vec4> colors;
  colors.reserve(atomColors.size());
  for (const glm::vec3& c : atomColors) colors.emplace_back(c, 1.0f);
  bufferData(m.atomColorBuffer, colors);
  const GpuPeel off{};  // the opaque draw: every bound off
  glNamedBufferData(m.peelBuffer, sizeof(off), &off, GL_STREAM_DRAW);

  const float inf = std::numeric_limits<float>::infinity();
  const float clearColor[4] = {o.background.r, o.background.g, o.background.b, 0.0f};
  const float clearDepth[4] = {inf, inf, 0.0f, 0.0f};
  const float clearNormal[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  const GLuint clearIds[4] = {0u, ~0u, ~0u, 0u};
  const float farDepth = 1.0f;
  glClearNamedFramebufferfv(m.fbo, GL_COLOR, 0, clearColor);
  glClearNamedFramebufferfv(m.fbo, GL_COLOR, 1, clearDepth);
  glClearNamedFramebufferfv(m.fbo, GL_COLOR, 2, clearNormal);
  glClearNamedFramebufferuiv(m.fbo, GL_COLOR, 3, clearIds);
  glClearNamedFramebufferfv(m.fbo, GL_DEPTH, 0, &farDepth);

  glBindFramebuffer(GL_FRAMEBUFFER, m.fbo);
  glViewport(0, 0, cam.width, cam.height);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glBindVertexArray(m.vao);
  glBindBufferBase(GL_UNIFORM_BUFFER, kFrameBinding, m.frameBuffer);
  glBindBufferBase(GL_UNIFORM_BUFFER, kPeelBinding, m.peelBuffer);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kAtomColorBinding, m.atomColorBuffer);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSkinAtomBinding, m.skinAtomBuffer);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSkinGridBinding, m.skinGridBuffer);
  glBindTextureUnit(kClipPlaneUnit, m.clipTexture);
  const std::size_t patchCount = m.ids.total();
  const std::vector<glm::uvec2> zeros(gl.countFragments ? patchCount : 0, glm::uvec2(0u));
  bufferData(m.countBuffer, zeros);
  m.counted = gl.countFragments;
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kFragmentCountBinding, m.countBuffer);
  m.transparent = transparent;
  m.passes = 1;
  // The light maps first (soft shadows, occlusion), each into its own target with a frame block
  // of its own; then the camera's block again, with the maps' counts and scales.
  m.drawLightMaps(o, gl, f);
  glNamedBufferData(m.frameBuffer, sizeof(f), &f, GL_STREAM_DRAW);
  glBindFramebuffer(GL_FRAMEBUFFER, m.fbo);
  glViewport(0, 0, cam.width, cam.height);
  // The ball-and-stick model first, opaque, into the main targets and the depth buffer the
  // surface is then tested against.
  const bool model = m.drawModel();
  if (transparent) {
    m.ensureBlockers();
    m.ensurePeelTargets();
    // The model is the peels' opaque layer: its colour and (t, viewZ) copied aside, as layer 0
    // is then drawn over it into the main targets.
    OpaqueLayer modelLayer;
    if (model) {
      if (opaque) throw std::invalid_argument("GlRenderer::draw: an opaque layer and a ball-and-stick model; give one");
      modelLayer = m.copyModelLayer();
      opaque = &modelLayer;
    }
    peel(o, gl, opaque);
  } else {
    drawPatches();
  }
  glUseProgram(0);
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glFinish();
  checkGlError("drawing the patches");
}

void GlRenderer::drawPatches() { impl_->drawPatches(); }

// Depth peeling (Everitt 2001, "Interactive order-independent transparency"): pass k draws
// every patch into a cleared layer target and keeps, per pixel, the nearest hit beyond layer
// k − 1's t by the merge distance (peelAfter in fragment_common.glsl) and in front of the
// opaque depth; the layer is then composited under the ones before it. Layer 0 goes to the
// main targets, so the buffers are the nearest crossing's as in trace/render.cpp. The passes
// stop when one writes no fragment (an occlusion query) or after maxLayers.
void GlRenderer::peel(const view::RenderOptions& o, const GlOptions& gl, const OpaqueLayer* opaque) {
  Impl& m = *impl_;
  GpuPeel p{};
  p.flags = glm::uvec4(0u, opaque ? 1u : 0u, 1u, 0u);
  p.merge = glm::vec4(static_cast<float>(gl.mergeDistance), static_cast<float>(gl.mergeRelative),
                      static_cast<float>(m.grow), static_cast<float>(o.opacity));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBlockerBinding, m.blockerBuffer);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBlockerListBinding, m.blockerListBuffer);
  glBindTextureUnit(kOpaqueDepthUnit, opaque ? opaque->depth : 0u);
  glBindTextureUnit(kOpaqueColorUnit, opaque ? opaque->color : 0u);
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glClearNamedFramebufferfv(m.accumFbo, GL_COLOR, 0, zero);
  glClearNamedFramebufferfv(m.accumFbo, GL_COLOR, 1, zero);
  const float inf = std::numeric_limits<float>::infinity();
  const float clearDepth[4] = {inf, inf, 0.0f, 0.0f};
  const float farDepth = 1.0f;
  GLuint previous = 0;  // the (t, viewZ) texture of layer k − 1
  m.passes = 0;
  for (int k = 0; k < o.maxLayers; ++k) {
    const GLuint target = k == 0 ? m.fbo : m.peelFbo[k % 2];
    const GLuint color = k == 0 ? m.targets[0] : m.peelColor[k % 2];
    const GLuint depth = k == 0 ? m.targets[1] : m.peelDepth[k % 2];
    if (k > 0) {
      glClearNamedFramebufferfv(target, GL_COLOR, 1, clearDepth);
      glClearNamedFramebufferfv(target, GL_DEPTH, 0, &farDepth);
    }
    p.flags.x = k > 0 ? 1u : 0u;
    p.flags.w = 0u;
    glNamedBufferSubData(m.peelBuffer, 0, sizeof(p), &p);
    glBindTextureUnit(kPreviousLayerUnit, previous);
    glBindFramebuffer(GL_FRAMEBUFFER, target);
    glEnable(GL_DEPTH_TEST);
    glBeginQuery(GL_ANY_SAMPLES_PASSED, m.query);
    drawPatches();
    glEndQuery(GL_ANY_SAMPLES_PASSED);
    GLuint written = 0;
    glGetQueryObjectuiv(m.query, GL_QUERY_RESULT, &written);
    ++m.passes;
    if (written == 0) break;
    // Composite: (α c, α) under what is there, one more layer where the layer has a hit.
    glBindTextureUnit(kPreviousLayerUnit, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, m.accumFbo);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFuncSeparatei(0, GL_ONE_MINUS_DST_ALPHA, GL_ONE, GL_ONE_MINUS_DST_ALPHA, GL_ONE);
    glBlendFunci(1, GL_ONE, GL_ONE);
    glBindTextureUnit(kLayerColorUnit, color);
    glBindTextureUnit(kLayerDepthUnit, depth);
    glUseProgram(m.peelProgram);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisable(GL_BLEND);
    glBindTextureUnit(kLayerColorUnit, 0);
    glBindTextureUnit(kLayerDepthUnit, 0);
    previous = depth;
  }
  // Resolve into targets[0]: the layers over the opaque colour, or over the background.
  p.flags.w = 1u;
  glNamedBufferSubData(m.peelBuffer, 0, sizeof(p), &p);
  glBindTextureUnit(kPreviousLayerUnit, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, m.resolveFbo);
  glDisable(GL_DEPTH_TEST);
  glBindTextureUnit(kAccumulatedUnit, m.accumColor);
  glUseProgram(m.peelProgram);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindTextureUnit(kAccumulatedUnit, 0);
  glBindTextureUnit(kOpaqueDepthUnit, 0);
  glBindTextureUnit(kOpaqueColorUnit, 0);
  glEnable(GL_DEPTH_TEST);
}

int GlRenderer::peelPasses() const { return impl_->passes; }

std::vector<glm::uvec2> GlRenderer::fragmentCounts() const {
  const Impl& m = *impl_;
  std::vector<glm::uvec2> counts;
  if (!m.counted) return counts;
  counts.resize(m.ids.total());
  if (!counts.empty())
    glGetNamedBufferSubData(m.countBuffer, 0, static_cast<GLsizeiptr>(counts.size() * sizeof(glm::uvec2)), counts.data());
  checkGlError("reading the fragment counts");
  return counts;
}

view::FrameBuffers GlRenderer::readBack() const {
  const Impl& m = *impl_;
  view::FrameBuffers fb;
  fb.reset(m.width, m.height);
  const std::size_t n = fb.pixels(), w = static_cast<std::size_t>(m.width), h = static_cast<std::size_t>(m.height);
  std::vector<float> color(4 * n), depth(2 * n), normal(4 * n);
  std::vector<GLuint> ids(4 * n);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(m.targets[0], 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(color.size() * sizeof(float)), color.data());
  glGetTextureImage(m.targets[1], 0, GL_RG, GL_FLOAT, static_cast<GLsizei>(depth.size() * sizeof(float)), depth.data());
  glGetTextureImage(m.targets[2], 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(normal.size() * sizeof(float)), normal.data());
  glGetTextureImage(m.targets[3], 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(ids.size() * sizeof(GLuint)),
                    ids.data());
  checkGlError("reading the frame back");

  const float inf = std::numeric_limits<float>::infinity();
  for (std::size_t y = 0; y < h; ++y) {
    // GL's row 0 is the bottom of the image, FrameBuffers' row 0 the top.
    const std::size_t src = (h - 1 - y) * w, dst = y * w;
    for (std::size_t x = 0; x < w; ++x) {
      const std::size_t s = src + x, d = dst + x;
      const bool hit = ids[4 * s] != 0u;
      for (int c = 0; c < 4; ++c) fb.rgba[4 * d + c] = color[4 * s + c];
      fb.depth[d] = hit ? depth[2 * s] : inf;
      fb.viewZ[d] = hit ? depth[2 * s + 1] : inf;
      for (int c = 0; c < 3; ++c) fb.normal[3 * d + c] = hit ? normal[4 * s + c] : 0.0f;
      fb.kind[d] = ids[4 * s];
      fb.patchId[d] = hit ? ids[4 * s + 1] : ~0u;
      fb.atomId[d] = hit ? ids[4 * s + 2] : ~0u;
    }
  }
  if (m.transparent) {
    std::vector<float> layers(n);
    glGetTextureImage(m.accumLayers, 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(layers.size() * sizeof(float)), layers.data());
    checkGlError("reading the layer counts back");
    fb.layers.resize(n);
    for (std::size_t y = 0; y < h; ++y)
      for (std::size_t x = 0; x < w; ++x) fb.layers[y * w + x] = static_cast<std::uint32_t>(layers[(h - 1 - y) * w + x]);
  }
  fb.rays = n;
  return fb;
}

view::FrameBuffers renderGl(const GlContext& context, const build::PatchList& patches,
                             const view::RenderOptions& options, std::span<const glm::vec3> atomColors,
                             const GlOptions& gl, const build::SphereBlockers* blockers,
                             const build::BallStickModel* model) {
  const auto start = std::chrono::steady_clock::now();
  GlRenderer renderer(context);
  view::FrameBuffers fb = renderGl(renderer, patches, options, atomColors, gl, blockers, model);
  fb.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return fb;
}

view::FrameBuffers renderGl(GlRenderer& renderer, const build::PatchList& patches, const view::RenderOptions& options,
                             std::span<const glm::vec3> atomColors, const GlOptions& gl,
                             const build::SphereBlockers* blockers, const build::BallStickModel* model) {
  const auto start = std::chrono::steady_clock::now();
  // The look-at point is the molecule's centre for framed views and near the surface for
  // close-ups: either way the coordinates the GPU sees are small (ORACLES D.4).
  renderer.upload(patches, options.camera.lookAt, blockers, model);
  renderer.draw(options, atomColors, gl);
  view::FrameBuffers fb = renderer.readBack();
  fb.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return fb;
}

GlTimings benchmarkGl(const GlContext& context, const build::PatchList& patches, const view::RenderOptions& options,
                      std::span<const glm::vec3> atomColors, const GlOptions& gl, int frames,
                      const build::SphereBlockers* blockers) {
  if (frames < 1) throw std::invalid_argument("benchmark: frames must be >= 1");
  GlRenderer renderer(context);
  using Clock = std::chrono::steady_clock;
  const glm::dvec3 origin = options.camera.lookAt;
  renderer.upload(patches, origin, blockers);
  renderer.draw(options, atomColors, gl);  // warm-up: shader compilation inside the driver, allocation
  std::vector<double> frame, draw;
  for (int i = 0; i < frames; ++i) {
    const auto t0 = Clock::now();
    renderer.upload(patches, origin, blockers);
    renderer.draw(options, atomColors, gl);
    frame.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  for (int i = 0; i < frames; ++i) {
    const auto t0 = Clock::now();
    renderer.draw(options, atomColors, gl);
    draw.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  GlTimings t;
  t.frames = frames;
  t.medianFrameSeconds = median(frame);
  t.medianDrawSeconds = median(draw);
  t.minDrawSeconds = *std::min_element(draw.begin(), draw.end());
  t.renderer = context.description();
  t.peelPasses = renderer.peelPasses();
  return t;
}

}  // namespace surftrace::gl
