#include "scene/MeshIO.h"

#include "scene/ConfinedFiles.h"
#include "scene/GltfChecks.h"
#include "scene/MeshFileChecks.h"
#include "util/Error.h"
#include "util/InputFile.h"
#include "util/Memory.h"
#include "util/Text.h"

#include <assimp/BaseImporter.h>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <set>

namespace rtsdf {
namespace fs = std::filesystem;

namespace {

// The import reads and validates only (ValidateDataStructure: a malformed import, like a face without indices, is
// an error instead of an assertion abort later); the post-processing runs after postProcess() has made the
// primitive types agree with the faces.
constexpr unsigned kReadSteps = aiProcess_ValidateDataStructure;
constexpr unsigned kPostSteps = aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType;

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
                                  oneLine(am->mName.C_Str(), 60), f, face.mIndices[c], am->mNumVertices));
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

/// Take out of @a importer every importer that does not claim @a fileName's extension (as assimp matches them: the
/// name's end, any case). Where the importers that claim it decline a file (two claim .gltf and .glb, and both
/// decline a JSON that does not parse), assimp would try every other importer's sniffing on the bytes, and some
/// read past the end of what is not theirs (fuzz_gltf: the OBJ importer on such a .gltf, a SEGV).
void keepOnlyImportersOf(Assimp::Importer& importer, const std::string& fileName) {
  const std::string name = toLower(fileName);
  for (std::size_t i = importer.GetImporterCount(); i-- > 0;) {
    Assimp::BaseImporter* candidate = importer.GetImporter(i);
    std::set<std::string> extensions;
    candidate->GetExtensionList(extensions);
    const bool claims = std::any_of(extensions.begin(), extensions.end(), [&name](const std::string& e) {
      const std::string end = "." + toLower(e);
      return name.size() >= end.size() && name.compare(name.size() - end.size(), end.size(), end) == 0;
    });
    // Taken out of the importer's list, it is ours to delete (the importer deletes only what its list holds).
    if (!claims && importer.UnregisterLoader(candidate) == aiReturn_SUCCESS) delete candidate;
  }
}

void configure(Assimp::Importer& importer, const std::string& fileName) {
  // Keep only triangles; points and lines carry no surface.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  keepOnlyImportersOf(importer, fileName);
}

} // namespace

bool isMeshFile(const fs::path& path) {
  Assimp::Importer importer;
  return path.has_extension() && importer.IsExtensionSupported(path.extension().string());
}

Mesh loadMeshFile(const fs::path& path, const MeshLoadOptions& options) {
  const std::uint64_t size = checkInputFile(path, "mesh file");
  // The importer holds the file and its mesh in memory: a file larger than the memory available cannot load.
  if (const std::uint64_t available = availableHostMemory(); available && size > available)
    throw Error(fmt::format("{}: the mesh file has {:.1f} GiB, more than the {:.1f} GiB of memory available",
                            path.string(), double(size) / (1u << 30), double(available) / (1u << 30)));
  const std::string ext = toLower(path.extension().string());
  checkHeaderClaims(readFileHead(path, 1 << 16), size, ext, path.string());
  // A glTF is read as gltfGeometry hands it on: checked, and only its surface.
  std::optional<std::string> gltf;
  if (ext == ".glb" || ext == ".gltf") {
    checkGltfForm(readFileHead(path, 64), ext, path.string());
    checkGlbFile(path, size);
    gltf = gltfGeometry(readFileHead(path, size), path.string(), fs::absolute(path).parent_path(),
                        options.allowOutsideReferences);
  }
  if (ext == ".obj") checkObjLines(readFileHead(path, size), path.string());
  Assimp::Importer importer;
  configure(importer, path.string());
  // Every file assimp opens goes through the confined file system (the importer owns and deletes it).
  // The path is made absolute so that every path the importer builds from a reference is absolute too: a bare
  // name would be read from the working folder.
  const std::string absolute = fs::absolute(path).string();
  ConfinedIOSystem* files = options.allowOutsideReferences ? nullptr : new ConfinedIOSystem(absolute, path.string());
  if (files) importer.SetIOHandler(files);
  // No vertex joining or degenerate removal here: validateMesh() welds and counts what it drops.
  const bool read = gltf ? importer.ReadFileFromMemory(gltf->data(), gltf->size(), kReadSteps, ext.c_str() + 1)
                         : importer.ReadFile(absolute, kReadSteps);
  const aiScene* scene = read ? postProcess(importer, path.string()) : nullptr;
  // A refused reference is the error even where the importer went on without the file (OBJ material libraries).
  if (files && !files->refusal().empty()) throw Error(files->refusal());
  if (!scene)
    throw Error(fmt::format("{}: cannot read mesh: {}", path.string(), oneLine(importer.GetErrorString())));
  Mesh mesh = toMesh(*scene, path.string());
  mesh.source = path.string();
  mesh.name = path.stem().string();
  return mesh;
}

Mesh loadMeshFromMemory(const std::string& bytes, const std::string& extension, const std::string& name) {
  checkHeaderClaims(bytes.substr(0, 1 << 16), bytes.size(), extension, name);
  std::string gltf;
  if (toLower(extension) == ".glb" || toLower(extension) == "glb" || toLower(extension) == ".gltf" ||
      toLower(extension) == "gltf") {
    checkGltfForm(bytes.substr(0, 64), extension, name);
    gltf = gltfGeometry(bytes, name, {}, false);
  }
  const std::string& read = gltf.empty() ? bytes : gltf;
  if (toLower(extension) == ".obj" || toLower(extension) == "obj") checkObjLines(bytes, name);
  Assimp::Importer importer;
  const std::string hint = extension.empty() || extension[0] != '.' ? extension : extension.substr(1);
  configure(importer, "." + hint);
  // assimp's memory reader hands every other name to the importer's file system: this one has no file.
  ConfinedIOSystem* files = new ConfinedIOSystem(name);
  importer.SetIOHandler(files);
  const aiScene* scene =
      importer.ReadFileFromMemory(read.data(), read.size(), kReadSteps, hint.c_str()) ? postProcess(importer, name)
                                                                                      : nullptr;
  if (!files->refusal().empty()) throw Error(files->refusal());
  if (!scene) throw Error(fmt::format("{}: cannot read mesh: {}", name, oneLine(importer.GetErrorString())));
  Mesh mesh = toMesh(*scene, name);
  mesh.source = mesh.name = name;
  return mesh;
}

} // namespace rtsdf
