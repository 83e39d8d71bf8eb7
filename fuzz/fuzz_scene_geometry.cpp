// Fuzz target: a scene's geometry, not just its JSON: instances' transforms and animations placed at several
// times (buildSceneGeometry, checkInstancePlacement), on the built-in meshes (box, sphere) a scene can hold
// without files. Any bytes must give geometry or an rtsdf::Error; never a non-finite or out-of-range vertex.
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "util/Error.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    // A folder that does not exist: mesh paths in the input never reach real files.
    const rtsdf::Scene scene =
        rtsdf::parseScene(std::string(reinterpret_cast<const char*>(data), size), "/nonexistent/fuzz.json");
    // Geometry is placed per instance: bound the work per input (a sphere of 7 subdivisions in many instances is
    // big, not wrong), so that the fuzzer spends its time on transforms and ranges.
    std::size_t placed = 0;
    for (const rtsdf::Instance& i : scene.instances) placed += scene.meshes[i.mesh].triangles.size();
    if (placed > 200000) return 0;
    std::vector<rtsdf::Bounds> meshBounds;
    for (const rtsdf::Mesh& m : scene.meshes) meshBounds.push_back(rtsdf::positionBounds(m));
    for (const double t : {0.0, 0.5, 1.0 / 3.0, 7.25, 1e6}) {
      rtsdf::checkInstancePlacement(scene, meshBounds, t);
      const rtsdf::SceneGeometry geo = rtsdf::buildSceneGeometry(scene, t);
      for (const rtsdf::WorldMesh& w : geo.meshes)
        for (const auto& p : w.positions)
          if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
    }
  } catch (const rtsdf::Error&) {
  }
  return 0;
}
