#pragma once
/// @file SweepRunner.h
/// @brief Runs the points of a sweep on one scene: the pipeline (and its soft shadows where the scene has a
///        camera) per point, the anchors, and the field error against the exact reference.
#include "suites/Sweep.h"
#include "gpu/VulkanContext.h"
#include "render/Renderer.h"
#include "scene/Scene.h"
#include "util/Error.h"

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rtsdf::bench {

/// @brief How the runner measures.
struct SweepRunOptions {
  std::string device;          ///< Vulkan device by index or name; empty: the best one
  double errorBand = 0.1;      ///< the field error is measured where |exact| <= errorBand (scene units)
  double fps = 30.0;           ///< frame rate of Dynamic points (scene time advances 1/fps per frame)
  int animationFrames = 16;    ///< the most frames a Dynamic point runs (the grids cover all of them)
  int repeats = 3;             ///< timed frames at least, after the first (warm-up): a static point with fewer
                               ///< frames runs more after its error is measured, for timing only
  bool shadows = true;         ///< measure the shadow image error where the scene has a camera and a light
  int shadowWidth = 320, shadowHeight = 180;
  int truthSamples = 256;      ///< samples per pixel of the ray-traced truth
  /// @brief Polled between frames: return true to stop (the point in progress throws SweepInterrupted).
  std::function<bool()> stopRequested;
  /// @throw SettingError naming the setting that is out of range.
  void validate() const;
};

/// @brief Thrown when SweepRunOptions::stopRequested said stop in the middle of a point.
struct SweepInterrupted : Interrupted {};

/// @brief One Vulkan context and one scene; points run one after another.
class SweepRunner {
public:
  /// @throw Error when the options are out of range; VulkanError when no Vulkan device is present.
  SweepRunner(const Scene& scene, const SweepRunOptions& options);
  ~SweepRunner();
  SweepRunner(const SweepRunner&) = delete;
  SweepRunner& operator=(const SweepRunner&) = delete;

  /// @brief Run one point: one record, or one per frame for a Dynamic point. A point that cannot run (a grid
  ///        beyond the device's limits, say) gives a record whose note says why; the sweep goes on.
  /// @throw SweepInterrupted when a stop was requested mid-point.
  std::vector<SweepRecord> run(const SweepPoint& point);

  /// @brief Destroy the device after the last point and refuse the sweep when the validation layer reported any
  ///        error during it (those at the device's destruction included). No point may run after.
  /// @throw Error from throwOnValidationErrors.
  void finish();

  bool animated() const { return mAnimated; }
  /// @brief Whether shadow errors are measured (the scene has a camera and a light, and shadows are on).
  bool measuresShadows() const { return mTruth != nullptr; }
  double sceneExtent() const { return mBounds.maxExtent(); }
  const gpu::DeviceInfo& device() const { return mCtx->info(); }
  /// @brief The runner's Vulkan context (its validation errors, say).
  const gpu::VulkanContext& context() const { return *mCtx; }

private:
  std::vector<SweepRecord> runPipeline(const SweepPoint& point);
  SweepRecord runAnchor(const SweepPoint& point);
  SweepRecord runStorage(const SweepPoint& point);
  /// The pipeline's fine grid for @a ps (pipelineGrids).
  GridSpec fineSpecOf(const PipelineSettings& ps) const;
  /// The exact field on @a spec at @a time over the error band (cached for static scenes).
  const openvdb::FloatGrid& exact(const GridSpec& spec, double time);
  void stopIfRequested() const;

  const Scene& mScene;
  SweepRunOptions mOptions;
  std::unique_ptr<gpu::VulkanContext> mCtx;
  Bounds mBounds;      ///< the grids' bounds: the union over the Dynamic frames
  bool mAnimated = false;
  std::unique_ptr<RenderedFrame> mTruth; ///< the ray-traced truth at time 0 (static points)
  std::map<std::string, openvdb::FloatGrid::Ptr> mExactCache;
};

} // namespace rtsdf::bench
