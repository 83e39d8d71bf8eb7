#include "scene/GltfChecks.h"

#include "scene/ConfinedFiles.h"
#include "util/Error.h"
#include "util/InputFile.h"
#include "util/Text.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <functional>
#include <map>
#include <optional>

namespace rtsdf {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr std::uint32_t kChunkJson = 0x4E4F534A, kChunkBin = 0x004E4942;

std::uint32_t u32At(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[at + std::size_t(i)]);
  return v;
}

bool isGlb(const std::string& head) { return head.size() >= 4 && head.compare(0, 4, "glTF") == 0; }

/// Where the chunk after one at @a at of @a length bytes starts: the importer pads each chunk to 4 bytes.
std::uint64_t nextChunkAt(std::uint64_t at, std::uint64_t length) { return at + 8 + (length + 3) / 4 * 4; }

/// The GLB checks over chunk headers read by @a read (offset, count: fewer bytes when it cannot reach them). They
/// follow the importer's reading: the JSON chunk at byte 12 whatever the header's length says, then the BIN chunk
/// after it where the header's length reaches past the BIN chunk's header; it reads no other chunk, and allocates
/// each of the two chunks' stated lengths before reading them.
void checkGlb(const std::function<std::string(std::uint64_t, std::size_t)>& read, std::uint64_t fileSize,
              const std::string& name) {
  const std::string header = read(0, 12);
  if (header.size() < 12)
    throw Error(fmt::format("{}: a GLB needs a 12-byte header but the file has {} bytes", name, fileSize));
  const std::uint64_t length = u32At(header, 8);
  if (length > fileSize)
    throw Error(fmt::format("{}: the GLB header says {} bytes but the file has {}", name, length, fileSize));
  if (length < 20)
    throw Error(fmt::format("{}: the GLB header says {} bytes: too few for its 12-byte header and its JSON chunk's",
                            name, length));
  std::uint64_t at = 12;
  for (int chunk = 0; chunk < 2 && at + 8 <= length; ++chunk) {
    const std::string ch = read(at, 8);
    if (ch.size() < 8) return; // beyond what the caller could read
    const std::uint64_t chunkLength = u32At(ch, 0), left = length - at - 8;
    const std::uint32_t type = u32At(ch, 4);
    if (chunkLength > left)
      throw Error(fmt::format("{}: GLB chunk {} ({}) says {} bytes but {} remain after its header", name, chunk,
                              type == kChunkJson ? "JSON" : type == kChunkBin ? "BIN" : "unknown type", chunkLength,
                              left));
    at = nextChunkAt(at, chunkLength);
  }
}

std::string decodeBase64(const std::string& text) {
  std::string out;
  unsigned bits = 0;
  int count = 0;
  for (const char c : text) {
    int v = c >= 'A' && c <= 'Z' ? c - 'A' : c >= 'a' && c <= 'z' ? c - 'a' + 26 : c >= '0' && c <= '9' ? c - '0' + 52
          : c == '+' ? 62 : c == '/' ? 63 : -1;
    if (v < 0) continue; // padding
    bits = (bits << 6) | unsigned(v);
    if ((count += 6) >= 8) out += char((bits >> (count -= 8)) & 0xFF);
  }
  return out;
}

/// @a obj's member @a key, or null when it has none.
const json& member(const json& obj, const char* key) {
  static const json kNone;
  return obj.is_object() && obj.contains(key) ? obj[key] : kNone;
}

/// The glTF's JSON and its GLB binary chunk (empty for a .gltf).
struct GltfParts {
  std::string jsonText, bin;
};

/// The JSON and BIN chunks as the importer reads them (checkGlb). std::nullopt where they do not fit or are not
/// of their types: the importer reports it.
std::optional<GltfParts> splitGltf(const std::string& bytes) {
  if (!isGlb(bytes)) return GltfParts{bytes, {}};
  if (bytes.size() < 20) return std::nullopt;
  const std::uint64_t length = std::min<std::uint64_t>(u32At(bytes, 8), bytes.size());
  GltfParts parts;
  std::uint64_t at = 12;
  for (int chunk = 0; chunk < 2 && (chunk == 0 || at + 8 <= length); ++chunk) {
    const std::uint64_t chunkLength = u32At(bytes, at);
    if (u32At(bytes, at + 4) != (chunk == 0 ? kChunkJson : kChunkBin) || chunkLength > bytes.size() - at - 8)
      return std::nullopt;
    (chunk == 0 ? parts.jsonText : parts.bin) = bytes.substr(at + 8, chunkLength);
    at = nextChunkAt(at, chunkLength);
  }
  return parts;
}

/// A glTF's buffers as bytes, read on first use (std::nullopt: cannot be read here).
class Buffers {
public:
  Buffers(const json& doc, GltfParts& parts, fs::path folder, std::string name, bool allowOutside)
      : mDoc(doc), mParts(parts), mFolder(std::move(folder)), mName(std::move(name)), mAllowOutside(allowOutside) {}

  const std::string* get(std::size_t index) {
    if (!mRead.count(index)) mRead[index] = load(index);
    return mRead[index] ? &*mRead[index] : nullptr;
  }

private:
  std::optional<std::string> load(std::size_t index) const {
    const json& buffers = member(mDoc, "buffers");
    if (!buffers.is_array() || index >= buffers.size() || !buffers[index].is_object()) return std::nullopt;
    const json& b = buffers[index];
    if (!b.contains("uri")) return index == 0 ? std::optional<std::string>(mParts.bin) : std::nullopt;
    if (!b["uri"].is_string()) return std::nullopt;
    const std::string uri = b["uri"];
    if (uri.rfind("data:", 0) == 0) {
      const std::size_t comma = uri.find(";base64,");
      if (comma == std::string::npos) return std::nullopt;
      return decodeBase64(uri.substr(comma + 8));
    }
    if (mFolder.empty()) return std::nullopt;
    const fs::path file = mFolder / uri;
    if (!mAllowOutside) requireInsideFolder(mName, uri, file, mFolder);
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) return std::nullopt; // assimp says it is missing
    return readFileBytes(file, "glTF buffer");
  }

  const json& mDoc;
  GltfParts& mParts;
  fs::path mFolder;
  std::string mName;
  bool mAllowOutside;
  std::map<std::size_t, std::optional<std::string>> mRead;
};

/// @a obj's member @a key as the importer reads an optional number (rapidjson's MemberOrDefault): @a fallback
/// where it is missing or not a whole number of 0 or more.
std::uint64_t unsignedOr(const json& obj, const char* key, std::uint64_t fallback) {
  const json& v = member(obj, key);
  return v.is_number_unsigned() ? v.get<std::uint64_t>() : fallback;
}

/// @a obj's member @a key as the importer reads an index (rapidjson's IsUint: 0 to 2^32 - 1); std::nullopt where
/// it is missing or anything else, which the importer takes as no index.
std::optional<std::uint32_t> indexOf(const json& obj, const char* key) {
  const json& v = member(obj, key);
  if (!v.is_number_unsigned() || v.get<std::uint64_t>() > 0xFFFFFFFFu) return std::nullopt;
  return v.get<std::uint32_t>();
}

/// A glTF primitive mode's name, the name of one of its elements, and the fewest indices (or vertices, without
/// indices) it needs for one element. The importer counts a strip's elements as count - 1 or count - 2 unchecked
/// (a line strip of no indices asked for 2^32 lines) and closes a loop through its first line even when it
/// dropped that line (a null read): both are refused here, with any index past the vertices whatever the mode.
struct ModeShape {
  const char* name;
  const char* element;
  std::uint64_t fewest;
};

ModeShape shapeOf(int mode) {
  static const ModeShape kShapes[] = {{"points", "point", 1},          {"lines", "line", 2},
                                      {"line loop", "line", 2},        {"line strip", "line", 2},
                                      {"triangles", "face", 3},        {"triangle strip", "face", 3},
                                      {"triangle fan", "face", 3}};
  return kShapes[mode];
}

/// The element (point, line or face) of @a mode that index number @a i of the primitive's list opens or ends.
std::uint64_t elementOf(int mode, std::uint64_t i) {
  switch (mode) {
  case 0: return i;
  case 1: return i / 2;
  case 2:
  case 3: return i < 1 ? 0 : i - 1;
  case 4: return i / 3;
  default: return i < 2 ? 0 : i - 2;
  }
}

/// The bytes of an index accessor: its buffer, where its indices start and their size (null: cannot be reached).
struct IndexBytes {
  const std::string* data = nullptr;
  std::uint64_t start = 0, size = 0;
};

IndexBytes indexBytes(const json& doc, const json& acc, std::uint64_t count, Buffers& buffers) {
  const json& views = member(doc, "bufferViews");
  const std::optional<std::uint32_t> viewIndex = indexOf(acc, "bufferView");
  if (!views.is_array() || acc.contains("sparse") || !viewIndex || *viewIndex >= views.size()) return {};
  const json& view = views[*viewIndex];
  const std::uint64_t type = unsignedOr(acc, "componentType", 0);
  const std::size_t size = type == 5121 ? 1 : type == 5123 ? 2 : type == 5125 ? 4 : 0;
  const std::optional<std::uint32_t> buffer = indexOf(view, "buffer");
  if (size == 0 || !buffer) return {};
  const std::string* data = buffers.get(*buffer);
  const std::uint64_t start = unsignedOr(view, "byteOffset", 0) + unsignedOr(acc, "byteOffset", 0);
  if (!data || start > data->size() || count > (data->size() - start) / size) return {}; // assimp: out of range
  return {data, start, size};
}

/// Check one primitive's element count and indices, its members read as the importer reads them; @return without
/// a word where they cannot be reached.
void checkPrimitive(const json& doc, const json& prim, Buffers& buffers, const std::string& where,
                    const std::string& name) {
  const json& modeValue = member(prim, "mode");
  const std::int64_t mode = modeValue.is_number_integer() ? modeValue.get<std::int64_t>() : 4;
  if (mode < 0 || mode > 6) return; // the importer makes no element of it
  const ModeShape shape = shapeOf(int(mode));
  // A POSITION that is not an index is skipped, and without one the importer makes a primitive of no vertices
  // (and goes on); one naming no accessor is an error it reports.
  const json& accessors = member(doc, "accessors");
  const std::size_t accessorCount = accessors.is_array() ? accessors.size() : 0;
  const std::optional<std::uint32_t> positions = indexOf(member(prim, "attributes"), "POSITION");
  if (positions && *positions >= accessorCount) return;
  const std::uint64_t vertices = positions ? unsignedOr(accessors[*positions], "count", 0) : 0;
  const std::string verticesText =
      positions ? fmt::format("{} vertices", vertices) : std::string("no vertices (no POSITION attribute)");
  const std::optional<std::uint32_t> indices = indexOf(prim, "indices");
  if (!indices) {
    // Without positions (the primitive is then not drawn) only the strips and fans count their elements wrongly.
    if (vertices < shape.fewest && (positions || mode == 3 || mode >= 5))
      throw Error(fmt::format("{}: {}: mode {} ({}) needs at least {} vertices but the primitive has {}", name, where,
                              mode, shape.name, shape.fewest, verticesText));
    return;
  }
  if (*indices >= accessorCount) return;
  const json& acc = accessors[*indices];
  const std::uint64_t count = unsignedOr(acc, "count", 0);
  if (count < shape.fewest)
    throw Error(fmt::format("{}: {}: mode {} ({}) needs at least {} indices but index accessor {} has {}", name, where,
                            mode, shape.name, shape.fewest, *indices, count));
  const IndexBytes bytes = indexBytes(doc, acc, count, buffers);
  if (!bytes.data) return;
  for (std::uint64_t i = 0; i < count; ++i) {
    std::uint64_t index = 0;
    for (std::size_t b = bytes.size; b-- > 0;) // little-endian
      index = (index << 8) | static_cast<unsigned char>((*bytes.data)[bytes.start + i * bytes.size + b]);
    if (index >= vertices)
      throw Error(fmt::format("{}: {}: {} {} uses vertex index {} but the primitive has {}", name, where,
                              shape.element, elementOf(int(mode), i), index, verticesText));
  }
}

} // namespace

void checkGlbLengths(const std::string& head, std::uint64_t fileSize, const std::string& name) {
  if (!isGlb(head)) return;
  checkGlb([&head](std::uint64_t at, std::size_t n) { return at < head.size() ? head.substr(at, n) : std::string(); },
           fileSize, name);
}

void checkGlbFile(const fs::path& path, std::uint64_t fileSize) {
  std::ifstream in(path, std::ios::binary);
  const auto read = [&in](std::uint64_t at, std::size_t n) {
    std::string bytes(n, '\0');
    in.clear();
    in.seekg(std::streamoff(at));
    in.read(bytes.data(), std::streamsize(n));
    bytes.resize(std::size_t(in.gcount()));
    return bytes;
  };
  if (isGlb(read(0, 4))) checkGlb(read, fileSize, path.string());
}

void checkGltfForm(const std::string& head, const std::string& extension, const std::string& name) {
  std::string ext = toLower(extension);
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  if (ext == "glb" && !isGlb(head)) throw Error(fmt::format("{}: not a binary glTF: a .glb starts with 'glTF'", name));
  if (ext != "gltf" || isGlb(head)) return;
  const std::size_t bom = head.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0; // a UTF-8 byte order mark, tolerated
  const std::size_t first = head.find_first_not_of(" \t\r\n", bom);
  if (first == std::string::npos || head[first] != '{')
    throw Error(fmt::format("{}: not a glTF: a .gltf is a JSON object (it starts with '{{') or a GLB", name));
}

void checkGltfPrimitives(const std::string& bytes, const std::string& name, const fs::path& folder, bool allowOutside) {
  std::optional<GltfParts> parts = splitGltf(bytes);
  if (!parts) return;
  json doc;
  try {
    doc = json::parse(parts->jsonText);
  } catch (const json::exception& e) {
    // Neither glTF importer takes it, and the importer would go on to sniff it with every other format's.
    throw Error(fmt::format("{}: not a glTF: malformed JSON: {}", name, oneLine(e.what(), 160)));
  }
  if (!doc.is_object()) throw Error(fmt::format("{}: not a glTF: its JSON is not an object", name));
  if (!doc.contains("meshes") || !doc["meshes"].is_array()) return; // assimp says what is wrong
  Buffers buffers(doc, *parts, folder, name, allowOutside);
  const json& meshes = doc["meshes"];
  try {
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      const json& prims = member(meshes[m], "primitives");
      if (!prims.is_array()) continue;
      const json& label = member(meshes[m], "name");
      const std::string meshName = label.is_string() ? fmt::format("mesh '{}'", oneLine(label.get<std::string>(), 60))
                                                     : fmt::format("mesh {}", m);
      for (std::size_t p = 0; p < prims.size(); ++p)
        if (prims[p].is_object())
          checkPrimitive(doc, prims[p], buffers, fmt::format("{} primitive {}", meshName, p), name);
    }
  } catch (const json::exception&) {
    return; // not expected (every member is read by type): the importer reports what is malformed
  }
}

} // namespace rtsdf
