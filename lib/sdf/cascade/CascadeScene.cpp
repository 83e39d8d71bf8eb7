#include "sdf/cascade/CascadeScene.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace rtsdf {

Bounds instanceBoxAt(const Instance& instance, const Bounds& meshBounds, double time) {
  Bounds box;
  if (meshBounds.empty()) return box;
  const glm::dmat4 m = instance.matrixAt(time);
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec4 p((corner & 1 ? meshBounds.max : meshBounds.min).x,
                       (corner & 2 ? meshBounds.max : meshBounds.min).y,
                       (corner & 4 ? meshBounds.max : meshBounds.min).z, 1.0);
    box.add(glm::dvec3(m * p));
  }
  return box;
}

namespace {

bool overlaps(const Bounds& a, const Bounds& b) {
  return !a.empty() && !b.empty() && glm::all(glm::lessThanEqual(a.min, b.max)) &&
         glm::all(glm::lessThanEqual(b.min, a.max));
}

} // namespace

Scene levelScene(const Scene& scene, const Bounds& box, double margin) {
  const Bounds reach{box.min - margin, box.max + margin};
  Scene out;
  out.path = scene.path;
  out.lights = scene.lights;
  out.camera = scene.camera;
  out.hasCamera = scene.hasCamera;
  out.cameraPath = scene.cameraPath;
  std::vector<Bounds> meshBounds;
  for (const Mesh& mesh : scene.meshes) meshBounds.push_back(positionBounds(mesh));
  std::map<std::size_t, std::size_t> meshIndex; // the scene's mesh -> the level's
  for (const Instance& inst : scene.instances) {
    const bool moves = inst.animation.kind != Animation::Kind::None;
    if (!moves && !overlaps(instanceBoxAt(inst, meshBounds.at(inst.mesh), 0.0), reach)) continue;
    auto [it, added] = meshIndex.emplace(inst.mesh, out.meshes.size());
    if (added) {
      out.meshes.push_back(scene.meshes.at(inst.mesh));
      if (inst.mesh < scene.meshReports.size()) out.meshReports.push_back(scene.meshReports[inst.mesh]);
    }
    Instance kept = inst;
    kept.mesh = it->second;
    out.instances.push_back(std::move(kept));
  }
  return out;
}

double levelSceneMargin(double band, double coarseVoxel, double fineVoxel) {
  return std::max(band, 0.0) + 2.0 * std::sqrt(3.0) * coarseVoxel + fineVoxel;
}

double levelSceneSlack(const CascadeShape& shape, int level) {
  const int moves = std::max(1, shape.coarseRes / 4 / std::max(1, shape.moveCells));
  return shape.coarseVoxel(level) * std::max(1, shape.moveCells) * moves;
}

double levelCutMargin(const CascadeShape& shape, const CascadeLevel& level, double band) {
  return levelSceneMargin(band, level.coarse.voxelSize, level.fine.voxelSize) + levelSceneSlack(shape, level.index);
}

std::uint64_t instanceTriangles(const Scene& scene) {
  std::uint64_t n = 0;
  for (const Instance& inst : scene.instances) n += scene.meshes.at(inst.mesh).triangles.size();
  return n;
}

} // namespace rtsdf
