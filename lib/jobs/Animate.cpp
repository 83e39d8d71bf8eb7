#include "jobs/Animate.h"

#include "grid/VdbIO.h"
#include "jobs/Bake.h"
#include "jobs/JobSupport.h"
#include "reference/ExactSdf.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/coarse/CoarseSdf.h"
#include "sdf/refine/RefinePasses.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>

namespace rtsdf {
namespace fs = std::filesystem;

PipelineSettings AnimateOptions::defaultPipeline() {
  return PipelineSettings{};
}

void AnimateOptions::validate() const {
  pipeline.validate();
  validateKnobs(*this);
  std::error_code ec;
  if (!vdbDir.empty() && !fs::is_directory(vdbDir, ec))
    throw SettingError("vdb folder", fmt::format("{}: {}", vdbDir.string(),
                                                 fs::exists(vdbDir, ec) ? "is not a folder" : "folder does not exist"));
}

namespace {

std::size_t focusInstance(const Scene& scene, const AnimateOptions& a) {
  for (std::size_t i = 0; i < scene.instances.size(); ++i)
    if (scene.instances[i].name == a.focus) return i;
  throw SettingError("focus", fmt::format("{} has no instance named '{}'", a.scene, a.focus));
}

/// The box instance @a idx sweeps over the animation, grown by the band, in fine index space.
openvdb::CoordBBox focusBox(const Scene& scene, const AnimateOptions& a, std::size_t idx, const GridSpec& fine) {
  Bounds swept;
  for (int f = 0; f < a.frames; ++f) {
    const SceneGeometry g = buildSceneGeometry(scene, a.still ? 0.0 : f / a.fps);
    for (const glm::vec3& p : g.meshes[idx].positions) swept.add(glm::dvec3(p));
  }
  const double band = a.pipeline.band.sceneUnits(fine.voxelSize);
  const glm::dvec3 lo = fine.worldToIndex(swept.min - band);
  const glm::dvec3 hi = fine.worldToIndex(swept.max + band);
  return openvdb::CoordBBox(openvdb::Coord(int(std::floor(lo.x)), int(std::floor(lo.y)), int(std::floor(lo.z))),
                            openvdb::Coord(int(std::ceil(hi.x)), int(std::ceil(hi.y)), int(std::ceil(hi.z))));
}


/// The frame files this run wrote: removed again unless the run finishes (keep()), so a failed or interrupted
/// animation leaves no output of any kind.
class WrittenFrames {
public:
  WrittenFrames() = default;
  WrittenFrames(const WrittenFrames&) = delete;
  WrittenFrames& operator=(const WrittenFrames&) = delete;
  ~WrittenFrames() {
    std::error_code ec;
    for (const fs::path& p : mPaths) fs::remove(p, ec);
  }
  void add(fs::path p) { mPaths.push_back(std::move(p)); }
  void keep() { mPaths.clear(); }

private:
  std::vector<fs::path> mPaths;
};

} // namespace

FieldError fieldErrorAgainstExact(const Scene& scene, const SdfPipeline& pipe, double t,
                                  const openvdb::CoordBBox* focus) {
  const SceneGeometry geo = buildSceneGeometry(scene, t);
  ExactSdfOptions eo;
  eo.band = fineLevelSetBand(pipe.settings(), pipe.fineSpec());
  eo.progress = false;
  const auto exact = exactSignedDistance(geo, pipe.fineSpec(), eo);
  if (focus) exact->clip(*focus);
  const auto fine = denseToLevelSet(pipe.fineField(), pipe.fineSpec(), float(eo.band));
  // A cascade level's band out of the view's reach holds the coarse SDF, not a refinement: not the level's voxels.
  for (const std::uint32_t packed : pipe.outOfViewVoxels())
    fine->tree().setValueOff(openvdb::Coord(int(packed & 1023u), int((packed >> 10) & 1023u), int(packed >> 20)));
  fine->setTransform(exact->transform().copy());
  return compareFields(*exact, *fine);
}

AnimateResult animate(const AnimateOptions& a, const JobControl& control,
                      const std::function<void(const AnimateFrame&)>& onFrame) {
  a.validate();
  const Scene scene = loadScene(a.scene, a.meshLoad);
  const std::size_t focus = a.focus.empty() ? 0 : focusInstance(scene, a);
  // Grids fixed over the whole animation: the union of the scene's bounds at every frame.
  Bounds bounds;
  for (int f = 0; f < a.frames; ++f) bounds.add(buildSceneGeometry(scene, a.still ? 0.0 : f / a.fps).bounds);
  WrittenFrames written; // removed unless the whole animation ran without a validation error
  AnimateResult result = runOnDevice(deviceContextOptions(a.device), [&](const gpu::VulkanContext& ctx) {
    warmUpPipeline(ctx, scene, bounds, a.pipeline, a.warmUpSeconds);
    SdfPipeline pipe(ctx, scene, bounds, a.pipeline);
    spdlog::info("coarse {}, fine {}", pipe.coarseSpec().describe(), pipe.fineSpec().describe());
    openvdb::CoordBBox box;
    if (!a.focus.empty()) box = focusBox(scene, a, focus, pipe.fineSpec());
    BakeOptions stamp; // the per-frame files carry the pipeline's settings
    stamp.scene = a.scene;
    stamp.pipeline = pipe.settings(); // lengths in scene units
    stamp.frames = a.frames;
    AnimateResult run;
    run.coarse = pipe.coarseSpec();
    run.fine = pipe.fineSpec();
    for (int f = 0; f < a.frames; ++f) {
      control.checkStop();
      AnimateFrame fr;
      fr.frame = f;
      fr.time = a.still ? 0.0 : f / a.fps;
      fr.stats = pipe.runFrame(fr.time);
      fr.deviceBytesAllocated = ctx.deviceBytesInUse(); // the pipeline alone: the warm-up's is released
      if (a.measureError) fr.error = fieldErrorAgainstExact(scene, pipe, fr.time, a.focus.empty() ? nullptr : &box);
      if (!a.vdbDir.empty()) {
        const fs::path file = a.vdbDir / fmt::format("frame{:04d}.vdb", f);
        writeVdb(file, {fineLevelSet(pipe, stamp, fr.time)}, a.vdb);
        written.add(file);
      }
      run.frames.push_back(fr);
      if (onFrame) onFrame(fr);
      control.report("animate", std::uint64_t(f + 1), std::uint64_t(a.frames));
    }
    std::uint64_t cut = 0;
    for (const AnimateFrame& fr : run.frames) cut += fr.stats.cutVoxels;
    warnOfCutWalks(cut, ctx.info().name);
    return run;
  });
  written.keep();
  return result;
}

std::string AnimateResult::csv() const {
  std::string csv = "frame,time,mask_coarse,mask_fine,voxelize_ms,transform_ms,distance_ms,upsample_ms,refine_ms,"
                    "host_ms,band_voxels,mean_abs_error_voxels,max_abs_error_voxels,wrong_sign_rate,refined_fine\n";
  for (const AnimateFrame& fr : frames) {
    const FrameStats& st = fr.stats;
    const FieldError& err = fr.error;
    csv += fmt::format("{},{},{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{},{:.5f},{:.4f},{:.6f},{}\n", fr.frame,
                       fr.time, st.maskCoarseVoxels, st.maskFineVoxels, st.passTotal(VoxelizePass::kName),
                       coarseTransformMs(st.passMs), st.passTotal(CoarseDistancePass::kName),
                       st.passTotal(UpsamplePass::kName), st.refineMs(), st.hostMs, err.voxels, err.meanAbs,
                       err.maxAbs, err.signErrorRate(), st.refinedFineVoxels);
  }
  return csv;
}

} // namespace rtsdf
