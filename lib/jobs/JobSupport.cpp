#include "jobs/JobSupport.h"

#include "sdf/SdfPipeline.h"
#include "util/Error.h"
#include "util/Text.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace rtsdf {

std::string meshSummary(const Scene& scene) {
  std::size_t tris = 0, dropped = 0, open = 0, reoriented = 0, turned = 0;
  for (const MeshReport& r : scene.meshReports) {
    tris += r.triangles;
    dropped += r.degenerateDropped;
    open += r.watertight() ? 0 : 1;
    reoriented += r.orientation.reorientedTriangles;
    turned += r.orientation.piecesTurnedOutward;
  }
  std::string repaired;
  if (reoriented) repaired = fmt::format(", {} faces re-oriented ({} closed pieces turned outward)", reoriented, turned);
  return fmt::format("{} meshes ({} open), {} instances, {} triangles, {} zero-area dropped{}", scene.meshes.size(),
                     open, scene.instances.size(), tris, dropped, repaired);
}

gpu::ContextOptions deviceContextOptions(const std::string& device) {
  gpu::ContextOptions o;
  o.device = device;
  return o;
}

void throwOnValidationErrors(const gpu::VulkanContext& ctx) {
  if (ctx.validationErrors())
    throw Error(fmt::format("Vulkan validation reported {} error(s); last: {}", ctx.validationErrors(),
                            oneLine(ctx.lastValidationMessage())));
}

void warnOfCutWalks(std::uint64_t cutVoxels, const std::string& device) {
  if (cutVoxels)
    spdlog::warn("{} fine voxel refinement(s) on {} ran out of the CPU device's loop budget (a voxel about equally "
                 "near very many triangles, such as the centre of a finely tessellated sphere): each kept the "
                 "nearest surface found, an upper bound of its distance; a GPU device has no such limit",
                 cutVoxels, device);
}

void warmUpGpu(double seconds, const std::function<void()>& gpuWork) {
  if (!(seconds > 0.0)) return;
  const auto t0 = std::chrono::steady_clock::now();
  do gpuWork();
  while (secondsSince(t0) < seconds);
}

void warmUpPipeline(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& bounds,
                    const PipelineSettings& settings, double seconds) {
  if (!(seconds > 0.0)) return;
  PipelineSettings full = settings;
  full.fullRecompute = true; // every masked voxel refined: the most work a frame of these settings does
  SdfPipeline warm(ctx, scene, bounds, full);
  warmUpGpu(seconds, [&] { warm.runFrame(0.0); });
}

std::string bundledScene(const std::string& name) { return std::string(RTSDF_DATA_DIR) + "/scenes/" + name; }

std::string bundledMesh(const std::string& name) { return std::string(RTSDF_DATA_DIR) + "/meshes/" + name; }

} // namespace rtsdf

namespace rtsdf::detail {

std::string meshSummary(const Scene& scene) {
  std::size_t tris = 0, dropped = 0, open = 0;
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    tris += scene.meshReports[i].triangles;
    dropped += scene.meshReports[i].degenerateDropped;
    open += scene.meshReports[i].watertight() ? 0 : 1;
  }
  return fmt::format("{} meshes ({} open), {} instances, {} triangles, {} zero-area dropped", scene.meshes.size(), open,
                     scene.instances.size(), tris, dropped);
}

const char* version() { return RTSDF_VERSION; }

} // namespace rtsdf::detail
