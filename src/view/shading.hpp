// Colour schemes and the lighting models shared by the Embree and GL paths.
#pragma once

#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace surftrace::view {

enum class ColorMode { Patch, Element, Chain, BFactor, Uniform, Residue, Hydrophobicity, Rainbow, Value };
ColorMode parseColorMode(const std::string& name);  // throws std::invalid_argument
const char* colorModeName(ColorMode mode);

// `--lighting`: Headlight (the default) is Blinn–Phong with a white light at the eye, so a
// concave pocket is brightest at its deepest point. The others light from a key light 45°
// above left of the eye, a weaker fill light below right and an ambient term (the key-fill model):
// Simple has nothing else; Soft adds soft shadows from an area key light and ambient occlusion
// (Embree by rays, GL by light maps: gl/gl_renderer.hpp, LightMaps), Full the same with more.
enum class LightingPreset { Headlight, Simple, Soft, Full };
LightingPreset parseLightingPreset(const std::string& name);  // throws std::invalid_argument
const char* lightingPresetName(LightingPreset preset);

// Headlight: c = base·(ambient + diffuse·max(0, n·e)) + specular·max(0, n·e)^shininess, e towards the eye.
// Key-fill (preset != Headlight): with k and f the unit directions towards the key and fill lights and
// h = normalize(k + e),
//   c = base·(ambient·A + diffuse·max(0, n·k)·S + fill·max(0, n·f)·A) + specular·S·[n·k > 0]·max(0, n·h)^shininess
// where S is the fraction of the key light that reaches the point (1 without shadows) and A
// the ambient visibility (1 without ambient occlusion). Both clamped to 1 per channel.
// The GL fragment shaders use these same numbers (GpuFrame::lighting, keyLight, fillLight).
struct Lighting {
  float ambient = 0.25f;
  float diffuse = 0.75f;  // the key light's diffuse weight in the key-fill model
  float specular = 0.25f;
  float shininess = 32.0f;
  LightingPreset preset = LightingPreset::Headlight;
  float fill = 0.0f;  // key-fill model only
  // Soft shadows (key-fill model): rays towards a disc of angular radius keyRadius (radians)
  // around the key direction; 0 rays: none (RenderOptions::shadows then casts one, to the centre).
  int shadowRays = 0;
  double keyRadius = 0.0;
  // Ambient-occlusion rays when RenderOptions::aoSamples is 0 (0: none).
  int occlusionRays = 0;
  // Embree: S and A traced with these few rays per hit, then smoothed over each smooth piece of
  // surface by this many edge-aware filter passes (trace/visibility_filter.hpp) before shading;
  // 0: each hit's own rays alone.
  int filterPasses = 0;

  bool keyFill() const { return preset != LightingPreset::Headlight; }
};

// The numbers of a preset (Headlight: Lighting{}).
Lighting lightingFor(LightingPreset preset);

// The unit directions towards the key and fill lights in the camera's frame: (right, true up,
// towards the eye) components. The key is 45° off the view axis, above left; the fill 46° off
// it, right and a little below.
inline constexpr glm::vec3 kKeyLightCamera{-0.5f, 0.5f, 0.70710678f};  // normalised where used
inline constexpr glm::vec3 kFillLightCamera{1.0f, -0.2f, 1.0f};

// The world directions of the two lights for a camera frame (right, up, forward unit vectors).
struct LightDirections {
  glm::dvec3 key, fill;
};
LightDirections lightDirections(const glm::dvec3& right, const glm::dvec3& up, const glm::dvec3& forward);

// Headlight shading (the key-fill terms are ignored).
glm::vec3 shade(const glm::vec3& base, const glm::dvec3& normal, const glm::dvec3& towardsEye, const Lighting& light);
// Either model: keyVisibility is S and ambientVisibility A above (the headlight model ignores both).
glm::vec3 shade(const glm::vec3& base, const glm::dvec3& normal, const glm::dvec3& towardsEye, const Lighting& light,
                const LightDirections& lights, float keyVisibility = 1.0f, float ambientVisibility = 1.0f);

// The directions both engines sample S and A along (Embree's rays, GL's light maps), so that the
// two estimate the same integrals:
// point i of n of a rank-1 (Fibonacci) lattice in the unit square, shifted by `rotation` modulo 1
// (a Cranley–Patterson rotation): stratified in u, low-discrepancy in (u, v);
glm::dvec2 latticePoint(int i, int n, const glm::dvec2& rotation = glm::dvec2(0.0));
// a unit vector t perpendicular to unit n, and b = n × t, the third of the right-handed frame;
void tangentFrame(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b);
// the direction towards the point of the key light's disc (angular radius `radius` around the
// unit key direction, t and b its tangentFrame) that lattice point q maps to, uniform in area;
glm::dvec3 keyDiscDirection(const glm::dvec3& key, const glm::dvec3& t, const glm::dvec3& b, double radius,
                            const glm::dvec2& q);
// direction i of n spread evenly over the unit sphere, equal areas (a Fibonacci sphere).
glm::dvec3 fibonacciSphere(int i, int n);

}  // namespace surftrace::view
