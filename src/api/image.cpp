// Stage "write" and the record of how an image was made (surftrace/image.hpp).
#include "surftrace/image.hpp"

#include <cstdio>
#include <span>

#include <nlohmann/json.hpp>

#include "build/io/output_file.hpp"
#include "gl/gl_renderer.hpp"
#include "surftrace/version.hpp"

namespace surftrace {
namespace {

// %g-style text of a number: "1024", "0.5", "1e+06".
std::string shortNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace

ImageMetadata imageMetadata(const ImageRecord& r, const Camera& camera) {
  const std::string software = std::string("surftrace ") + version();
  ImageMetadata meta;
  meta["surftrace:renderer"] = r.renderer.empty() ? software : software + " " + r.renderer;
  meta["surftrace:engine"] = r.engine;
  meta["surftrace:camera"] = cameraToJson(camera);
  meta["surftrace:surface"] = r.surface;
  meta["surftrace:probe_radius"] = std::to_string(r.probeRadius);
  if (r.shrinkFactor) meta["surftrace:shrink_factor"] = std::to_string(*r.shrinkFactor);
  meta["surftrace:input"] = r.input;
  if (!r.trajectory.empty()) meta["surftrace:trajectory"] = r.trajectory;
  if (r.frame) meta["surftrace:frame"] = std::to_string(*r.frame);
  if (r.timePs) meta["surftrace:time_ps"] = std::to_string(*r.timePs);
  meta["surftrace:color"] = r.color;
  // Every setting that changes pixels is recorded, so that `compare` can tell two images made
  // alike from two made differently (it reads them back).
  auto triple = [](const glm::dvec3& v) { return shortNumber(v.x) + "," + shortNumber(v.y) + "," + shortNumber(v.z); };
  if (r.color == "uniform") meta["surftrace:uniform_color"] = triple(r.uniformColor);
  meta["surftrace:background"] =
      triple(r.background) + (r.backgroundAlpha < 1.0 ? "," + shortNumber(r.backgroundAlpha) : std::string());
  if (r.colorMap) {
    const ColorLegend& c = *r.colorMap;
    nlohmann::json j{{"map", c.map},
                     {"range", {c.lo, c.hi}},
                     {"range_from", c.rangeFromData ? "data" : "--color-range"},
                     {"label", c.label},
                     {"missing_atoms", c.missing},
                     {"missing_color", triple(glm::dvec3(view::kMissingColor))}};
    if (!r.valuesFile.empty()) j["values"] = r.valuesFile;
    meta["surftrace:color_map"] = j.dump();
  }
  if (!r.colorSelect.empty()) meta["surftrace:color_select"] = nlohmann::json(r.colorSelect).dump();
  if (r.legendInImage) meta["surftrace:color_legend"] = "image";
  if (!r.legendFile.empty()) meta["surftrace:color_legend_file"] = r.legendFile;
  nlohmann::json lighting{{"model", "Blinn-Phong headlight"},
                          {"ambient", r.lighting.ambient},
                          {"diffuse", r.lighting.diffuse},
                          {"specular", r.lighting.specular},
                          {"shininess", r.lighting.shininess},
                          {"shadows", r.shadows},
                          {"ao_samples", r.aoSamples},
                          {"ao_distance", r.aoDistance}};
  if (r.lighting.keyFill()) {
    lighting["model"] = std::string("key-fill ") + view::lightingPresetName(r.lighting.preset);
    lighting["fill"] = r.lighting.fill;
    lighting["shadow_rays"] = r.lighting.shadowRays;
    lighting["key_radius_degrees"] = r.lighting.keyRadius * 180.0 / 3.14159265358979323846;
    lighting["occlusion_rays"] = r.lighting.occlusionRays;
    lighting["filter_passes"] = r.lighting.filterPasses;
    // GL takes its shadows and occlusion from light maps, not rays (gl/gl_renderer.hpp): the
    // record names the maps it drew in place of the rays, the filter and the occlusion
    // distance, none of which it uses.
    if (r.engine == "gl") {
      const gl::LightMaps maps = gl::lightMapsFor(r.lighting);
      lighting.erase("shadow_rays");
      lighting.erase("occlusion_rays");
      lighting.erase("filter_passes");
      lighting.erase("ao_distance");
      if (maps.key + maps.ambient > 0)
        lighting["light_maps"] = {{"key", maps.key},
                                  {"ambient", maps.ambient},
                                  {"texel_angstrom", maps.texel},
                                  {"key_texel_angstrom", maps.keyTexel > 0.0 ? maps.keyTexel : maps.texel}};
    }
  }
  meta["surftrace:lighting"] = lighting.dump();
  meta["surftrace:samples_per_pixel"] = std::to_string(r.samplesPerPixel);
  meta["surftrace:command"] = r.commandLine;
  if (r.opacity < 1.0) {
    meta["surftrace:opacity"] = std::to_string(r.opacity);
    meta["surftrace:max_layers"] = std::to_string(r.maxLayers);
  }
  if (r.effects.any()) meta["surftrace:effects"] = r.effects.json(camera);
  if (r.ballAndStick)
    meta["surftrace:ball_and_stick"] = "{\"ball_scale\": " + shortNumber(r.ballScale) +
                                       ", \"stick_radius\": " + shortNumber(r.stickRadius) +
                                       ", \"bonds\": " + std::to_string(r.bonds) + "}";
  for (const auto& [key, value] : r.engineSettings) meta[key] = value;
  meta["Software"] = software;
  return meta;
}

EncodedFiles encodeImage(const std::string& png, const std::string& exr, const FrameBuffers& image,
                         const ImageRecord& record, const Camera& camera, int pngLevel) {
  const ImageMetadata meta = imageMetadata(record, camera);
  EncodedFiles files{png, exr, {}, {}};
  if (!png.empty()) files.pngBytes = view::encodePng(png, image, meta, pngLevel);
  if (!exr.empty()) files.exrBytes = view::encodeExr(exr, image, meta);
  return files;
}

void writeFiles(const EncodedFiles& files) {
  if (!files.png.empty())
    build::writeFileAtomically(files.png, std::as_bytes(std::span<const unsigned char>(files.pngBytes)));
  if (!files.exr.empty())
    build::writeFileAtomically(files.exr, std::as_bytes(std::span<const unsigned char>(files.exrBytes)));
}

void writeImage(const std::string& png, const std::string& exr, const FrameBuffers& image, const ImageRecord& record,
                const Camera& camera) {
  writeFiles(encodeImage(png, exr, image, record, camera));
}

}  // namespace surftrace
