// The render settings an image records in its metadata (imageMetadata, surftrace/image.hpp), read
// back so that `compare` can tell two images made alike from two made differently.
#pragma once

#include <string>
#include <vector>

#include "view/image_io.hpp"

namespace surftrace::view {

// One setting that changes pixels, as the two images record it (canonical text: numbers
// rounded to 6 digits, JSON re-serialised).
struct SettingDifference {
  std::string name;  // "colour scheme", "background", ...
  std::string test, reference;
};

struct SettingsComparison {
  std::vector<SettingDifference> differences;
  // Settings one image records and the other does not (an image from an older SurfTrace):
  // neither equal nor different.
  std::vector<std::string> notRecordedInTest, notRecordedInReference;
};

// The settings of two SurfTrace images compared: colour scheme (and the uniform colour),
// background, lighting (headlight terms, shadows, ambient occlusion), samples per pixel,
// opacity (and layers), image-space effects and the ball-and-stick model. Opacity, effects and
// the model are recorded only when they are on, so their absence means opaque, none, none.
SettingsComparison compareSettings(const ImageMetadata& test, const ImageMetadata& reference);

// "colour scheme: test element, reference patch; background: ..."
std::string describe(const std::vector<SettingDifference>& differences);

}  // namespace surftrace::view
