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
constexpr int kMaxJsonDepth = 64;
constexpr std::size_t kMaxDataUriHeader = 100;

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
  if (const std::uint32_t version = u32At(header, 4); version != 2)
    throw Error(fmt::format("{}: GLB version {}: only glTF 2.0 is read", name, version));
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

/// Base64 @a text as bytes; std::nullopt for a character outside its alphabet, or padding before the end (the
/// importer decodes such a character as 0, and the bytes would not be what it reads).
std::optional<std::string> decodeBase64(const std::string& text) {
  std::string out;
  unsigned bits = 0;
  int count = 0;
  const std::size_t end = text.find_last_not_of('=') + 1;
  if (text.size() - end > 2) return std::nullopt;
  for (std::size_t i = 0; i < end; ++i) {
    const char c = text[i];
    const int v = c >= 'A' && c <= 'Z'   ? c - 'A'
                  : c >= 'a' && c <= 'z' ? c - 'a' + 26
                  : c >= '0' && c <= '9' ? c - '0' + 52
                  : c == '+'             ? 62
                  : c == '/'             ? 63
                                         : -1;
    if (v < 0) return std::nullopt;
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
  bool glb = false, hasBin = false;
};

/// The JSON and BIN chunks as the importer reads them (checkGlb). std::nullopt where they do not fit or are not
/// of their types: the importer reports it.
std::optional<GltfParts> splitGltf(const std::string& bytes) {
  if (!isGlb(bytes)) return GltfParts{bytes, {}};
  if (bytes.size() < 20) return std::nullopt;
  const std::uint64_t length = std::min<std::uint64_t>(u32At(bytes, 8), bytes.size());
  GltfParts parts;
  parts.glb = true;
  std::uint64_t at = 12;
  for (int chunk = 0; chunk < 2 && (chunk == 0 || at + 8 <= length); ++chunk) {
    const std::uint64_t chunkLength = u32At(bytes, at);
    if (u32At(bytes, at + 4) != (chunk == 0 ? kChunkJson : kChunkBin) || chunkLength > bytes.size() - at - 8)
      return std::nullopt;
    (chunk == 0 ? parts.jsonText : parts.bin) = bytes.substr(at + 8, chunkLength);
    parts.hasBin = chunk == 1;
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
    if (mParts.glb && index == 0) return mParts.bin; // the importer's buffer 0 in a GLB, whatever its uri says
    const json& buffers = member(mDoc, "buffers");
    if (!buffers.is_array() || index >= buffers.size() || !buffers[index].is_object()) return std::nullopt;
    const json& b = buffers[index];
    if (!b.contains("uri") || !b["uri"].is_string()) return std::nullopt;
    const std::string uri = b["uri"];
    // The importer marks a data URI it has parsed by a leading 0x10 and keeps its offsets in a char.
    if (std::any_of(uri.begin(), uri.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; }))
      throw Error(fmt::format("{}: buffer {}: its uri holds a control character", mName, index));
    if (uri.rfind("data:", 0) == 0 && uri.find(',') > kMaxDataUriHeader)
      throw Error(fmt::format("{}: buffer {}: a data URI whose media type runs past {} characters", mName, index,
                              kMaxDataUriHeader));
    if (uri.rfind("data:", 0) == 0) {
      const std::size_t comma = uri.find(";base64,");
      if (comma == std::string::npos || comma > uri.find(','))
        throw Error(fmt::format("{}: buffer {}: a data URI that is not base64 (a glTF's are)", mName, index));
      const std::optional<std::string> bytes = decodeBase64(uri.substr(comma + 8));
      if (!bytes)
        throw Error(fmt::format("{}: buffer {}: its data URI holds a character outside base64", mName, index));
      return bytes;
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

/// The bytes of one component of glTF component type @a type (0: not a component type).
std::uint64_t componentBytes(std::uint64_t type) {
  switch (type) {
  case 5120: // BYTE
  case 5121: return 1; // UNSIGNED_BYTE
  case 5122: // SHORT
  case 5123: return 2; // UNSIGNED_SHORT
  case 5125: // UNSIGNED_INT
  case 5126: return 4; // FLOAT
  default: return 0;
  }
}

/// The components of one element of glTF accessor type @a type (0: not an accessor type).
std::uint64_t componentsOf(const json& type) {
  static const std::map<std::string, std::uint64_t> kTypes = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4},
                                                               {"MAT2", 4},   {"MAT3", 9}, {"MAT4", 16}};
  const auto it = type.is_string() ? kTypes.find(type.get<std::string>()) : kTypes.end();
  return it == kTypes.end() ? 0 : it->second;
}

/// Where an accessor's elements lie: its buffer's bytes (null where they cannot be read here), the first element's
/// offset in them, the step between elements and one element's size.
struct AccessorBytes {
  const std::string* data = nullptr;
  std::uint64_t start = 0, stride = 0, elementBytes = 0, count = 0;
};

/// Check that a buffer view of @a bytesNeeded bytes from @a offset lies within the view @a viewIndex and the view
/// within its buffer; @return the buffer's bytes and where the view starts (null: the buffer cannot be read here).
std::pair<const std::string*, std::uint64_t> checkViewReach(const json& doc, std::uint32_t viewIndex,
                                                            std::uint64_t offset, std::uint64_t bytesNeeded,
                                                            Buffers& buffers, const std::string& what) {
  const json& views = member(doc, "bufferViews");
  if (!views.is_array() || viewIndex >= views.size() || !views[viewIndex].is_object())
    throw Error(fmt::format("{}: buffer view {} does not exist", what, viewIndex));
  const json& view = views[viewIndex];
  const std::uint64_t viewLength = unsignedOr(view, "byteLength", 0), viewStart = unsignedOr(view, "byteOffset", 0);
  if (offset > viewLength || bytesNeeded > viewLength - offset)
    throw Error(fmt::format("{}: {} bytes from byte {} reach past the {} bytes of buffer view {}", what, bytesNeeded,
                            offset, viewLength, viewIndex));
  const std::optional<std::uint32_t> buffer = indexOf(view, "buffer");
  if (!buffer) throw Error(fmt::format("{}: buffer view {} names no buffer", what, viewIndex));
  const std::string* data = buffers.get(*buffer);
  if (data && (viewStart > data->size() || viewLength > data->size() - viewStart))
    throw Error(fmt::format("{}: buffer view {} ({} bytes from byte {}) reaches past the {} bytes of buffer {}", what,
                            viewIndex, viewLength, viewStart, data->size(), *buffer));
  return {data, viewStart};
}

/// Check a sparse accessor's substitutions (the importer writes each value at its index without a check).
void checkSparse(const json& doc, const json& sparse, std::uint64_t count, std::uint64_t elementBytes,
                 Buffers& buffers, const std::string& what) {
  const json& indices = member(sparse, "indices");
  const json& values = member(sparse, "values");
  const std::uint64_t n = unsignedOr(sparse, "count", 0);
  const std::uint64_t size = componentBytes(unsignedOr(indices, "componentType", 0));
  const std::optional<std::uint32_t> indexView = indexOf(indices, "bufferView");
  const std::optional<std::uint32_t> valueView = indexOf(values, "bufferView");
  if (!sparse.is_object() || n == 0 || n > count || !indexView || !valueView || size == 0)
    throw Error(fmt::format("{}: a sparse part needs a count of 1 to {}, and indices and values with a buffer view "
                            "each", what, count));
  const std::uint64_t indexOffset = unsignedOr(indices, "byteOffset", 0);
  const auto [data, viewStart] =
      checkViewReach(doc, *indexView, indexOffset, n * size, buffers, what + " sparse indices");
  checkViewReach(doc, *valueView, unsignedOr(values, "byteOffset", 0), n * elementBytes, buffers,
                 what + " sparse values");
  if (!data) return;
  for (std::uint64_t i = 0; i < n; ++i) {
    std::uint64_t index = 0;
    for (std::uint64_t b = size; b-- > 0;)
      index = (index << 8) | static_cast<unsigned char>((*data)[viewStart + indexOffset + i * size + b]);
    if (index >= count)
      throw Error(fmt::format("{}: sparse index {} is {}, past the accessor's {} elements", what, i, index, count));
  }
}

/// Check accessor @a index as the spec lays it out (a known type and component type, a count of 1 or more, every
/// element within its buffer view and the view within its buffer, sparse parts within theirs): the importer reads
/// what these say without checking all of it (a count times one component, not one element). @return its bytes.
AccessorBytes checkAccessor(const json& doc, std::uint32_t index, Buffers& buffers, const std::string& what) {
  const json& accessors = member(doc, "accessors");
  if (!accessors.is_array() || index >= accessors.size() || !accessors[index].is_object())
    throw Error(fmt::format("{}: accessor {} does not exist", what, index));
  const json& acc = accessors[index];
  const std::uint64_t components = componentsOf(member(acc, "type"));
  const std::uint64_t size = componentBytes(unsignedOr(acc, "componentType", 0));
  AccessorBytes out;
  out.count = unsignedOr(acc, "count", 0);
  if (components == 0 || size == 0 || out.count == 0 || out.count > 0xFFFFFFFFu)
    throw Error(fmt::format("{}: accessor {} needs a type (SCALAR, VEC2-4, MAT2-4), a component type (5120-5126) "
                            "and a count from 1 to 2^32 - 1", what, index));
  out.elementBytes = components * size;
  const std::string self = fmt::format("{}: accessor {}", what, index);
  if (acc.contains("sparse")) checkSparse(doc, acc["sparse"], out.count, out.elementBytes, buffers, self);
  const std::optional<std::uint32_t> viewIndex = indexOf(acc, "bufferView");
  if (!viewIndex) return out; // zeros, with sparse values on them
  const json& views = member(doc, "bufferViews");
  static const json kNone;
  const json& stride = views.is_array() && *viewIndex < views.size() ? member(views[*viewIndex], "byteStride") : kNone;
  out.stride = stride.is_number_unsigned() ? stride.get<std::uint64_t>() : out.elementBytes;
  if (acc.contains("sparse") && out.stride != out.elementBytes) // the importer steps through its packed copy by it
    throw Error(fmt::format("{}: a sparse accessor on a view with a byteStride ({}) is not read", self, stride.dump()));
  if (!stride.is_null() && (out.stride < out.elementBytes || out.stride % 4 != 0 || out.stride > 252))
    throw Error(fmt::format("{}: buffer view {} has a byteStride of {}, not a multiple of 4 from {} to 252", self,
                            *viewIndex, stride.dump(), out.elementBytes));
  const std::uint64_t offset = unsignedOr(acc, "byteOffset", 0);
  const auto [data, viewStart] =
      checkViewReach(doc, *viewIndex, offset, (out.count - 1) * out.stride + out.elementBytes, buffers, self);
  out.data = data;
  out.start = viewStart + offset;
  return out;
}

/// Check a primitive's index accessor as the spec has it (unsigned scalars, tightly packed, no sparse part: the
/// importer reads each index as 4 bytes or fewer at each element's step) and @return its bytes.
AccessorBytes checkIndexAccessor(const json& doc, std::uint32_t index, Buffers& buffers, const std::string& what) {
  const AccessorBytes bytes = checkAccessor(doc, index, buffers, what); // it exists, then
  const json& acc = doc["accessors"][index];
  const std::uint64_t type = unsignedOr(acc, "componentType", 0);
  if (componentsOf(member(acc, "type")) != 1 || (type != 5121 && type != 5123 && type != 5125) ||
      acc.contains("sparse") || (bytes.data && bytes.stride != bytes.elementBytes))
    throw Error(fmt::format("{}: index accessor {} must hold tightly packed unsigned SCALARs (component type 5121, "
                            "5123 or 5125) without a sparse part", what, index));
  return bytes;
}

/// Check every accessor a primitive's attributes and morph targets name (the importer skips a value that is not an
/// index): the importer extracts each one.
void checkAttributeAccessors(const json& doc, const json& prim, Buffers& buffers, const std::string& what) {
  const auto checkAll = [&](const json& attributes, const std::string& of) {
    if (!attributes.is_object()) return;
    for (const auto& [semantic, value] : attributes.items())
      if (const std::optional<std::uint32_t> index = indexOf(attributes, semantic.c_str()))
        checkAccessor(doc, *index, buffers, fmt::format("{}{} {}", what, of, oneLine(semantic, 40)));
  };
  checkAll(member(prim, "attributes"), "");
  const json& targets = member(prim, "targets");
  if (targets.is_array())
    for (std::size_t t = 0; t < targets.size(); ++t) checkAll(targets[t], fmt::format(" target {}", t));
}

/// Check one primitive, its members read as the importer reads them: the accessors it names, enough indices (or
/// vertices, without indices) for one element of its mode, and every index within its vertices.
void checkPrimitive(const json& doc, const json& prim, Buffers& buffers, const std::string& where) {
  checkAttributeAccessors(doc, prim, buffers, where);
  const json& modeValue = member(prim, "mode"); // rapidjson's IsInt, else triangles
  const bool intMode = modeValue.is_number_integer() && modeValue.get<std::int64_t>() >= INT32_MIN &&
                       modeValue.get<std::int64_t>() <= INT32_MAX;
  const std::int64_t mode = intMode ? modeValue.get<std::int64_t>() : 4;
  if (mode < 0 || mode > 6) return; // the importer makes no element of it
  const ModeShape shape = shapeOf(int(mode));
  // Without a POSITION attribute the importer makes a primitive of no vertices (and goes on).
  const std::optional<std::uint32_t> positions = indexOf(member(prim, "attributes"), "POSITION");
  const std::uint64_t vertices = positions ? unsignedOr(doc["accessors"][*positions], "count", 0) : 0;
  const std::string verticesText =
      !positions ? std::string("no vertices (no POSITION attribute)")
                 : fmt::format("{} {}", vertices, vertices == 1 ? "vertex" : "vertices");
  const std::optional<std::uint32_t> indices = indexOf(prim, "indices");
  if (!indices) {
    // Without positions (the primitive is then not drawn) only the strips and fans count their elements wrongly.
    if (vertices < shape.fewest && (positions || mode == 3 || mode >= 5))
      throw Error(fmt::format("{}: mode {} ({}) needs at least {} vertices but the primitive has {}", where, mode,
                              shape.name, shape.fewest, verticesText));
    return;
  }
  const AccessorBytes bytes = checkIndexAccessor(doc, *indices, buffers, where);
  if (bytes.count < shape.fewest)
    throw Error(fmt::format("{}: mode {} ({}) needs at least {} indices but index accessor {} has {}", where, mode,
                            shape.name, shape.fewest, *indices, bytes.count));
  if (!bytes.data) return;
  for (std::uint64_t i = 0; i < bytes.count; ++i) {
    std::uint64_t index = 0;
    for (std::uint64_t b = bytes.elementBytes; b-- > 0;) // little-endian
      index = (index << 8) | static_cast<unsigned char>((*bytes.data)[bytes.start + i * bytes.elementBytes + b]);
    if (index >= vertices)
      throw Error(fmt::format("{}: {} {} uses vertex index {} but the primitive has {}", where, shape.element,
                              elementOf(int(mode), i), index, verticesText));
  }
}

/// The glTF's JSON as a document, refused where the importer would not read it as glTF 2.0.
json parseGltfJson(const std::string& text, const std::string& name) {
  json doc;
  try {
    // The importer's JSON reader recurses into each level: a deep file ends it (a glTF needs a handful of levels).
    doc = json::parse(text, [&name](int depth, json::parse_event_t, json&) {
      if (depth > kMaxJsonDepth)
        throw Error(fmt::format("{}: not a glTF: its JSON nests deeper than {} levels", name, kMaxJsonDepth));
      return true;
    });
  } catch (const json::exception& e) {
    // Neither glTF importer takes it, and the importer would go on to sniff it with every other format's.
    throw Error(fmt::format("{}: not a glTF: malformed JSON: {}", name, oneLine(e.what(), 160)));
  }
  if (!doc.is_object()) throw Error(fmt::format("{}: not a glTF: its JSON is not an object", name));
  const json& version = member(member(doc, "asset"), "version");
  if (!version.is_string() || version.get<std::string>().rfind("2.", 0) != 0)
    throw Error(fmt::format("{}: asset.version is {}: only glTF 2.0 is read", name, oneLine(version.dump(), 40)));
  return doc;
}

/// Check every primitive of every mesh (checkPrimitive).
void checkMeshes(const json& doc, Buffers& buffers, const std::string& name) {
  const json& meshes = member(doc, "meshes");
  if (!meshes.is_array()) return; // the importer says what is wrong
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const json& prims = member(meshes[m], "primitives");
    if (!prims.is_array()) continue;
    const json& label = member(meshes[m], "name");
    const std::string meshName = label.is_string() ? fmt::format("mesh '{}'", oneLine(label.get<std::string>(), 60))
                                                   : fmt::format("mesh {}", m);
    for (std::size_t p = 0; p < prims.size(); ++p)
      if (prims[p].is_object())
        checkPrimitive(doc, prims[p], buffers, fmt::format("{}: {} primitive {}", name, meshName, p));
  }
}

/// The object @a from with only its members named in @a keep (anything else as it is: the importer reports it).
json keepOnly(const json& from, std::initializer_list<const char*> keep) {
  if (!from.is_object()) return from;
  json out = json::object();
  for (const char* key : keep)
    if (from.contains(key)) out[key] = from[key];
  return out;
}

/// @a doc with only what the surface needs: the scenes' node tree with its transforms and meshes, each primitive's
/// positions, indices and mode (and its extensions, which the importer refuses where it cannot read them), and the
/// accessors, views and buffers they name. Skins, animations, materials, textures, images, cameras and the other
/// attributes are dropped: the importer reads each (skins and animations whether or not anything uses them), and
/// trusts what they say (a skin without inverse bind matrices, an animation sampler of no inputs ended it). External
/// buffers are named by their absolute paths, as the importer reads this document from memory.
json geometryOnly(const json& doc, const GltfParts& parts, const fs::path& folder) {
  json out = keepOnly(doc, {"asset", "scene", "scenes", "extensionsUsed", "extensionsRequired", "accessors",
                            "bufferViews", "buffers"});
  if (const json& nodes = member(doc, "nodes"); nodes.is_array()) {
    out["nodes"] = json::array();
    for (const json& node : nodes)
      out["nodes"].push_back(
          keepOnly(node, {"name", "children", "matrix", "translation", "rotation", "scale", "mesh"}));
  }
  if (const json& meshes = member(doc, "meshes"); meshes.is_array()) {
    out["meshes"] = json::array();
    for (const json& mesh : meshes) {
      json kept = keepOnly(mesh, {"name", "primitives"});
      if (kept.is_object() && kept.contains("primitives") && kept["primitives"].is_array())
        for (json& prim : kept["primitives"]) {
          const json attributes = keepOnly(member(prim, "attributes"), {"POSITION"});
          prim = keepOnly(prim, {"mode", "indices", "extensions"});
          if (prim.is_object()) prim["attributes"] = attributes.is_null() ? json::object() : attributes;
        }
      out["meshes"].push_back(std::move(kept));
    }
  }
  if (out.contains("buffers") && out["buffers"].is_array())
    for (std::size_t i = 0; i < out["buffers"].size(); ++i) {
      json& buffer = out["buffers"][i];
      const json& uri = member(buffer, "uri");
      if (!uri.is_string()) continue;
      if (parts.glb && i == 0) buffer.erase("uri"); // the importer's buffer 0 of a GLB is its BIN chunk
      else if (uri.get<std::string>().rfind("data:", 0) != 0 && !folder.empty())
        buffer["uri"] = (folder / uri.get<std::string>()).string();
    }
  return out;
}

/// A GLB of @a jsonText and, where the file had one, its BIN chunk @a bin.
std::string assembleGlb(std::string jsonText, const std::optional<std::string>& bin) {
  const auto u32 = [](std::uint64_t v) {
    std::string b(4, '\0');
    for (int i = 0; i < 4; ++i) b[std::size_t(i)] = char((v >> (8 * i)) & 0xFF);
    return b;
  };
  while (jsonText.size() % 4) jsonText += ' ';
  std::string body = u32(jsonText.size()) + u32(kChunkJson) + jsonText;
  if (bin) {
    std::string padded = *bin;
    while (padded.size() % 4) padded += '\0';
    body += u32(padded.size()) + u32(kChunkBin) + padded;
  }
  return "glTF" + u32(2) + u32(12 + body.size()) + body;
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

std::string gltfGeometry(const std::string& bytes, const std::string& name, const fs::path& folder, bool allowOutside) {
  std::optional<GltfParts> parts = splitGltf(bytes);
  if (!parts)
    throw Error(fmt::format("{}: not a glTF: a GLB's first chunk must be its JSON and its second, if any, its BIN "
                            "chunk, each within the file", name));
  const json doc = parseGltfJson(parts->jsonText, name);
  Buffers buffers(doc, *parts, folder, name, allowOutside);
  try {
    checkMeshes(doc, buffers, name);
  } catch (const json::exception& e) { // not expected: every member is read by its type
    throw Error(fmt::format("{}: not a glTF: {}", name, oneLine(e.what(), 160)));
  }
  const std::string text = geometryOnly(doc, *parts, folder).dump();
  return parts->glb ? assembleGlb(text, parts->hasBin ? std::optional<std::string>(parts->bin) : std::nullopt) : text;
}

} // namespace rtsdf
