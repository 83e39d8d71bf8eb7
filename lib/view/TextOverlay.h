#pragma once
/// @file TextOverlay.h
/// @brief A line of text as pixel coverage, for the strip ComposePass draws at the top of the viewer's picture
///        (stb_easy_font's glyphs: axis-aligned quads, no font files).
#include <cstdint>
#include <string>
#include <vector>

namespace rtsdf {

/// @brief Rows of the text strip at scale 1 (stb_easy_font's glyphs are 7 pixels high).
constexpr int kTextStripRows = 12;

/// @brief Lines of the text strip at most (a status line wider than the window wraps onto the next).
constexpr int kTextStripMaxLines = 3;

/// @brief @a text broken at its " | " separators into at most kTextStripMaxLines lines ('\n' between them) that
///        fit @a width pixels at @a scale where they can; a part wider than the strip is cut off when drawn.
std::string wrapText(const std::string& text, int width, int scale = 1);

/// @brief The lines of @a text (one more than its '\n's).
int lineCount(const std::string& text);

/// @brief The coverage of @a text drawn from pixel (4, 2) at @a scale: @a rows x @a width bytes, x fastest,
///        1 where a glyph covers the pixel, 0 elsewhere; what does not fit is cut off.
/// @throw Error when @a width, @a rows or @a scale is not positive.
std::vector<std::uint8_t> rasterizeText(const std::string& text, int width, int rows, int scale = 1);

/// @brief The coverage bytes packed four to a uint (byte i of the strip in bits 8 (i % 4) of word i / 4), as
///        compose.comp reads them; zero-padded to whole words.
std::vector<std::uint32_t> packCoverage(const std::vector<std::uint8_t>& coverage);

} // namespace rtsdf
