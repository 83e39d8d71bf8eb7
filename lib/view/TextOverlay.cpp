#include "view/TextOverlay.h"

#include "util/Error.h"

#include <fmt/format.h>
#include <stb/stb_easy_font.h>

#include <algorithm>
#include <cmath>

namespace rtsdf {

std::vector<std::uint8_t> rasterizeText(const std::string& text, int width, int rows, int scale) {
  if (width <= 0 || rows <= 0 || scale <= 0)
    throw Error(fmt::format("a text strip of {}x{} pixels at scale {}", width, rows, scale));
  std::vector<std::uint8_t> coverage(std::size_t(width) * std::size_t(rows), 0);
  // stb_easy_font writes four 16-byte vertices per quad, at most ~270 bytes per character.
  struct Vertex { float x, y, z; unsigned char color[4]; };
  std::vector<Vertex> vertices(text.size() * 70 + 4);
  std::string line = text;
  unsigned char white[4] = {255, 255, 255, 255};
  const int quads = stb_easy_font_print(0.0f, 0.0f, line.data(), white, vertices.data(),
                                        int(vertices.size() * sizeof(Vertex)));
  for (int q = 0; q < quads; ++q) {
    const Vertex& a = vertices[std::size_t(q) * 4];
    const Vertex& c = vertices[std::size_t(q) * 4 + 2]; // the opposite corner
    const int x0 = 4 + int(std::lround(std::min(a.x, c.x) * float(scale)));
    const int x1 = 4 + int(std::lround(std::max(a.x, c.x) * float(scale)));
    const int y0 = 2 + int(std::lround(std::min(a.y, c.y) * float(scale)));
    const int y1 = 2 + int(std::lround(std::max(a.y, c.y) * float(scale)));
    for (int y = std::max(y0, 0); y < std::min(y1, rows); ++y)
      for (int x = std::max(x0, 0); x < std::min(x1, width); ++x)
        coverage[std::size_t(y) * std::size_t(width) + std::size_t(x)] = 1;
  }
  return coverage;
}

std::vector<std::uint32_t> packCoverage(const std::vector<std::uint8_t>& coverage) {
  std::vector<std::uint32_t> words((coverage.size() + 3) / 4, 0u);
  for (std::size_t i = 0; i < coverage.size(); ++i)
    if (coverage[i]) words[i / 4] |= std::uint32_t(coverage[i]) << (8 * (i % 4));
  return words;
}

} // namespace rtsdf
