#pragma once
/// @file Bake.h
/// @brief rtsdf's main job: the signed distance field of a scene as a sparse OpenVDB level set, by any of the
///        four methods (the exact reference, OpenVDB's meshToLevelSet, the GPU coarse SDF, the full RTSDF
///        pipeline), and its .vdb file.
#include "grid/VdbIO.h"
#include "reference/ExactSdf.h"
#include "scene/MeshIO.h"
#include "scene/Scene.h"
#include "sdf/SdfPipeline.h"
#include "util/EnumNames.h"
#include "util/JobControl.h"
#include "util/Knobs.h"
#include "util/PassTimes.h"

#include <openvdb/openvdb.h>

#include <filesystem>
#include <optional>
#include <string>

namespace rtsdf {

/// @brief The SDF builders a bake offers.
enum class BakeMethod {
  Exact,   ///< CPU exact reference (Embree closest points + robust sign)
  OpenVdb, ///< OpenVDB's meshToLevelSet
  Jfa,     ///< GPU coarse SDF: voxelization + nearest seeds by PipelineSettings::coarseMethod (the exact
           ///< transform by default, 3D jump flooding on request), distance minus beta
  Rtsdf    ///< the full pipeline: coarse SDF, OpenVDB ray mask, fine SDF refined through the GPU BVH
};
template <> struct EnumNames<BakeMethod> {
  static constexpr const char* kSetting = "bake method";
  static constexpr std::pair<const char*, BakeMethod> kValues[] = {{"exact", BakeMethod::Exact},
                                                                   {"openvdb", BakeMethod::OpenVdb},
                                                                   {"jfa", BakeMethod::Jfa},
                                                                   {"rtsdf", BakeMethod::Rtsdf}};
};

/// @brief Everything a bake needs. Lengths (the band, the padding) in scene units or in voxels of the output grid.
struct BakeOptions {
  std::string scene;                   ///< scene (.json) or mesh file; recorded in the file's metadata
  MeshLoadOptions meshLoad;            ///< whether the scene's mesh paths and meshes' references may leave their folder
  BakeMethod method = BakeMethod::Exact;
  int resolution = 128;                ///< voxels across the longest side (exact, openvdb; see setOutputResolution)
  bool fullDomain = false;             ///< every voxel active (exact only)
  double time = 0.0;                   ///< animation time in seconds
  SignMethod sign = SignMethod::Auto;  ///< sign rule of the exact method
  int frames = -1;                     ///< refinement frames to accumulate (rtsdf); < 0: bakeFrames()
  bool allowEmpty = false;             ///< a level set with no active voxel is a result, not an error
  std::string device;                  ///< Vulkan device by index or name; empty: the best one (jfa, rtsdf)
  /// The band d and the padding for every method (pipeline.band: active voxels |d| <= band; for rtsdf also the
  /// ray mask) and the GPU pipeline's knobs: coarse resolution (jfa, rtsdf), fine resolution, rays, alpha,
  /// refinement mode, jump-flooding variant, beta, seed (rtsdf). An exact or openvdb bake at resolution N and an
  /// rtsdf bake at fine resolution N with the same band and padding have the same voxels (pipelineGrids).
  PipelineSettings pipeline;
  /// exact, openvdb, jfa: bake on these voxels instead of the scene's padded bounds at the resolution (e.g. the
  /// voxels of another file, to compare with it voxel for voxel).
  std::optional<GridSpec> grid;
  /// @throw SettingError naming the setting that is out of range.
  void validate() const;
};

/// @brief Set the output grid of @a o.method to @a res voxels across the scene: the fine grid for rtsdf (the
///        coarse one at half of it), the coarse grid for jfa, the resolution for exact and openvdb.
void setOutputResolution(BakeOptions& o, int res);

/// @brief The voxels across the scene of @a o's output grid (the fine grid for rtsdf, the coarse for jfa).
int outputResolution(const BakeOptions& o);

/// @brief The refinement frames of an rtsdf bake: o.frames when > 0; else 1 in closest mode without sign rays (an
///        exact value settles in one refinement), 16 otherwise (votes and decayed history accumulate).
int bakeFrames(const BakeOptions& o);

/// @brief Whether @a method reads the setting named @a setting (SettingError::setting(), knob rows): a front
///        end refuses a setting given for a method that would ignore it. A setting not listed as one of some
///        methods only is read by every method (a new knob of the GPU pipeline alone must be listed here).
bool bakeMethodUses(BakeMethod method, const std::string& setting);

/// @brief @a o with its pipeline's lengths in scene units, voxels measured on the output grid over @a bounds (or
///        o.grid's voxels), and its frames chosen (bakeFrames).
/// @throw SettingError "band" when the band is under one voxel of the output grid (requireBandOfAVoxel).
BakeOptions bakeOptionsResolved(const BakeOptions& o, const Bounds& bounds);

/// @brief A finished bake.
struct BakeResult {
  openvdb::FloatGrid::Ptr grid;   ///< the level set "surface", rtsdf:* metadata stamped
  GridSpec spec;                  ///< its voxels (the fine grid for rtsdf)
  GridSpec coarseSpec;            ///< the coarse grid (rtsdf)
  double seconds = 0.0;           ///< the build's wall time (loading and writing excluded)
  ExactSdfStats exact;            ///< counters of the exact method
  FrameStats lastFrame;           ///< the last frame's mask and pass times (jfa: passes only; rtsdf)
  /// rtsdf: refinements of a fine voxel that a CPU device's loop budget ended (FrameStats::cutVoxels), summed over
  /// the frames and cascade levels; each kept an upper bound of its distance. 0 on a GPU.
  std::uint64_t cutVoxels = 0;
  std::string device;             ///< the Vulkan device that ran (jfa, rtsdf)
  std::string sceneSummary;       ///< meshes, instances, triangles, dropped triangles
  std::vector<std::filesystem::path> inputs; ///< the scene and mesh files read (an output never replaces one)
  /// Cascades (pipeline.cascades > 1, CascadeBake.h): one level set per level, finest first, named
  /// cascadeGridName(level); grid is level 0. writeBake writes these instead of grid.
  std::vector<openvdb::FloatGrid::Ptr> levels;
  std::vector<FrameStats> levelFrames; ///< cascades: each level's last frame
  BakeOptions options;            ///< the options in effect (bakeOptionsResolved: lengths in scene units)
};

/// @brief A bake's own knobs (the pipeline's: KnobTable<PipelineSettings>); docs/settings.md.
template <> struct KnobTable<BakeOptions> {
  using S = BakeOptions;
  static constexpr auto kKnobs = std::make_tuple(
      enumKnob(&S::method, "-m,--method",
               "exact: CPU exact reference; openvdb: OpenVDB's meshToLevelSet; jfa: GPU coarse SDF (voxelization, "
               "nearest seeds by the coarse method, distance minus beta); rtsdf: coarse SDF, ray mask compacted on "
               "the GPU and fine SDF refined through the GPU BVH"),
      knob("resolution", &S::resolution, "-r,--res", KnobRange::closed(1, GridSpec::kMaxResolution),
           "Voxels of the output grid along the scene's longest axis, other axes following (rtsdf: the fine grid, "
           "the coarse at half of it; jfa: the coarse grid; --coarse and --fine override)"),
      flagKnob("full domain", &S::fullDomain, "--full", "Full-domain field: every voxel active (exact method only)",
               "full_domain"),
      knob("time", &S::time, "-t,--time", KnobRange::finite(), "Animation time in seconds"),
      enumKnob(&S::sign, "--sign",
               "Sign rule of the exact method: auto (pseudo-normal for closed meshes, winding number for open ones), "
               "pseudonormal, winding"),
      knob("frames", &S::frames, "--frames",
           KnobRange::closed(1, 100000).orNegative("by the refinement mode: 1 closest without rays, 16 otherwise"),
           "Frames of refinement to accumulate (method rtsdf)"),
      flagKnob("allow empty", &S::allowEmpty, "--allow-empty",
               "Write the level set even when no voxel is active (else an error)"),
      knob("device", &S::device, "--device", KnobRange::any(), "Vulkan device by index or name (see 'rtsdf info')"));
};

/// @brief Bake the SDF of @a options.scene.
/// @throw SettingError on a setting out of range, Error on bad input (the file and the problem), a missing
///        Vulkan device, a grid too large for memory, a Vulkan validation error or a level set with no active
///        voxel (unless options.allowEmpty); Interrupted when @a control
///        asks to stop between refinement frames.
BakeResult bake(const BakeOptions& options, const JobControl& control = {});

/// @brief Bake a scene already in memory (options.scene only names it in the file's metadata).
/// @throw As bake(options, control), but for the scene's own file.
BakeResult bake(const Scene& scene, const BakeOptions& options, const JobControl& control = {});

/// @brief How a bake is written.
struct BakeOutputOptions {
  bool fog = false;      ///< also a "density" fog grid, which Blender displays directly
  VdbWriteOptions vdb;   ///< compression, half floats
};

/// @brief Write @a result to @a path atomically (nothing is left behind on failure).
/// @throw Error when @a path is not a .vdb name, is one of result.inputs, or cannot be written.
void writeBake(const BakeResult& result, const std::filesystem::path& path, const BakeOutputOptions& output = {});

/// @brief What a bake did, as the lines `rtsdf bake` prints (scene, method, grid, band, activity, time, output).
std::string bakeReport(const BakeOptions& options, const BakeResult& result, const std::filesystem::path& output,
                       const BakeOutputOptions& written = {});

/// @brief The level-set band of the fine SDF the RTSDF pipeline writes: d, or three fine voxels when d = 0 (so
///        the file is still a valid level set).
double fineLevelSetBand(const PipelineSettings& settings, const GridSpec& fine);

/// @brief The pipeline's fine SDF after its last frame as a level set stamped with @a options (rtsdf metadata)
///        and the moment @a time.
openvdb::FloatGrid::Ptr fineLevelSet(const SdfPipeline& pipeline, const BakeOptions& options, double time);

} // namespace rtsdf
