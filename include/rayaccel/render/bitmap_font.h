// A tiny 5x7 bitmap font (digits, a few capitals and signs) for labels drawn into rendered images.
#pragma once

#include <string_view>

#include "rayaccel/render/image.h"

namespace rayaccel {

inline constexpr int kGlyphWidth = 5;
inline constexpr int kGlyphHeight = 7;
inline constexpr int kGlyphAdvance = 6;  ///< glyph width plus a one-pixel gap

/// True when the font has a glyph for c: 0-9, space, . , - + / = ( ) and A C D E I K M N O P R S T X Y (lower case
/// letters draw as capitals).
bool has_glyph(char c);
/// Width in pixels of `text` drawn at integer `scale` (no trailing gap); 0 for empty text.
int text_width(std::string_view text, int scale);
/// Draws `text` with its top-left corner at (x, y), each font pixel a scale x scale block, clipped to the image.
/// Characters without a glyph draw as a hollow box so a missing glyph is visible rather than silently dropped.
void draw_text(Image& image, std::string_view text, int x, int y, int scale, Rgb colour);

}  // namespace rayaccel
