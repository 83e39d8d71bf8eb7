#include "util/Text.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace rtsdf {

std::string toLower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string oneLine(const std::string& message, std::size_t maxChars) {
  std::string out;
  out.reserve(std::min(message.size(), maxChars + 3));
  for (const char c : message) {
    const char s = (static_cast<unsigned char>(c) < 32 || c == 127) ? ' ' : c;
    if (s == ' ' && (out.empty() || out.back() == ' ')) continue;
    if (out.size() >= maxChars) return out + "...";
    out += s;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

std::string escapedBytes(const std::string& bytes, std::size_t maxBytes) {
  std::string out;
  for (std::size_t i = 0; i < bytes.size() && i < maxBytes; ++i) {
    const auto c = static_cast<unsigned char>(bytes[i]);
    out += c >= 0x20 && c < 0x7F ? std::string(1, char(c)) : fmt::format("\\x{:02x}", c);
  }
  return bytes.size() > maxBytes ? out + "..." : out;
}

} // namespace rtsdf
