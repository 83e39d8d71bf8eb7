#pragma once
/// @file CascadeSet.h
/// @brief Camera-centred cascade levels on the GPU: one set of pipeline parts per level (an SdfPipeline on the level's
///        grids, over the instances near its box), each with its own coarse SDF, ray mask, brick pool and refinement
///        state, so a level's memory is that of one box of today's counts whatever the world's size.
#include "gpu/VulkanContext.h"
#include "scene/Scene.h"
#include "sdf/SdfPipeline.h"
#include "sdf/cascade/CascadeLayout.h"
#include "sdf/cascade/CascadeMemory.h"

#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace rtsdf {

/// @brief What moveTo() did: the levels whose box moved; of those, the ones whose scene was cut again as they
///        scrolled, and the ones rebuilt from scratch (the others scrolled, keeping what they knew).
struct CascadeMove {
  std::vector<int> moved, recut, rebuilt;
};

/// @brief K levels around a camera position (CascadeLayout), each an SdfPipeline of its own. A camera move that
///        changes a level's snapped box scrolls that level (SdfPipeline::scroll: its buffers shift by whole bricks,
///        and the next frame refines only what entered). Its part of the scene is cut with some slack
///        (levelSceneSlack); a level that drifts past it gets its scene cut again around its new box as it scrolls.
///        A level whose grids cannot scroll (a jump of a grid's width or more, fine voxels straddling coarse ones)
///        is rebuilt from scratch.
class CascadeSet {
public:
  /// @throw SettingError as SdfPipeline, and naming the fine resolution when all levels together do not fit the
  ///        device or host (checked before any level is allocated).
  CascadeSet(const gpu::VulkanContext& ctx, const Scene& scene, const CascadeLayout& layout,
             const PipelineSettings& s);
  ~CascadeSet();
  CascadeSet(const CascadeSet&) = delete;
  CascadeSet& operator=(const CascadeSet&) = delete;

  /// @brief One frame of every level at @a time seconds, finest first; their statistics. Levels lost by a move
  ///        that failed are built again first.
  /// @throw Error as SdfPipeline::runFrame, and as the constructor for a lost level built again.
  std::vector<FrameStats> runFrame(double time);
  /// @brief Centre the levels on @a camera (level i on camera + lookAhead 2^i, CascadeLayout::around); a level
  ///        whose snapped box changed scrolls, or is rebuilt (its history lost) where it cannot (see the class).
  ///        Levels lost by a move that failed are built again (listed as rebuilt, not as moved).
  /// @throw Error where a level's scroll or rebuild fails (the device's): that level, and the levels after it that
  ///        were to move, are lost (their buffers released; level() refuses them) until the next runFrame or moveTo
  ///        builds them again where the layout then puts them. The layout is the new one in any case.
  CascadeMove moveTo(const glm::dvec3& camera, const glm::dvec3& lookAhead = glm::dvec3(0.0));
  /// @brief From the next frame on, levels above 0 refine only the band near @a camera's view: within
  ///        PipelineSettings::cascadeViewMargin of their coarse voxels of the cone holding the image at @a aspect
  ///        (width over height; SdfPipeline::setViewReach). A negative margin leaves every level refining its whole
  ///        band. Levels rebuilt later take the same view.
  /// @throw Error as viewReachOf.
  void setView(const Camera& camera, double aspect);
  int levels() const { return int(mLevels.size()); }
  /// @throw Error for a level lost by a move that failed (see moveTo).
  const SdfPipeline& level(int i) const;
  /// @brief The instances level @a i places (levelScene).
  /// @throw Error as level().
  const Scene& levelScene(int i) const;
  const CascadeLayout& layout() const { return mLayout; }
  /// @brief The estimate checked at construction.
  const CascadeMemory& memory() const { return mMemory; }

private:
  struct Level {
    std::unique_ptr<Scene> scene; ///< outlives its pipeline, which keeps a reference
    std::unique_ptr<SdfPipeline> pipeline;
    Bounds sceneBox; ///< the box the scene was cut around (the level's box when it was built)
    bool lost = false; ///< a move failed on it: nothing held, built again before the set is used next
  };
  friend class CascadeFaults; // failures injected into moves, for tests
  /// Level @a i of the layout: its part of the scene and its pipeline (limited to the view where one is set).
  Level buildLevel(int i) const;
  /// buildLevel, where no failure is injected (CascadeFaults).
  Level freshLevel(int i);
  /// Release level @a i and mark it lost (moveTo's failures).
  void loseLevel(int i);
  /// Build every lost level again (where the layout puts it), appending their indices to @a rebuilt if given.
  void rebuildLostLevels(std::vector<int>* rebuilt);
  /// Limit level @a i's refinement to the view set (setView), if any, for i > 0.
  void applyView(int i, SdfPipeline& level) const;
  /// Level @a i's part of the scene around its box in the layout (levelScene with levelCutMargin).
  std::unique_ptr<Scene> cutScene(int i) const;
  /// Scroll level @a i to the layout's box, its scene cut again when it drifted past the slack; false when its grids
  /// cannot scroll there. @a recut: set when the scene was cut again.
  bool scrollLevel(int i, bool& recut);
  const gpu::VulkanContext& mCtx;
  const Scene& mScene;
  PipelineSettings mSettings;
  CascadeLayout mLayout;
  CascadeMemory mMemory;
  std::vector<Level> mLevels;
  gpu::Buffer mScrollScratch; ///< shared by the levels' scrolls (SdfPipeline::scroll), one at a time
  std::optional<std::pair<Camera, double>> mView; ///< setView's camera and aspect
  bool mFailNextBuild = false; ///< tests (CascadeFaults): the next level built in a move or again throws Error
};

/// @brief One frame's statistics over every level: counts, bytes and times summed, passes listed level after level
///        (passTotal sums a pass over the levels), the field changed where any level's did.
FrameStats sumFrameStats(const std::vector<FrameStats>& levels);

} // namespace rtsdf
