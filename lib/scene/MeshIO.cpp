#include "scene/MeshIO.h"

#include "util/Error.h"
#include "util/InputFile.h"
#include "util/Memory.h"
#include "util/Text.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>

namespace rtsdf {
namespace fs = std::filesystem;

namespace {

// The import reads and validates only (ValidateDataStructure: a malformed import, like a face without indices, is
// an error instead of an assertion abort later); the post-processing runs after postProcess() has made the
// primitive types agree with the faces.
constexpr unsigned kReadSteps = aiProcess_ValidateDataStructure;
constexpr unsigned kPostSteps = aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType;


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

/// A PLY header must end, and its element counts must fit in the file: in ASCII each property takes at least 2
/// bytes, in binary its type's size (a list at least its count's).
void checkPlyHeader(const std::string& head, std::uint64_t fileSize, const std::string& name) {
  std::istringstream in(head);
  std::string line, format;
  double need = 0, count = 0;
  std::string element;
  while (std::getline(in, line)) {
    std::istringstream w(line);
    std::string key;
    w >> key;
    if (endsPlyHeader(line)) key = "end_header";
    else if (key == "end_header") key.clear(); // a look-alike assimp reads past
    if (key == "format") w >> format;
    else if (key == "element") {
      w >> element >> count;
      if (!(count >= 0)) throw Error(fmt::format("{}: PLY element '{}' has a negative count", name, element));
    } else if (key == "property") {
      std::string type;
      w >> type;
      if (type == "list") w >> type; // a list takes at least its count's bytes
      need += count * (format == "ascii" ? 2 : std::max(1, plyTypeBytes(type)));
    } else if (key == "end_header") {
      if (need > double(fileSize))
        throw Error(fmt::format("{}: the PLY header declares elements that need at least {:.0f} bytes, but the "
                                "file has {}", name, need, fileSize));
      return;
    }
  }
  // assimp's PLY reader spins without end (a minute and more) on a header that never ends.
  throw Error(fmt::format("{}: the PLY header has no 'end_header' line (the word, then the end of its line) in its first {} bytes", name, head.size()));
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

/// Header claims checked against the file's size before assimp allocates for them.
void checkHeaderClaims(const std::string& head, std::uint64_t fileSize, const std::string& extension,
                       const std::string& name) {
  const std::string ext = toLower(extension);
  if (ext == ".off") checkOffHeader(head, fileSize, name);
  if (ext == ".ply") checkPlyHeader(head, fileSize, name);
}

/// Every triangle of an imported scene, in one mesh.
Mesh toMesh(const aiScene& scene, const std::string& name) {
  Mesh mesh;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh* am = scene.mMeshes[m];
    if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const unsigned base = unsigned(mesh.positions.size());
    for (unsigned v = 0; v < am->mNumVertices; ++v)
      mesh.positions.emplace_back(am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z);
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (unsigned c = 0; c < 3; ++c)
        if (face.mIndices[c] >= am->mNumVertices)
          throw Error(fmt::format("{}: mesh '{}' face {} uses vertex index {} but it has {} vertices", name,
                                  am->mName.C_Str(), f, face.mIndices[c], am->mNumVertices));
      mesh.triangles.emplace_back(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
    }
  }
  if (mesh.triangles.empty()) throw Error(fmt::format("{}: empty mesh (no triangles)", name));
  return mesh;
}

/// Triangulate, flatten and sort an imported scene. Importers can flag a mesh as holding polygons when none of its
/// faces has more than three corners, or leave a face with none (the fuzzer found PLY files that do), and
/// assimp's Triangulate then aborts on an assertion: such faces are errors, and the flags are recomputed from
/// the faces. @return nullptr when post-processing fails. @throw Error naming @a name for a face without corners.
const aiScene* postProcess(Assimp::Importer& importer, const std::string& name) {
  // The scene belongs to the importer until post-processing, which edits it in place anyway.
  aiScene* scene = const_cast<aiScene*>(importer.GetScene());
  if (!scene) return nullptr;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    aiMesh* mesh = scene->mMeshes[m];
    unsigned types = 0;
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const unsigned n = mesh->mFaces[f].mNumIndices;
      if (n == 0) throw Error(fmt::format("{}: cannot read mesh: face {} of mesh {} has no corners", name, f, m));
      types |= n == 1 ? aiPrimitiveType_POINT : n == 2 ? aiPrimitiveType_LINE : n == 3 ? aiPrimitiveType_TRIANGLE
                                                                                       : aiPrimitiveType_POLYGON;
    }
    mesh->mPrimitiveTypes = types;
  }
  return importer.ApplyPostProcessing(kPostSteps);
}

void configure(Assimp::Importer& importer) {
  // Keep only triangles; points and lines carry no surface.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
}

} // namespace

bool isMeshFile(const fs::path& path) {
  Assimp::Importer importer;
  return path.has_extension() && importer.IsExtensionSupported(path.extension().string());
}

Mesh loadMeshFile(const fs::path& path) {
  const std::uint64_t size = checkInputFile(path, "mesh file");
  // The importer holds the file and its mesh in memory: a file larger than the memory available cannot load.
  if (const std::uint64_t available = availableHostMemory(); available && size > available)
    throw Error(fmt::format("{}: the mesh file has {:.1f} GiB, more than the {:.1f} GiB of memory available",
                            path.string(), double(size) / (1u << 30), double(available) / (1u << 30)));
  checkHeaderClaims(readFileHead(path, 1 << 16), size, path.extension().string(), path.string());
  if (toLower(path.extension().string()) == ".obj") checkObjLines(readFileHead(path, size), path.string());
  Assimp::Importer importer;
  configure(importer);
  // No vertex joining or degenerate removal here: validateMesh() welds and counts what it drops.
  const aiScene* scene = importer.ReadFile(path.string(), kReadSteps) ? postProcess(importer, path.string()) : nullptr;
  if (!scene)
    throw Error(fmt::format("{}: cannot read mesh: {}", path.string(), oneLine(importer.GetErrorString())));
  Mesh mesh = toMesh(*scene, path.string());
  mesh.source = path.string();
  mesh.name = path.stem().string();
  return mesh;
}

Mesh loadMeshFromMemory(const std::string& bytes, const std::string& extension, const std::string& name) {
  checkHeaderClaims(bytes.substr(0, 1 << 16), bytes.size(), extension, name);
  if (toLower(extension) == ".obj" || toLower(extension) == "obj") checkObjLines(bytes, name);
  Assimp::Importer importer;
  configure(importer);
  const std::string hint = extension.empty() || extension[0] != '.' ? extension : extension.substr(1);
  const aiScene* scene =
      importer.ReadFileFromMemory(bytes.data(), bytes.size(), kReadSteps, hint.c_str()) ? postProcess(importer, name)
                                                                                        : nullptr;
  if (!scene) throw Error(fmt::format("{}: cannot read mesh: {}", name, oneLine(importer.GetErrorString())));
  Mesh mesh = toMesh(*scene, name);
  mesh.source = mesh.name = name;
  return mesh;
}

} // namespace rtsdf
