#pragma once
/// @file PipelineSettings.h
/// @brief The knobs of the RTSDF pipeline (PipelineSettings), their enums, the defaults that depend on them, and the
///        grids they give (pipelineGrids).
#include "grid/GridSpec.h"
#include "sdf/coarse/CoarseMethod.h"
#include "util/Bounds.h"
#include "util/EnumNames.h"
#include "util/Knobs.h"
#include "util/Length.h"

#include <cstdint>
#include <utility>

namespace rtsdf {

/// @brief How the fine SDF is refined.
enum class RefineMode {
  Rays,   ///< the paper: x random rays per masked voxel per frame, decayed history
  Closest ///< exact closest-point distance through the same BVH (deterministic)
};
template <> struct EnumNames<RefineMode> {
  static constexpr const char* kSetting = "refinement mode";
  static constexpr std::pair<const char*, RefineMode> kValues[] = {{"rays", RefineMode::Rays},
                                                                   {"closest", RefineMode::Closest}};
};

/// @brief How closest mode finds each fine voxel's nearest triangle. Both give the same distances (the same
///        triangle test on the same triangles); the sign ties among equally near triangles are resolved by the same
///        rule.
enum class ClosestSearch {
  Auto, ///< by the kind of device the shaders are for (ShaderTarget): Cell on a CPU device, Voxel on a GPU, the
        ///< faster on each (docs/results.md, "Closest mode's first frame: 4-5x on lavapipe, and what the same
        ///< changes did on an NVIDIA H200")
  Cell, ///< one BVH walk per box of at most 2x2x2 fine voxels under a coarse voxel collects the triangles that can be
        ///< nearest to one of them (at most RTSDF_CELL_CANDIDATES, the nearest kept); each voxel tests only those
  Voxel ///< one BVH walk per fine voxel
};
template <> struct EnumNames<ClosestSearch> {
  static constexpr const char* kSetting = "closest search";
  static constexpr std::pair<const char*, ClosestSearch> kValues[] = {
      {"auto", ClosestSearch::Auto}, {"cell", ClosestSearch::Cell}, {"voxel", ClosestSearch::Voxel}};
};

/// @brief The kind of device the refinement's shader variants are built for. A CPU device (lavapipe) runs the lanes
///        of a SIMD vector together and runs the code behind a branch whenever any lane takes it, so its BVH walks
///        descend to a leaf before testing its triangles (RTSDF_POINT_WALK_WHILE_WHILE); on a GPU that shape was 4x
///        slower, and one node per step is kept. The results are the same either way.
enum class ShaderTarget {
  Device, ///< the kind of the device the pipeline runs on
  Cpu,    ///< the CPU variants on any device (tests run both kinds on one device)
  Gpu     ///< the GPU variants on any device
};

/// @brief Where the fine SDF lives on the GPU. Either way the refinement keeps its values, sign votes and history
///        only in bricks of RTSDF_BRICK^3 fine voxels under the ray mask (the sparse fine state, a pool sized by the
///        mask); outside the mask the fine SDF is the coarse one upsampled.
enum class FineStorage {
  Dense, ///< also a dense fine SDF (the refinement writes it under the band, UpsamplePass elsewhere), for shading
         ///< passes that sample it (fineBuffer()); memory grows with the grid's volume
  Sparse ///< the coarse SDF and the bricks only: memory grows with the band (surface area x band width)
};
template <> struct EnumNames<FineStorage> {
  static constexpr const char* kSetting = "fine storage";
  static constexpr std::pair<const char*, FineStorage> kValues[] = {{"dense", FineStorage::Dense},
                                                                    {"sparse", FineStorage::Sparse}};
};

/// @brief The most cascade levels: level 9's voxel is 512 times level 0's.
constexpr int kMaxCascades = 10;

/// @brief Every knob of the pipeline. The defaults are the fast and accurate point of the speed/accuracy tables
///        (docs/results.md, "Defaults"): closest-point refinement at coarse 64 / fine 128 with a band of 6 fine
///        voxels; pipelinePreset(Preset::Paper) gives the paper's. Lengths may be in voxels of the fine grid until
///        a job resolves them (withLengthsResolved); the pipeline itself works in scene units.
struct PipelineSettings {
  int coarseRes = 64;    ///< voxels across the scene for the coarse SDF
  int fineRes = 128;     ///< voxels across the scene for the fine SDF (>= coarseRes)
  Length band = Length::voxels(6); ///< d: refine where |c| <= d
  Length padding = -1.0; ///< margin around the scene bounds; < 0: defaultPadding (the band, at most a quarter)
  double alpha = 0.95;   ///< history decay
  int rays = 0;          ///< x: rays per masked voxel per frame (closest mode: sign rays)
  RefineMode mode = RefineMode::Closest;
  ClosestSearch closestSearch = ClosestSearch::Auto; ///< closest mode: one walk per box of voxels or per voxel
  ShaderTarget shaderTarget = ShaderTarget::Device; ///< the kind of device the shader variants are for
  CoarseMethod coarseMethod = CoarseMethod::Edt; ///< how the coarse SDF finds nearest seeds
  double beta = -1.0;    ///< coarse shell; < 0: half a coarse voxel
  std::uint32_t seed = 1;
  /// Refine every masked voxel every frame (the paper's frame, the anchor of incremental refinement). Default:
  /// incremental, a voxel is refined only when it is new to the mask, a moving instance came within reach of it
  /// (either pose within |f| of it), or it has not settled (see settleFrames); otherwise it keeps its value.
  bool fullRecompute = false;
  /// Run every pass of every frame over the whole grid (for measuring and as a fallback; implied by fullRecompute).
  /// Default: a frame runs only the passes whose inputs changed since they last ran (the coarse SDF when an instance
  /// moved, the mask while a band voxel is due a refinement, the upsampling where the coarse SDF changed); the
  /// results are the same bit for bit.
  bool fullRebuild = false;
  /// Incremental: refinements in a row after which a voxel is settled; < 0: by the mode (settleFramesFor).
  int settleFrames = -1;
  /// Incremental: a settled voxel is refined again once every this many frames (0: never, its value is kept);
  /// < 0: by the mode (refreshPeriodFor).
  int refreshPeriod = -1;
  FineStorage fineStorage = FineStorage::Dense; ///< a dense fine SDF for shading, or only the bricks
  /// The brick pool's capacity at the first frame; 0: sized by the first frame's band (poolBricksFor). A pool that
  /// overflows is regrown from the next frame on.
  std::int64_t poolBricks = 0;
  /// Camera-centred cascade levels (lib/sdf/cascade): 1 is one box fitted to the scene; K > 1 gives K boxes of these
  /// coarse and fine voxel counts around the camera, level i's voxels 2^i times level 0's (CascadeLayout).
  int cascades = 1;
  /// The side of cascade level 0 in scene units (cascades > 1); < 0: the outermost level, centred on the camera,
  /// holds the whole scene (cascadeShapeFor), level 0 being 2^(cascades - 1) times smaller.
  double cascadeExtent = -1.0;
  /// Cascade levels above 0 refine only the band near the camera's view (the paper's future work: outside the view a
  /// lower resolution): within this many of the level's coarse voxels of the cone that holds the image, the rest
  /// keeps the coarse SDF (ViewReach). < 0 (the default): every level refines its whole band. Off by default: a
  /// camera on a path gives every level a new view every frame, and writing the band out of view again then cost
  /// the towns' frames more than the walks it saved (docs/results.md, 2026-11-27).
  double cascadeViewMargin = -1.0;
  /// @throw SettingError naming the setting ("band", "coarse resolution", ...) when one is out of range.
  void validate() const;
};

/// @brief The pipeline's knobs, one row each (docs/settings.md is generated from it). shaderTarget is for tests
///        and has no row.
template <> struct KnobTable<PipelineSettings> {
  using S = PipelineSettings;
  static constexpr auto kKnobs = std::make_tuple(
      knob("coarse resolution", &S::coarseRes, "--coarse", KnobRange::closed(1, 1024),
           "Coarse SDF resolution: voxels across the scene (methods jfa, rtsdf)"),
      knob("fine resolution", &S::fineRes, "--fine", KnobRange::closed(1, 1024),
           "Fine SDF resolution: voxels across the scene (method rtsdf), at least the coarse resolution"),
      knob("band", &S::band, "-d,--band", KnobRange::atLeast(0),
           "Narrow-band half-width: refine where |coarse SDF| <= band, the level set's active voxels; at least one "
           "voxel (0: no refinement, method rtsdf) [d]"),
      knob("padding", &S::padding, "--padding",
           KnobRange::atLeast(0).orNegative("the band, at most a quarter of the scene's longest side"),
           "Margin around the scene bounds, at most the scene's longest side"),
      knob("rays", &S::rays, "--rays", KnobRange::closed(0, 1024),
           "Rays cast per masked fine voxel per frame (closest mode: rays that vote on the sign where the nearest "
           "triangle's side is in doubt) [x]"),
      knob("alpha", &S::alpha, "--alpha", KnobRange::closed(0, 1),
           "How much of its history a voxel keeps each frame in rays mode: the new distance is the smaller of the "
           "ray hit and alpha times the old one plus (1 - alpha) times the coarse one [alpha]"),
      enumKnob(&S::mode, "--refine", "rays: the paper's random rays; closest: exact closest-point distance"),
      enumKnob(&S::closestSearch, "--closest-search",
               "Closest mode: cell (one BVH walk per box of fine voxels collects the triangles they test), voxel "
               "(one walk per fine voxel) or auto (cell on a CPU device such as lavapipe, voxel on a GPU: the faster "
               "on each); the same distances"),
      enumKnob(&S::coarseMethod, "--coarse-method,--jfa",
               "How the coarse SDF finds each voxel's nearest seed: edt (exact separable transform) or the "
               "jump-flooding variants jfa, 1+jfa (the paper's) and jfa+2; --jfa is the older name"),
      knob("beta", &S::beta, "--beta", KnobRange::atLeast(0).orNegative("half a coarse voxel"),
           "Shell subtracted from the coarse distances, in scene units [beta]"),
      knob("seed", &S::seed, "--seed", KnobRange::any(), "Random seed of the ray directions"),
      flagKnob("full recompute", &S::fullRecompute, "--full-recompute",
               "Refine every masked voxel every frame (the paper's frame); default: only voxels new to the band, "
               "near a moving instance or not yet settled"),
      flagKnob("full rebuild", &S::fullRebuild, "--full-rebuild",
               "Run every pass of every frame over the whole grid (the same fields, for measuring and as a "
               "fallback); default: a frame runs only the passes whose inputs changed (none on a static scene once "
               "the band has settled)"),
      knob("settle frames", &S::settleFrames, "--settle-frames",
           KnobRange::closed(1, 1000000).orNegative("by the refinement mode: 1 closest with rays 0, 4 closest, 32 rays"),
           "Refinements in a row after which a voxel is settled and kept"),
      knob("refresh period", &S::refreshPeriod, "--refresh-period",
           KnobRange::closed(0, 1000000).orNegative("by the refinement mode: 0 closest, 8 rays"),
           "A settled voxel is refined again every this many frames, 0: never"),
      enumKnob(&S::fineStorage, "--fine-storage",
               "dense: the bricks under the band and a dense fine SDF resolved every frame (what shading samples); "
               "sparse: the bricks only (memory grows with the band, not the grid: size L on small devices)"),
      knob("pool bricks", &S::poolBricks, "", KnobRange::closed(0, 4294967296.0).noting("0: sized by the first frame's band"),
           "Capacity of the brick pool at the first frame, in bricks (regrown when it overflows)"),
      knob("cascades", &S::cascades, "--cascades", KnobRange::closed(1, kMaxCascades),
           "Camera-centred cascade levels, each of the coarse and fine voxel counts, level i's voxel 2^i times level "
           "0's; shading samples the finest level holding a point (1: one box fitted to the scene)"),
      knob("cascade extent", &S::cascadeExtent, "--cascade-extent",
           KnobRange::above(0).orNegative("the outermost level, around the camera, holds the scene"),
           "Side of cascade level 0 in scene units (cascades > 1)"),
      knob("cascade view margin", &S::cascadeViewMargin, "--cascade-view-margin",
           KnobRange::closed(0, 1e6).orNegative("every level refines its whole band"),
           "Cascade levels above 0 refine the band only within this many of their coarse voxels of the camera's "
           "view (the cone holding the image); elsewhere they keep the coarse SDF"));
};

/// @brief Named sets of settings.
enum class Preset {
  Default, ///< the defaults: fast on a CPU device and accurate (closest, coarse 64 / fine 128)
  Paper    ///< the paper's: rays mode, x = 10, alpha = 0.95, 1+JFA, coarse 128 / fine 256, 16 frames
};
template <> struct EnumNames<Preset> {
  static constexpr const char* kSetting = "preset";
  static constexpr std::pair<const char*, Preset> kValues[] = {{"default", Preset::Default}, {"paper", Preset::Paper}};
};

/// @brief The pipeline's settings of @a preset.
PipelineSettings pipelinePreset(Preset preset);

/// @brief The voxel size the lengths of @a s given in voxels are measured in: the fine grid's over @a bounds.
double fineVoxelSize(const Bounds& bounds, const PipelineSettings& s);

/// @brief @a s with every length in scene units: a length in voxels times @a voxelSize. Lengths already in scene
///        units are kept, so resolving twice changes nothing.
PipelineSettings withLengthsResolved(const PipelineSettings& s, double voxelSize);

/// @brief @a s with its lengths resolved against the fine grid over @a bounds (fineVoxelSize).
PipelineSettings withLengthsResolved(const PipelineSettings& s, const Bounds& bounds);

/// @brief A level set's band of at least one voxel of @a voxelSize (0 < band < 1 voxel would leave a level set
///        with no voxel inside its band).
/// @throw SettingError "band" saying the band in voxels and the least accepted.
void requireBandOfAVoxel(double band, double voxelSize);

/// @brief The refinements in a row after which a voxel is settled under @a s: 0 with fullRecompute (every voxel is
///        refined every frame); else s.settleFrames when > 0; else, by the mode, 1 in closest mode with no sign rays
///        (an exact, deterministic value: a second refinement would repeat it), 4 in closest mode with sign rays
///        (a few frames of votes), 32 in rays mode (its decayed history converges over frames).
int settleFramesFor(const PipelineSettings& s);

/// @brief How often a settled voxel is refined again under @a s: s.refreshPeriod when >= 0; else 0 (never) in
///        closest mode, whose settled values are exact, and 8 in rays mode, which keeps accumulating rays, slower.
int refreshPeriodFor(const PipelineSettings& s);

/// @brief The margin a grid keeps around @a bounds for a band of half-width @a band when none is given: the band,
///        so that it fits, but at most a quarter of the longest side, so that a band wider than the scene does not
///        blow the grid up.
double defaultPadding(const Bounds& bounds, double band);

/// @brief The padding @a s asks for: s.padding when >= 0, else defaultPadding(bounds, s.band).
/// @throw SettingError "padding" when s.padding exceeds the longest side of @a bounds.
double pipelinePadding(const Bounds& bounds, const PipelineSettings& s);

/// @brief A level set's band no longer than @a grid's diagonal (a longer one holds every voxel: ask for the full
///        domain). Not applied to the ray-mask band, where a band beyond the grid masks every voxel.
/// @throw SettingError "band" naming the largest band accepted.
void requireBandWithin(const GridSpec& grid, double band);

/// @brief A coarse shell beta no longer than @a coarse's diagonal (a longer one makes every voxel inside).
/// @throw SettingError "beta" naming the largest beta accepted and the default.
void requireBetaWithin(const GridSpec& coarse, double beta);

/// @brief The coarse grid over a fine grid: the same corner, the voxel size of GridSpec::fromBounds(@a bounds,
///        @a coarseRes, @a padding), and enough voxels to cover the fine grid.
GridSpec coarseGridOver(const GridSpec& fine, const Bounds& bounds, int coarseRes, double padding);

/// @brief Grids SdfPipeline can run on under @a s: beta within the coarse grid, at most 1024 fine voxels an axis.
/// @throw SettingError naming "beta" or "fine resolution".
void requirePipelineGrids(const GridSpec& coarse, const GridSpec& fine, const PipelineSettings& s);

/// @brief The coarse and fine grids SdfPipeline builds for @a bounds and @a s. The fine grid is
///        GridSpec::fromBounds(bounds, fineRes, pipelinePadding), the very voxels an exact or OpenVDB bake at
///        resolution fineRes uses, so their files compare voxel for voxel; the coarse grid lies over it.
/// @throw Error when the settings are out of range (PipelineSettings::validate) or the fine grid needs more
///        than 1024 voxels along an axis.
std::pair<GridSpec, GridSpec> pipelineGrids(const Bounds& bounds, const PipelineSettings& s);

} // namespace rtsdf
