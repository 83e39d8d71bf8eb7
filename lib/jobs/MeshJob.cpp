#include "jobs/MeshJob.h"

#include "grid/VdbIO.h"
#include "util/AtomicFile.h"
#include "util/Error.h"
#include "util/Text.h"

#include <assimp/Exporter.hpp>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <cctype>
#include <memory>

namespace rtsdf {
namespace fs = std::filesystem;

namespace {

/// assimp's exporter for an output extension: OBJ without a material file, binary PLY and STL.
const char* exporterFor(const fs::path& output) {
  std::string ext = output.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".obj") return "objnomtl";
  if (ext == ".ply") return "plyb";
  if (ext == ".stl") return "stlb";
  return nullptr;
}

/// The polygons of volumeToMesh as one assimp mesh of outward triangles (OpenVDB winds them inward).
std::unique_ptr<aiScene> toScene(const std::vector<openvdb::Vec3s>& points, const std::vector<openvdb::Vec3I>& tris,
                                 const std::vector<openvdb::Vec4I>& quads) {
  auto scene = std::make_unique<aiScene>();
  scene->mRootNode = new aiNode("level set");
  scene->mRootNode->mNumMeshes = 1;
  scene->mRootNode->mMeshes = new unsigned[1]{0};
  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial*[1]{new aiMaterial()};
  scene->mNumMeshes = 1;
  auto* mesh = new aiMesh();
  scene->mMeshes = new aiMesh*[1]{mesh};
  mesh->mName = "surface";
  mesh->mMaterialIndex = 0;
  mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  mesh->mNumVertices = unsigned(points.size());
  mesh->mVertices = new aiVector3D[points.size()];
  for (std::size_t i = 0; i < points.size(); ++i) mesh->mVertices[i] = {points[i].x(), points[i].y(), points[i].z()};
  mesh->mNumFaces = unsigned(tris.size() + 2 * quads.size());
  mesh->mFaces = new aiFace[mesh->mNumFaces];
  unsigned f = 0;
  auto add = [&](unsigned a, unsigned b, unsigned c) {
    aiFace& face = mesh->mFaces[f++];
    face.mNumIndices = 3;
    face.mIndices = new unsigned[3]{a, c, b}; // reversed: outward
  };
  for (const auto& t : tris) add(t[0], t[1], t[2]);
  for (const auto& q : quads) {
    add(q[0], q[1], q[2]);
    add(q[0], q[2], q[3]);
  }
  return scene;
}

} // namespace

void MeshOptions::validate() const {
  validateKnobs(*this);
  if (!exporterFor(output))
    throw Error(fmt::format("{}: a mesh is written as .obj, .ply or .stl (the extension picks the format)",
                            output.string()));
}

MeshResult meshLevelSet(const MeshOptions& o, const JobControl& control) {
  o.validate();
  checkOutputPath(o.output, o.output.extension().string(), {o.input});
  const openvdb::FloatGrid::Ptr grid = readLevelSet(o.input, o.grid);
  control.report("meshing", 0, 1);
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*grid, points, tris, quads, o.isovalue, o.adaptivity);
  control.report("meshing", 1, 1);
  if (tris.empty() && quads.empty())
    throw Error(fmt::format("{}: the level {} crosses no voxel of grid '{}' (values from {} to {}): no surface to "
                            "mesh", o.input.string(), o.isovalue, oneLine(grid->getName(), 60),
                            -grid->background(), grid->background()));
  control.checkStop();
  MeshResult r;
  r.vertices = points.size();
  r.triangles = tris.size() + 2 * quads.size();
  for (const auto& p : points) r.bounds.add(glm::dvec3(p.x(), p.y(), p.z()));
  r.voxelSize = grid->voxelSize()[0];
  r.upAxis = upAxisOf(*grid) == UpAxis::Z ? "z" : "y";
  const std::unique_ptr<aiScene> scene = toScene(points, tris, quads);
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(scene.get(), exporterFor(o.output));
  if (!blob || blob->next) // one file: a second blob would be a material library
    throw Error(fmt::format("{}: cannot write the mesh: {}", o.output.string(),
                            blob ? "the exporter made several files" : oneLine(exporter.GetErrorString(), 200)));
  writeTextAtomically(o.output, std::string(static_cast<const char*>(blob->data), blob->size));
  return r;
}

std::string MeshResult::report(const MeshOptions& o) const {
  std::string t = fmt::format("input      {} (voxel size {:.6g}, up {})\n", o.input.string(), voxelSize, upAxis);
  t += fmt::format("level      {}{}\n", o.isovalue, o.adaptivity > 0.0 ? fmt::format(", adaptivity {}", o.adaptivity)
                                                                           : std::string());
  t += fmt::format("mesh       {} vertices, {} triangles\n", vertices, triangles);
  t += fmt::format("bounds     ({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g})\n", bounds.min.x, bounds.min.y,
                   bounds.min.z, bounds.max.x, bounds.max.y, bounds.max.z);
  t += fmt::format("output     {}\n", o.output.string());
  return t;
}

} // namespace rtsdf
