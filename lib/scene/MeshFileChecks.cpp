#include "scene/MeshFileChecks.h"

#include "scene/GltfChecks.h"
#include "util/Error.h"
#include "util/Text.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <set>
#include <sstream>
#include <vector>

namespace rtsdf {

namespace {

/// The first two numbers in @a text at or after @a at (false when there are not two).
bool firstTwoNumbers(const std::string& text, std::size_t at, double (&counts)[2]) {
  for (double& count : counts) {
    at = text.find_first_of("0123456789+-.", at);
    if (at == std::string::npos) return false;
    char* end = nullptr;
    count = std::strtod(text.c_str() + at, &end);
    at = std::size_t(end - text.c_str()) + (end == text.c_str() + at); // past the number (or its lone sign)
  }
  return true;
}

/// The counts an OFF header declares must fit in the file: every vertex takes at least 6 bytes ("0 0 0\n") and
/// every face 8 ("3 0 1 2\n"). Without this check the importer reserves memory for whatever the header says.
/// The scan is lenient on purpose, comments skipped, and checks two readings: the first two numbers after the
/// keyword, wherever they start (assimp reads "OFF6666" as a count of 6666), and the first two numbers of the
/// file (assimp also takes a file whose keyword comes later, or never, and reads its counts from the top).
void checkOffHeader(const std::string& head, std::uint64_t fileSize, const std::string& name) {
  std::string text;
  std::istringstream in(head);
  for (std::string line; std::getline(in, line);) text += line.substr(0, line.find('#')) + "\n";
  const std::size_t keyword = text.find("OFF");
  for (std::size_t at : {std::size_t(0), keyword == std::string::npos ? std::size_t(0) : keyword + 3}) {
    double counts[2];
    if (!firstTwoNumbers(text, at, counts)) continue; // malformed: the importer says so
    const double vertices = counts[0], faces = counts[1], need = 6.0 * vertices + 8.0 * faces;
    if (!(vertices >= 0 && faces >= 0 && need <= double(fileSize)))
      throw Error(fmt::format("{}: the OFF header declares {:.0f} vertices and {:.0f} faces, which need at least "
                              "{:.0f} bytes, but the file has {}", name, vertices, faces, need, fileSize));
  }
}

/// Bytes of one PLY scalar property type (0 when unknown).
int plyTypeBytes(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

/// Whether @a line ends a PLY header for assimp's reader: 'end_header' at the start of the line, then the end of
/// the line or one of the separators its tokenizer knows (space, tab, '\r', '\f', '\0'). Anything else after it
/// ('\v' for one: the fuzzer found it) is no end for assimp, which then spins on the body as it does without one.
bool endsPlyHeader(const std::string& line) {
  static const std::string kToken = "end_header";
  if (line.compare(0, kToken.size(), kToken) != 0) return false;
  if (line.size() == kToken.size()) return true;
  const char next = line[kToken.size()];
  return next == ' ' || next == '\t' || next == '\r' || next == '\f' || next == '\0';
}

/// What assimp's strtoul10 reads from the start of @a text: its leading digits as a 32-bit unsigned that wraps.
double leadingDigitsAsAssimp(const std::string& text) {
  std::uint32_t value = 0;
  for (std::size_t i = 0; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i)
    value = value * 10u + std::uint32_t(text[i] - '0');
  return double(value);
}

/// The record count assimp's PLY reader takes from an element line: the number after a name it knows, else the
/// digits the name starts with. For any other name it reads the count where the name starts (its own slip): 0 for
/// 'color', 3817748707 records allocated at once for '555...5loat' (fuzz_mesh).
double plyElementCount(const std::string& elementName, std::istringstream& rest) {
  static const std::set<std::string> kKnown = {"vertex", "face", "tristrips", "edge", "material"};
  if (!kKnown.count(elementName)) return leadingDigitsAsAssimp(elementName);
  double count = 0;
  rest >> count;
  return count;
}

/// One element of a PLY header: its name, its record count and the least bytes one record takes.
struct PlyElement {
  std::string name;
  double count = 0;
  double recordBytes = 0;
};

/// A PLY header must end, and its element counts must fit in the bytes after it: in ASCII each property takes at
/// least 2 bytes, in binary its type's size (a list at least its count's). The first element that does not fit
/// is named.
void checkPlyHeader(const std::string& head, std::uint64_t fileSize, const std::string& name) {
  std::istringstream in(head);
  std::string line, format;
  std::vector<PlyElement> elements;
  std::uint64_t headerBytes = 0;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    headerBytes += line.size() + 1;
    std::istringstream w(line);
    std::string key;
    w >> key;
    if (endsPlyHeader(line)) key = "end_header";
    else if (key == "end_header") key.clear(); // a look-alike assimp reads past
    ++lineNumber;
    // assimp skips a line it does not know, but not always cleanly: a line 'proper555...5ty float x' after an
    // element made it allocate 28 GB (fuzz_mesh). The format has no other keywords.
    static const std::set<std::string> kKeywords = {"ply", "format", "comment", "obj_info", "element", "property",
                                                    "end_header"};
    if (!key.empty() && !kKeywords.count(key))
      throw Error(fmt::format("{}: line {} of the PLY header starts with '{}', not a PLY keyword (format, comment, "
                              "obj_info, element, property, end_header)", name, lineNumber, escapedBytes(key, 40)));
    if (key == "format") w >> format;
    else if (key == "element") {
      PlyElement e;
      w >> e.name;
      e.count = plyElementCount(e.name, w);
      if (!(e.count >= 0))
        throw Error(fmt::format("{}: PLY element '{}' has a negative count", name, oneLine(e.name, 40)));
      elements.push_back(e);
    } else if (key == "property" && !elements.empty()) {
      std::string type;
      w >> type;
      if (type == "list") w >> type; // a list takes at least its count's bytes
      elements.back().recordBytes += format == "ascii" ? 2 : std::max(1, plyTypeBytes(type));
    } else if (key == "end_header") {
      const std::uint64_t left = fileSize - std::min(fileSize, headerBytes);
      double need = 0;
      for (PlyElement& e : elements) {
        // A record of no properties still takes a line in ASCII, and assimp allocates each one before reading.
        e.recordBytes = std::max(e.recordBytes, 1.0);
        need += e.count * e.recordBytes;
        if (need > double(left))
          throw Error(fmt::format("{}: the PLY header declares element '{}' with {:.0f} records of at least {:.0f} "
                                  "bytes ({} at least {:.0f} bytes), but the file has {} bytes after its header",
                                  name, oneLine(e.name, 40), e.count, e.recordBytes,
                                  &e == &elements.front() ? "in all" : "with the elements before it", need, left));
      }
      return;
    }
  }
  // assimp's PLY reader spins without end (a minute and more) on a header that never ends.
  throw Error(fmt::format("{}: the PLY header has no 'end_header' line (the word, then the end of its line) in its "
                          "first {} bytes", name, head.size()));
}

/// Whether assimp reads an STL as ASCII: it starts with "solid" (after blanks) and, in a file of 500 bytes or
/// more, its first 500 bytes are ASCII (binary files often start with "solid" too). Its reader's own test.
bool stlReadsAsAscii(const std::string& head, std::uint64_t fileSize) {
  const std::size_t start = head.find_first_not_of(" \t\r\n\f\v");
  if (start == std::string::npos || head.compare(start, 5, "solid") != 0 || start + 5 >= fileSize) return false;
  if (fileSize < 500) return true;
  const auto first = head.begin() + std::ptrdiff_t(start);
  return std::all_of(first, first + std::ptrdiff_t(std::min(head.size() - start, std::size_t(500))),
                     [](char c) { return static_cast<unsigned char>(c) <= 127; });
}

/// A binary STL is an 80-byte header, a 4-byte triangle count and 50 bytes per triangle: the count must match
/// the file's size exactly (assimp otherwise says only "Failed to determine STL storage representation").
void checkStl(const std::string& head, std::uint64_t fileSize, const std::string& name) {
  if (stlReadsAsAscii(head, fileSize)) return;
  if (fileSize < 84 || head.size() < 84)
    throw Error(fmt::format("{}: a binary STL needs at least 84 bytes (header and triangle count) but the file has "
                            "{} (and it does not start as an ASCII STL, with 'solid')", name, fileSize));
  std::uint32_t count = 0;
  for (int i = 3; i >= 0; --i) count = (count << 8) | static_cast<unsigned char>(head[80 + std::size_t(i)]);
  const std::uint64_t need = 84 + 50 * std::uint64_t(count);
  if (need != fileSize)
    throw Error(fmt::format("{}: binary STL says {} triangles ({} bytes) but the file has {} bytes", name, count,
                            need, fileSize));
}

/// The vertices assimp's OBJ parser reads from one face, line or point statement @a s (the keyword first):
/// its tokenizer, step for step (ObjFileParser::getFace), so that the count is the importer's, however odd
/// the bytes. @return -1 where the importer rejects the statement itself (a zero index).
int objStatementVertices(const std::string& s) {
  const auto isSpace = [](char c) { return c == ' ' || c == '\t'; };
  const auto isLineEnd = [](char c) { return c == '\r' || c == '\n' || c == '\0' || c == '\f'; };
  std::size_t at = 0;
  while (at < s.size() && !isSpace(s[at]) && !isLineEnd(s[at])) ++at; // the keyword
  while (at < s.size() && (isSpace(s[at]) || isLineEnd(s[at]))) ++at;
  int vertices = 0, position = 0; // position: 0 vertex, 1 texture coordinate, 2 normal ('/' separated)
  while (at < s.size() && !isLineEnd(s[at])) {
    std::size_t step = 1;
    if (s[at] == '/') {
      ++position;
    } else if (isSpace(s[at])) {
      position = 0;
    } else {
      const int value = int(std::strtol(s.c_str() + at, nullptr, 10)); // what atoi reads there
      if (value == 0) return -1;
      for (int rest = value / 10; rest != 0; rest /= 10) ++step;
      step += value < 0;
      vertices += position == 0;
    }
    at += step;
  }
  return vertices;
}

/// OBJ polylines ('l') need two vertices. assimp's OBJ importer counts a one-vertex 'l' as no vertex but still
/// copies one, so one-vertex lines before a longer one make it write past the end of the mesh's vertex array
/// (the fuzzer found it: a heap overflow inside assimp, which ASan cannot see). The statements are split as
/// assimp's reader splits them: a statement ends at '\n', '\r', '\f' or '\0' unless a backslash comes right
/// before, which continues it after the next '\n'.
} // namespace

void checkObjLines(const std::string& text, const std::string& name) {
  const auto isLineEnd = [](char c) { return c == '\r' || c == '\n' || c == '\0' || c == '\f'; };
  std::string statement; // the current statement, kept only when it is an 'l'
  bool started = false, keep = false;
  std::size_t line = 1, first = 1;
  for (std::size_t at = 0; at <= text.size(); ++at) {
    const bool end = at == text.size();
    if (!end && text[at] == '\\' && at + 1 < text.size() && isLineEnd(text[at + 1])) {
      at = text.find('\n', at + 1); // continued after the next '\n'
      if (at == std::string::npos) at = text.size() - 1;
      ++line;
      continue;
    }
    if (!end && !isLineEnd(text[at])) {
      if (!started) keep = text[at] == 'l';
      started = true;
      if (keep) statement += text[at];
      continue;
    }
    if (keep && objStatementVertices(statement) == 1)
      throw Error(fmt::format("{}: line {}: an OBJ line element ('l') needs at least 2 vertices, this one has 1",
                              name, first));
    statement.clear();
    started = keep = false;
    line += !end && text[at] == '\n';
    first = line;
  }
}

void checkHeaderClaims(const std::string& head, std::uint64_t fileSize, const std::string& extension,
                       const std::string& name) {
  std::string ext = toLower(extension);
  if (!ext.empty() && ext[0] != '.') ext = "." + ext;
  if (ext == ".off") checkOffHeader(head, fileSize, name);
  if (ext == ".ply") checkPlyHeader(head, fileSize, name);
  if (ext == ".stl") checkStl(head, fileSize, name);
  if (ext == ".glb" || ext == ".gltf") checkGlbLengths(head, fileSize, name);
}

} // namespace rtsdf
