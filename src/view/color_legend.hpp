// The colour bar of a colour map with its range and label: drawn into a frame's corner, or as an
// image of its own.
#pragma once

#include <cstddef>
#include <string>

#include <glm/vec3.hpp>

#include "view/frame_buffers.hpp"

namespace surftrace::view {

// What a colour scheme that maps numbers through a colour map shows (view/atom_colors.hpp).
struct ColorLegend {
  std::string map;
  double lo = 0.0, hi = 1.0;
  bool rangeFromData = true;   // min..max of the atoms' numbers, not --color-range
  std::string label;           // what the numbers are
  std::string loText, hiText;  // the bar's end labels
  std::size_t missing = 0;     // atoms without a number (kMissingColor)
};

// The legend's layout at `scale` image pixels per font pixel: the label on top, the bar (the
// map from lo at its left to hi at its right, pixel column i taking the map at (i + 0.5)/width),
// and the end labels under it, on a panel of the background colour (linear, as
// RenderOptions::background; the map's sRGB colours are decoded to it) with text in black or white
// (whichever stands out from it).
struct LegendLayout {
  int scale = 1;
  int width = 0, height = 0;        // the panel
  int barX = 0, barY = 0;           // the bar's top-left corner inside the panel
  int barWidth = 0, barHeight = 0;
};
LegendLayout legendLayout(const ColorLegend& legend, int scale);
// The scale a frame of this size draws its legend at: 1 up to 600 pixels on the shorter side,
// then one more per 600.
int legendScale(int width, int height);

// The legend as its own opaque image (its colour buffer only; the other buffers are misses).
FrameBuffers legendImage(const ColorLegend& legend, const glm::vec3& background, int scale);

// Draws the legend, opaque, into the bottom-right corner of `frame`'s colour (a margin of 4
// font pixels); the buffers other than colour are left as they are. std::invalid_argument when
// the frame is too small to hold it.
void drawLegend(FrameBuffers& frame, const ColorLegend& legend, const glm::vec3& background);
// The same check alone, before any work.
void checkLegendFits(int width, int height, const ColorLegend& legend);

}  // namespace surftrace::view
