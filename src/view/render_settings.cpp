// The render settings an image's metadata records, compared between two images (render_settings.hpp).
#include "view/render_settings.hpp"

#include <cstdio>
#include <functional>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

namespace surftrace::view {
namespace {

std::optional<std::string> recorded(const ImageMetadata& meta, const std::string& key) {
  const auto it = meta.find(key);
  if (it == meta.end()) return std::nullopt;
  return it->second;
}

// Comma-separated numbers to 6 digits ("1.000000" and "1" are one value); text that is not
// numbers stays as it is.
std::string numbers(const std::string& text) {
  std::istringstream in(text);
  std::string item, out;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || *end != '\0') return text;
    char n[32];
    std::snprintf(n, sizeof n, "%.6g", v);
    if (!out.empty()) out += ',';
    out += n;
  }
  return out;
}

std::string canonicalJson(const std::string& text) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  return j.is_discarded() ? text : j.dump();
}

// How one setting reads from an image's metadata: its canonical text, or nothing when the image
// does not record it.
struct Setting {
  const char* name;
  std::function<std::optional<std::string>(const ImageMetadata&)> read;
  // Compared only when this holds for both images (e.g. the uniform colour under --color uniform).
  std::function<bool(const ImageMetadata&)> applies = [](const ImageMetadata&) { return true; };
};

std::vector<Setting> settings() {
  auto plain = [](const char* key, std::string (*canon)(const std::string&)) {
    return [key, canon](const ImageMetadata& m) -> std::optional<std::string> {
      const auto v = recorded(m, key);
      if (!v) return std::nullopt;
      return canon(*v);
    };
  };
  // Recorded only when on: absent means off (every SurfTrace image that records a colour scheme).
  auto whenOn = [](const char* key, const char* off) {
    return [key, off](const ImageMetadata& m) -> std::optional<std::string> {
      if (const auto v = recorded(m, key)) return canonicalJson(*v);
      if (!recorded(m, "surftrace:color")) return std::nullopt;
      return std::string(off);
    };
  };
  auto opacity = [](const ImageMetadata& m) -> std::optional<std::string> {
    if (const auto v = recorded(m, "surftrace:opacity"))
      return numbers(*v) + " (" + numbers(recorded(m, "surftrace:max_layers").value_or("?")) + " layers)";
    if (!recorded(m, "surftrace:color")) return std::nullopt;
    return std::string("1 (opaque)");
  };
  auto lighting = [](const ImageMetadata& m) -> std::optional<std::string> {
    const auto v = recorded(m, "surftrace:lighting");
    if (!v) return std::nullopt;
    nlohmann::json j = nlohmann::json::parse(*v, nullptr, false);
    if (j.is_discarded()) return *v;
    // The ray length of ambient occlusion changes nothing without its rays.
    if (j.value("ao_samples", 0) == 0 && j.value("occlusion_rays", 0) == 0) j.erase("ao_distance");
    return j.dump();
  };
  auto uniform = [](const ImageMetadata& m) { return recorded(m, "surftrace:color").value_or("") == "uniform"; };
  return {{"colour scheme", plain("surftrace:color", [](const std::string& s) { return s; })},
          {"uniform colour", plain("surftrace:uniform_color", numbers), uniform},
          {"background", plain("surftrace:background", numbers)},
          {"lighting", lighting},
          {"samples per pixel", plain("surftrace:samples_per_pixel", numbers)},
          {"opacity", opacity},
          {"effects", whenOn("surftrace:effects", "none")},
          {"ball and stick", whenOn("surftrace:ball_and_stick", "none")},
          {"colour map", whenOn("surftrace:color_map", "none")},
          {"colour selections", whenOn("surftrace:color_select", "none")},
          {"legend", whenOn("surftrace:color_legend", "none")}};
}

}  // namespace

SettingsComparison compareSettings(const ImageMetadata& test, const ImageMetadata& reference) {
  SettingsComparison out;
  for (const Setting& s : settings()) {
    if (!s.applies(test) || !s.applies(reference)) continue;
    const auto a = s.read(test), b = s.read(reference);
    if (a && b && *a != *b) out.differences.push_back({s.name, *a, *b});
    if (!a && b) out.notRecordedInTest.emplace_back(s.name);
    if (a && !b) out.notRecordedInReference.emplace_back(s.name);
  }
  return out;
}

std::string describe(const std::vector<SettingDifference>& differences) {
  std::string text;
  for (const SettingDifference& d : differences) {
    if (!text.empty()) text += "; ";
    text += d.name + ": test " + d.test + ", reference " + d.reference;
  }
  return text;
}

}  // namespace surftrace::view
