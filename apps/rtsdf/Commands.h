#pragma once
/// @file Commands.h
/// @brief The rtsdf subcommands: settings structs filled by CLI11 and the functions that run them.
#include "reference/ExactSdf.h"
#include "sdf/SdfPipeline.h"

#include <string>
#include <vector>

namespace rtsdf::app {

/// @brief The SDF builders `bake` offers.
enum class BakeMethod {
  Exact,   ///< CPU exact reference (Embree closest points + robust sign)
  OpenVdb, ///< OpenVDB's meshToLevelSet
  Jfa,     ///< GPU coarse SDF: voxelization + 3D jump flooding (distance minus beta)
  Rtsdf    ///< the full pipeline: coarse SDF, OpenVDB ray mask, fine SDF refined through the GPU BVH
};

struct BakeSettings {
  std::string scene;
  std::string output;
  std::string method = "exact";
  int resolution = 128;
  double band = 0.1;
  bool fullDomain = false;
  double padding = -1.0; ///< < 0: the band (so the band fits inside the grid)
  double time = 0.0;
  std::string sign = "auto";
  bool fog = false;
  bool halfFloat = false;
  std::string compression = "blosc";
  int coarse = 128;            ///< resolution of --method jfa
  std::string jfaVariant = "1+jfa";
  double beta = -1.0;          ///< < 0: half a coarse voxel
  std::string device;          ///< Vulkan device by index or name; empty: the best one
  int fine = 256;              ///< fine resolution of --method rtsdf
  int rays = 10;               ///< x
  double alpha = 0.95;
  int frames = 16;
  std::string refine = "rays";
  std::uint32_t seed = 1;
};

struct AnimateSettings {
  std::string scene;
  int frames = 60;
  double fps = 30.0;
  std::string csv;             ///< per-frame statistics (CSV); empty: stdout only
  std::string vdbDir;          ///< per-frame .vdb files; empty: none
  bool error = true;           ///< measure each frame against the exact field of the same moment
  std::string focus;           ///< measure only in the box an instance sweeps over the animation (ghosting)
  BakeSettings pipeline;       ///< coarse, fine, band, alpha, rays, refine, jfa, beta, seed, device
};

/// @brief The pipeline settings a bake or animate command asked for.
PipelineSettings pipelineSettings(const BakeSettings& s);

struct CompareSettings {
  std::string a, b;
};

struct BenchSettings {
  std::vector<std::string> scenes;
  std::vector<int> resolutions{128, 256};
  double bandFraction = 0.05;
  int repeats = 3;
  std::string output;
  std::string suite = "reference"; ///< reference: exact vs OpenVDB; coarse: GPU coarse-SDF passes vs CPU
  std::string device;
  std::string sweep;               ///< quick, default or paper: the speed/accuracy sweep (empty: a suite)
  std::string outDir;              ///< the sweep's folder (CSV, report, plots); empty: sweep-<scene>
  double errorBand = 0.1;          ///< the sweep's field error is measured where |exact| <= errorBand
  bool shadows = true;             ///< the sweep also measures the shadow image error (scenes with a camera)
  int truthSamples = 256;
  std::string command;             ///< the command line, for the report
};

struct RenderCommandSettings {
  std::string scene;
  std::string output;          ///< .exr
  std::string png;             ///< empty: the output with .png
  std::string shadows = "sdf";
  int width = 640, height = 360;
  int frames = 8;              ///< frames rendered (TAA and SDF accumulation); the last is written
  double fps = 30.0;
  double time = 0.0;           ///< time of the last frame
  std::string penumbra = "centered";
  std::string sdfSampling = "texture";
  double epsilon = 1.0, bias = 0.15, minStep = 0.5, maxStep = 0.05, normalOffset = -1.0;
  int maxSteps = 256;
  bool jitter = true;
  int shadowMapRes = 1024, pcfRadius = 2;
  double shadowBias = 1.5;
  bool taa = true;
  double taaBlend = 0.1;
  int samples = 256;
  bool compare = false;        ///< also ray trace the truth and report the image error
  BakeSettings pipeline;       ///< coarse, fine, band, alpha, rays, refine, jfa, beta, seed, device
};

int runBake(const BakeSettings& s);
int runRender(const RenderCommandSettings& s);
int runInfo();
int runCompare(const CompareSettings& s);
int runBench(const BenchSettings& s);
/// @brief `rtsdf bench --sweep`: every point of the preset on one scene; CSV rows as points finish, then the
///        Markdown report and the plots. Ctrl-C stops after the current frame and keeps what finished.
/// @return 0, or 130 when interrupted (the report then covers the finished points).
int runSweep(const BenchSettings& s);
int runAnimate(const AnimateSettings& s);

/// @brief The CPU's model name (from /proc/cpuinfo), for benchmark reports.
std::string cpuName();

/// @brief Fail early (before any work) when @a path cannot be written: missing folder or a directory.
void checkOutputPath(const std::string& path);

} // namespace rtsdf::app
