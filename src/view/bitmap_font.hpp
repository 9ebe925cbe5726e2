// A small bitmap font (5×7 capitals and digits, lower case with descenders in an 8-row cell) for
// the text a legend draws into an image: no font file, no library, the same pixels everywhere.
#pragma once

#include <functional>
#include <string>

namespace surftrace::view {

// Cell size in font pixels: each character advances kGlyphAdvance, a line is kGlyphHeight.
inline constexpr int kGlyphWidth = 5, kGlyphAdvance = 6, kGlyphHeight = 8;

// Width in font pixels of `text` (kGlyphAdvance per character, less the last gap).
int textWidth(const std::string& text);

// Calls `dot(x, y)` for every set font pixel of `text`, x to the right and y down from its
// top-left corner. Printable ASCII has glyphs; anything else draws as '?'.
void forEachTextDot(const std::string& text, const std::function<void(int, int)>& dot);

}  // namespace surftrace::view
