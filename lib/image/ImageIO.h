#pragma once
/// @file ImageIO.h
/// @brief Image files: linear float OpenEXR (named channels) and 8-bit sRGB PNG, both written atomically.
#include "image/Image.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace rtsdf {

/// @brief Write @a image as a linear float32 OpenEXR file (ZIP compression), one EXR channel per image
///        channel with its name ("R", "G", "B", "sun.V", ...).
/// @note Atomic (rtsdf::writeFileAtomically): no partial file is left on failure, an existing file is kept.
/// @note OpenEXR stores channels sorted by name; readExr returns them in that order.
/// @throw Error naming the file: no channels, any NaN/Inf value (naming the channel and pixel), I/O failure.
void writeExr(const std::filesystem::path& path, const Image& image);

/// @brief Read every channel of a scan-line or tiled EXR file as float (half and uint channels are converted).
/// @note Pixels are indexed from the data window's corner: row 0 is its top row.
/// @throw Error naming the file when it is missing or malformed, or uses subsampled channels.
Image readExr(const std::filesystem::path& path);

/// @brief An 8-bit RGB raster: width*height pixels, 3 bytes each, x fastest, row 0 at the top.
struct PngPixels {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};

/// @brief Write an 8-bit sRGB PNG (libpng) of channels @a r, @a g, @a b: linear values, clamped to [0, 1],
///        encoded with the sRGB transfer function and rounded to the nearest byte.
/// @note Pass the same name three times for a grey image. Atomic, like writeExr.
/// @throw Error naming the file: a missing channel, a NaN value (naming channel and pixel), I/O failure.
void writePng(const std::filesystem::path& path, const Image& image, const std::string& r = "R",
              const std::string& g = "G", const std::string& b = "B");

/// @brief Write 8-bit sRGB-encoded bytes as they are (a picture composed on the GPU).
/// @note Atomic, like writeExr.
/// @throw Error naming the file: a size that does not match the bytes, I/O failure.
void writePng(const std::filesystem::path& path, const PngPixels& pixels);

/// @brief Read a PNG as 8-bit RGB bytes (for tests and comparisons). Grey, palette and alpha images are
///        converted by libpng's simplified API (alpha is composited onto black).
/// @throw Error naming the file when it is missing or not a readable PNG.
PngPixels readPng(const std::filesystem::path& path);

/// @brief Linear value -> sRGB-encoded value in [0, 1] (IEC 61966-2-1); the input is clamped to [0, 1].
float linearToSrgb(float v);
/// @brief sRGB-encoded value -> linear value in [0, 1]; the input is clamped to [0, 1].
float srgbToLinear(float v);

} // namespace rtsdf
