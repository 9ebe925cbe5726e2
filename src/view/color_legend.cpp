// The colour bar with its range and label (color_legend.hpp).
#include "view/color_legend.hpp"

#include <algorithm>
#include <stdexcept>

#include "view/bitmap_font.hpp"
#include "view/color_map.hpp"
#include "view/srgb.hpp"

namespace surftrace::view {
namespace {

constexpr int kPad = 4, kGap = 3, kBarHeight = 10, kBarWidth = 128, kMargin = 4;

// Black on a light background, white on a dark one (Rec. 709 luma of the sRGB-encoded colour,
// as the image shows it; `background` is linear, as RenderOptions holds it).
glm::vec3 inkFor(const glm::vec3& background) {
  const glm::vec3 shown = linearToSrgb(background);
  const float luma = 0.2126f * shown.r + 0.7152f * shown.g + 0.0722f * shown.b;
  return luma > 0.5f ? glm::vec3(0.0f) : glm::vec3(1.0f);
}

// Paints the panel with its top-left corner at (x0, y0) of `f`.
void paint(FrameBuffers& f, int x0, int y0, const ColorLegend& legend, const glm::vec3& background, int scale) {
  const LegendLayout l = legendLayout(legend, scale);
  const ColorMap& map = ColorMap::named(legend.map);
  const glm::vec3 ink = inkFor(background);
  auto set = [&](int x, int y, const glm::vec3& c) {
    const int px = x0 + x, py = y0 + y;
    if (px < 0 || py < 0 || px >= f.width || py >= f.height) return;
    const std::size_t p = static_cast<std::size_t>(py) * static_cast<std::size_t>(f.width) + static_cast<std::size_t>(px);
    f.rgba[4 * p] = c.r, f.rgba[4 * p + 1] = c.g, f.rgba[4 * p + 2] = c.b, f.rgba[4 * p + 3] = 1.0f;
  };
  for (int y = 0; y < l.height; ++y)
    for (int x = 0; x < l.width; ++x) set(x, y, background);
  auto text = [&](const std::string& s, int x, int y) {
    forEachTextDot(s, [&](int dx, int dy) {
      for (int j = 0; j < scale; ++j)
        for (int i = 0; i < scale; ++i) set(x + dx * scale + i, y + dy * scale + j, ink);
    });
  };
  text(legend.label, kPad * scale, kPad * scale);
  // A frame of ink one font pixel wide around the bar, the bar inside it.
  for (int y = -scale; y < l.barHeight + scale; ++y)
    for (int x = -scale; x < l.barWidth + scale; ++x) set(l.barX + x, l.barY + y, ink);
  for (int x = 0; x < l.barWidth; ++x) {
    const glm::vec3 c = srgbToLinear(map.at((x + 0.5) / l.barWidth));  // the map's sRGB bytes in a PNG
    for (int y = 0; y < l.barHeight; ++y) set(l.barX + x, l.barY + y, c);
  }
  const int labelsY = l.barY + l.barHeight + (1 + kGap) * scale;
  text(legend.loText, l.barX, labelsY);
  text(legend.hiText, l.barX + l.barWidth - textWidth(legend.hiText) * scale, labelsY);
}

}  // namespace

LegendLayout legendLayout(const ColorLegend& legend, int scale) {
  LegendLayout l;
  l.scale = scale;
  l.barWidth = kBarWidth * scale;
  l.barHeight = kBarHeight * scale;
  const int ends = textWidth(legend.loText) + kGap + textWidth(legend.hiText);
  const int inner = std::max({kBarWidth + 2, textWidth(legend.label), ends});
  l.width = (2 * kPad + inner) * scale;
  l.barX = (kPad + 1) * scale;
  l.barY = (kPad + kGlyphHeight + kGap + 1) * scale;
  l.height = (kPad + kGlyphHeight + kGap + 1 + kBarHeight + 1 + kGap + kGlyphHeight + kPad) * scale;
  return l;
}

int legendScale(int width, int height) { return 1 + std::min(width, height) / 600; }

FrameBuffers legendImage(const ColorLegend& legend, const glm::vec3& background, int scale) {
  const LegendLayout l = legendLayout(legend, scale);
  FrameBuffers f;
  f.reset(l.width, l.height);
  paint(f, 0, 0, legend, background, scale);
  return f;
}

void checkLegendFits(int width, int height, const ColorLegend& legend) {
  const int scale = legendScale(width, height);
  const LegendLayout l = legendLayout(legend, scale);
  if (l.width + kMargin * scale > width || l.height + kMargin * scale > height)
    throw std::invalid_argument("--legend: the legend (" + std::to_string(l.width) + "x" + std::to_string(l.height) +
                                " pixels) does not fit a " + std::to_string(width) + "x" + std::to_string(height) +
                                " image: render it larger, or write the legend to its own file with --legend-file");
}

void drawLegend(FrameBuffers& f, const ColorLegend& legend, const glm::vec3& background) {
  checkLegendFits(f.width, f.height, legend);
  const int scale = legendScale(f.width, f.height);
  const LegendLayout l = legendLayout(legend, scale);
  paint(f, f.width - l.width - kMargin * scale, f.height - l.height - kMargin * scale, legend, background, scale);
}

}  // namespace surftrace::view
