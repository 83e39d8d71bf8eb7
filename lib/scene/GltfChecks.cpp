#include "scene/GltfChecks.h"

#include "scene/ConfinedFiles.h"
#include "util/Error.h"
#include "util/InputFile.h"
#include "util/Text.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

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

/// The GLB checks over chunk headers read by @a read (offset, count: fewer bytes when it cannot reach them).
void checkGlb(const std::function<std::string(std::uint64_t, std::size_t)>& read, std::uint64_t fileSize,
              const std::string& name) {
  const std::string header = read(0, 12);
  if (header.size() < 12)
    throw Error(fmt::format("{}: a GLB needs a 12-byte header but the file has {} bytes", name, fileSize));
  const std::uint64_t length = u32At(header, 8);
  if (length > fileSize)
    throw Error(fmt::format("{}: the GLB header says {} bytes but the file has {}", name, length, fileSize));
  std::uint64_t at = 12;
  for (int chunk = 0; at < length; ++chunk) {
    const std::string ch = read(at, 8);
    if (ch.size() < 8) return; // beyond what the caller could read: assimp reports a cut chunk header
    if (length - at < 8)
      throw Error(fmt::format("{}: GLB chunk {} starts {} bytes before the end of the file: too few for its header",
                              name, chunk, length - at));
    const std::uint64_t chunkLength = u32At(ch, 0), left = length - at - 8;
    const std::uint32_t type = u32At(ch, 4);
    if (chunkLength > left)
      throw Error(fmt::format("{}: GLB chunk {} ({}) says {} bytes but {} remain after its header", name, chunk,
                              type == kChunkJson ? "JSON" : type == kChunkBin ? "BIN" : "unknown type", chunkLength,
                              left));
    at += 8 + chunkLength;
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

std::optional<GltfParts> splitGltf(const std::string& bytes) {
  if (!isGlb(bytes)) return GltfParts{bytes, {}};
  GltfParts parts;
  for (std::size_t at = 12; at + 8 <= bytes.size();) {
    const std::size_t length = u32At(bytes, at);
    const std::uint32_t type = u32At(bytes, at + 4);
    if (length > bytes.size() - at - 8) return std::nullopt;
    (type == kChunkJson ? parts.jsonText : parts.bin) = bytes.substr(at + 8, length);
    at += 8 + length;
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

std::uint64_t countOf(const json& accessors, const json& index) {
  if (!index.is_number_unsigned() || index.get<std::size_t>() >= accessors.size()) return 0;
  const json& a = accessors[index.get<std::size_t>()];
  return a.is_object() && a.contains("count") && a["count"].is_number_unsigned() ? a["count"].get<std::uint64_t>() : 0;
}

/// Check one primitive's indices; @return without a word where they cannot be reached.
void checkPrimitive(const json& doc, const json& prim, Buffers& buffers, const std::string& where,
                    const std::string& name) {
  const int mode = prim.value("mode", 4);
  if (mode < 4 || !prim.contains("indices") || !prim.contains("attributes") || !prim["attributes"].is_object()) return;
  const json& accessors = member(doc, "accessors");
  const json& views = member(doc, "bufferViews");
  if (!accessors.is_array() || !views.is_array() || !prim["attributes"].contains("POSITION")) return;
  const std::uint64_t vertices = countOf(accessors, prim["attributes"]["POSITION"]);
  const json& ii = prim["indices"];
  if (!ii.is_number_unsigned() || ii.get<std::size_t>() >= accessors.size()) return;
  const json& acc = accessors[ii.get<std::size_t>()];
  if (!acc.is_object() || acc.contains("sparse") || !member(acc, "bufferView").is_number_unsigned()) return;
  const std::size_t viewIndex = acc["bufferView"];
  if (viewIndex >= views.size() || !views[viewIndex].is_object()) return;
  const json& view = views[viewIndex];
  const int type = acc.value("componentType", 0);
  const std::size_t size = type == 5121 ? 1 : type == 5123 ? 2 : type == 5125 ? 4 : 0;
  if (size == 0 || !view.value("buffer", json()).is_number_unsigned()) return;
  const std::string* data = buffers.get(view["buffer"].get<std::size_t>());
  const std::uint64_t start = view.value("byteOffset", std::uint64_t(0)) + acc.value("byteOffset", std::uint64_t(0));
  const std::uint64_t count = acc.value("count", std::uint64_t(0));
  if (!data || start > data->size() || count > (data->size() - start) / size) return; // assimp: out of range
  for (std::uint64_t i = 0; i < count; ++i) {
    std::uint64_t index = 0;
    for (std::size_t b = size; b-- > 0;) // little-endian
      index = (index << 8) | static_cast<unsigned char>((*data)[start + i * size + b]);
    if (index >= vertices) {
      const std::uint64_t face = mode == 4 ? i / 3 : (i < 2 ? 0 : i - 2);
      throw Error(fmt::format("{}: {}: face {} uses vertex index {} but the primitive has {} vertices", name, where,
                              face, index, vertices));
    }
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

void checkGltfIndices(const std::string& bytes, const std::string& name, const fs::path& folder, bool allowOutside) {
  std::optional<GltfParts> parts = splitGltf(bytes);
  if (!parts) return;
  const json doc = json::parse(parts->jsonText, nullptr, false);
  if (!doc.is_object() || !doc.contains("meshes") || !doc["meshes"].is_array()) return; // assimp says what is wrong
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
    return; // a value of the wrong type: assimp reports the malformed file
  }
}

} // namespace rtsdf
