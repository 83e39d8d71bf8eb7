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

std::string wrapText(const std::string& text, int width, int scale) {
  const auto fits = [&](std::string line) { return 4 + stb_easy_font_width(line.data()) * scale <= width; };
  std::string out, line;
  int lines = 1;
  for (std::size_t at = 0; at < text.size();) {
    std::size_t end = text.find(" | ", at);
    end = end == std::string::npos ? text.size() : end + 3;
    const std::string part = text.substr(at, end - at);
    if (!line.empty() && !fits(line + part) && lines < kTextStripMaxLines) {
      while (!line.empty() && line.back() == ' ') line.pop_back();
      out += line + "\n";
      line.clear();
      ++lines;
    }
    line += part;
    at = end;
  }
  return out + line;
}

int lineCount(const std::string& text) { return 1 + int(std::count(text.begin(), text.end(), '\n')); }

std::vector<std::uint32_t> packCoverage(const std::vector<std::uint8_t>& coverage) {
  std::vector<std::uint32_t> words((coverage.size() + 3) / 4, 0u);
  for (std::size_t i = 0; i < coverage.size(); ++i)
    if (coverage[i]) words[i / 4] |= std::uint32_t(coverage[i]) << (8 * (i % 4));
  return words;
}

} // namespace rtsdf
