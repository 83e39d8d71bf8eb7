#include "scene/MeshIO.h"

#include "util/Error.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <system_error>

namespace rtsdf {
namespace fs = std::filesystem;

bool isMeshFile(const fs::path& path) {
  Assimp::Importer importer;
  return path.has_extension() && importer.IsExtensionSupported(path.extension().string());
}

Mesh loadMeshFile(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(fmt::format("{}: mesh file not found", path.string()));
  if (!fs::is_regular_file(path, ec)) throw Error(fmt::format("{}: not a regular file", path.string()));

  Assimp::Importer importer;
  // Keep only triangles; points and lines carry no surface.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // No vertex joining or degenerate removal here: validateMesh() welds and counts what it drops.
  const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                                              aiProcess_SortByPType);
  if (!scene) throw Error(fmt::format("{}: cannot read mesh: {}", path.string(), importer.GetErrorString()));

  Mesh mesh;
  mesh.source = path.string();
  mesh.name = path.stem().string();
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const unsigned base = unsigned(mesh.positions.size());
    for (unsigned v = 0; v < am->mNumVertices; ++v)
      mesh.positions.emplace_back(am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z);
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (unsigned c = 0; c < 3; ++c)
        if (face.mIndices[c] >= am->mNumVertices)
          throw Error(fmt::format("{}: mesh '{}' face {} uses vertex index {} but it has {} vertices", path.string(),
                                  am->mName.C_Str(), f, face.mIndices[c], am->mNumVertices));
      mesh.triangles.emplace_back(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
    }
  }
  if (mesh.triangles.empty()) throw Error(fmt::format("{}: empty mesh (no triangles)", path.string()));
  return mesh;
}

} // namespace rtsdf
