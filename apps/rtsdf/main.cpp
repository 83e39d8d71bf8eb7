// rtsdf: real-time signed distance fields of triangle-mesh scenes.
#include "Commands.h"
#include "util/Error.h"
#include "util/Log.h"
#include "util/Progress.h"

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <exception>

namespace {

/// The GPU pipeline's knobs, shared by bake and animate.
void addPipelineOptions(CLI::App* cmd, rtsdf::app::BakeSettings& s) {
  cmd->add_option("--coarse", s.coarse, "Coarse SDF resolution: voxels across the scene (methods jfa, rtsdf)")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  cmd->add_option("--fine", s.fine, "Fine SDF resolution (method rtsdf), at least --coarse")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  cmd->add_option("--rays", s.rays, "Rays per masked fine voxel per frame (x)")->check(CLI::Range(0, 1024))->capture_default_str();
  cmd->add_option("--alpha", s.alpha, "History decay: f = min(alpha f' + (1 - alpha) c, r)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--refine", s.refine, "rays: the paper's random rays; closest: exact closest-point distance")
      ->check(CLI::IsMember({"rays", "closest"}))
      ->capture_default_str();
  cmd->add_option("--seed", s.seed, "Random seed of the ray directions")->capture_default_str();
  cmd->add_option("--jfa", s.jfaVariant, "Jump-flooding variant: jfa, 1+jfa or jfa+2")
      ->check(CLI::IsMember({"jfa", "1+jfa", "jfa+2"}))
      ->capture_default_str();
  cmd->add_option("--beta", s.beta, "Coarse SDF shell: distance minus beta, in scene units (default: half a coarse voxel)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--device", s.device, "Vulkan device by index or name (see 'rtsdf info')");
}

} // namespace

int main(int argc, char** argv) {
  using namespace rtsdf::app;
  CLI::App app{"rtsdf: signed distance fields of triangle-mesh scenes (OpenVDB export, GPU jump flooding and ray "
               "refinement, soft shadows)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("rtsdf ") + RTSDF_VERSION);
  int verbosity = 0;
  bool quiet = false;
  app.add_flag("-v,--verbose", verbosity, "More log output (repeat for trace)");
  app.add_flag("-q,--quiet", quiet, "Only warnings and errors; no progress bar");

  BakeSettings bake;
  CLI::App* bakeCmd = app.add_subcommand("bake", "Build the signed distance field of a scene and write it as a .vdb");
  bakeCmd->add_option("scene", bake.scene, "Scene (.json) or mesh file (.obj, .ply, .stl, .gltf, ...)")->required();
  bakeCmd->add_option("-o,--output", bake.output, "Output .vdb file (written atomically)")->required();
  bakeCmd->add_option("-m,--method", bake.method,
                      "exact: CPU exact reference; openvdb: OpenVDB's meshToLevelSet; jfa: GPU coarse SDF "
                      "(voxelization + jump flooding, distance minus beta); rtsdf: coarse SDF, OpenVDB ray mask and "
                      "fine SDF refined through the GPU BVH")
      ->check(CLI::IsMember({"exact", "openvdb", "jfa", "rtsdf"}))
      ->capture_default_str();
  bakeCmd->add_option("-r,--res", bake.resolution, "Voxels along the scene's longest axis (other axes follow)")
      ->check(CLI::Range(1, 8192))
      ->capture_default_str();
  bakeCmd->add_option("-d,--band", bake.band,
                      "Narrow-band half-width in scene units (active voxels: |d| <= band); for rtsdf the ray-mask "
                      "band d (0: no refinement)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  bakeCmd->add_flag("--full", bake.fullDomain, "Full-domain field: every voxel active (exact method only)");
  bakeCmd->add_option("--padding", bake.padding, "Margin around the scene bounds in scene units (default: the band)")
      ->check(CLI::NonNegativeNumber);
  bakeCmd->add_option("-t,--time", bake.time, "Animation time in seconds")->capture_default_str();
  bakeCmd->add_option("--sign", bake.sign,
                      "Sign rule of the exact method: auto (pseudo-normal for closed meshes, winding number for "
                      "open ones), pseudonormal, winding")
      ->check(CLI::IsMember({"auto", "pseudonormal", "winding"}))
      ->capture_default_str();
  addPipelineOptions(bakeCmd, bake);
  bakeCmd->add_option("--frames", bake.frames, "Frames of refinement to accumulate (method rtsdf)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  bakeCmd->add_flag("--fog", bake.fog, "Also write a 'density' fog grid so Blender shows the volume");
  bakeCmd->add_flag("--half", bake.halfFloat, "Store values as 16-bit halves");
  bakeCmd->add_option("--compression", bake.compression, "blosc, zip or none")
      ->check(CLI::IsMember({"blosc", "zip", "none"}))
      ->capture_default_str();

  AnimateSettings anim;
  CLI::App* animCmd = app.add_subcommand(
      "animate", "Run the RTSDF pipeline over an animation: per-frame mask size, pass times and error against the "
                 "exact field of the same moment (ghosting), optionally per-frame .vdb files");
  animCmd->add_option("scene", anim.scene, "Scene (.json) or mesh file")->required();
  animCmd->add_option("--frames", anim.frames, "Frames to run")->check(CLI::Range(1, 100000))->capture_default_str();
  animCmd->add_option("--fps", anim.fps, "Frames per second of scene time")->check(CLI::PositiveNumber)->capture_default_str();
  animCmd->add_option("--csv", anim.csv, "Write per-frame statistics to this CSV file");
  animCmd->add_option("--vdb-dir", anim.vdbDir, "Write frameNNNN.vdb files (fine SDF band) into this folder");
  animCmd->add_flag("!--no-error", anim.error, "Skip the per-frame comparison with the exact field");
  animCmd->add_option("--focus", anim.focus,
                      "Measure the error only in the box this instance sweeps (e.g. teapot: ghosting behind it)");
  animCmd->add_option("-d,--band", anim.pipeline.band, "Band d in scene units")->check(CLI::NonNegativeNumber)->capture_default_str();
  anim.pipeline.fine = 128;
  anim.pipeline.coarse = 64;
  addPipelineOptions(animCmd, anim.pipeline);

  RenderCommandSettings render;
  CLI::App* renderCmd = app.add_subcommand(
      "render", "Render the scene camera's view with soft shadows (SDF sphere tracing, shadow maps or ray-traced "
                "truth) to a linear EXR (R, G, B and each light's visibility) and an sRGB PNG");
  renderCmd->add_option("scene", render.scene, "Scene (.json) with a camera and lights")->required();
  renderCmd->add_option("-o,--output", render.output, "Output .exr (written atomically)")->required();
  renderCmd->add_option("--png", render.png, "Output .png (default: the .exr's name with .png)");
  renderCmd->add_option("--shadows", render.shadows,
                        "sdf: sphere tracing of the RTSDF fine SDF; shadowmap: depth maps with PCF; raytraced: "
                        "distributed ray tracing on the CPU (the truth)")
      ->check(CLI::IsMember({"sdf", "shadowmap", "raytraced"}))
      ->capture_default_str();
  renderCmd->add_option("--width", render.width, "Image width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  renderCmd->add_option("--height", render.height, "Image height in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  renderCmd->add_option("--frames", render.frames, "Frames rendered (SDF refinement and TAA accumulate); the last one is written")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  renderCmd->add_option("--fps", render.fps, "Frames per second of scene time")->check(CLI::PositiveNumber)->capture_default_str();
  renderCmd->add_option("-t,--time", render.time, "Scene time of the written frame in seconds")->capture_default_str();
  renderCmd->add_option("--penumbra", render.penumbra,
                        "SDF penumbra estimate: classic (k h / t), improved (triangulated between samples), centered "
                        "(marches through occluders: penumbra centred on the shadow boundary)")
      ->check(CLI::IsMember({"classic", "improved", "centered"}))
      ->capture_default_str();
  renderCmd->add_option("--sdf-sampling", render.sdfSampling,
                        "How the SDF march reads the fine SDF: texture (a 3D texture, hardware trilinear filtering, "
                        "one fetch per step) or buffer (filtered in the shader like the CPU reference, eight fetches)")
      ->check(CLI::IsMember({"texture", "buffer"}))
      ->capture_default_str();
  renderCmd->add_option("--epsilon", render.epsilon, "SDF hit threshold and march start in fine voxels (>= 1)")
      ->check(CLI::Range(1.0, 64.0))
      ->capture_default_str();
  renderCmd->add_option("--bias", render.bias,
                        "Subtracted from SDF samples, in fine voxels: against leaks through thin surfaces and the "
                        "filtered field's overestimate at convex edges")
      ->check(CLI::Range(0.0, 64.0))
      ->capture_default_str();
  renderCmd->add_option("--min-step", render.minStep,
                        "Shortest SDF march step in fine voxels: how densely the march samples near occluders")
      ->check(CLI::Range(0.05, 64.0))
      ->capture_default_str();
  renderCmd->add_option("--max-step", render.maxStep, "Longest SDF march step, against banding (scene units)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  renderCmd->add_option("--max-steps", render.maxSteps, "SDF march steps at most")->check(CLI::Range(1, 4096))->capture_default_str();
  renderCmd->add_option("--normal-offset", render.normalOffset,
                        "SDF march start off the surface along its normal (scene units; default: the bias)")
      ->check(CLI::NonNegativeNumber);
  renderCmd->add_flag("!--no-jitter", render.jitter, "Do not jitter the SDF march's start per pixel and frame");
  renderCmd->add_option("--shadow-map-res", render.shadowMapRes, "Shadow map texels per side (per cube face)")
      ->check(CLI::Range(1, 8192))
      ->capture_default_str();
  renderCmd->add_option("--pcf-radius", render.pcfRadius, "PCF kernel radius in texels")->check(CLI::Range(0, 16))->capture_default_str();
  renderCmd->add_option("--shadow-bias", render.shadowBias, "Shadow map depth bias in texels")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  renderCmd->add_flag("!--no-taa", render.taa, "Turn temporal accumulation off");
  renderCmd->add_option("--taa-blend", render.taaBlend, "TAA weight of the newest frame")
      ->check(CLI::Range(1e-6, 1.0))
      ->capture_default_str();
  renderCmd->add_option("--samples", render.samples, "Ray-traced shadows: samples per pixel and light")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  renderCmd->add_flag("--compare", render.compare,
                      "Also ray trace the truth and print the visibility RMSE and FLIP of the picture");
  // Fine 256 (the paper's size M): the default scene's sun penumbrae are only a few voxels wide at 128.
  render.pipeline.coarse = 64;
  render.pipeline.fine = 256;
  render.pipeline.band = 0.1;
  render.pipeline.refine = "closest";
  render.pipeline.rays = 0; // closest points signed by the closest triangle: decayed ray votes lag behind moving objects
  renderCmd->add_option("-d,--band", render.pipeline.band, "SDF ray-mask band d in scene units")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  addPipelineOptions(renderCmd, render.pipeline);

  app.add_subcommand("info", "Print versions, Vulkan devices with their limits, and embedded shaders");

  CompareSettings cmp;
  CLI::App* cmpCmd = app.add_subcommand(
      "compare", "Compare two level-set .vdb files on the voxels active in both: mean/RMS/max |difference| in voxels "
                 "and the rate of sign disagreement");
  cmpCmd->add_option("a", cmp.a, "First .vdb")->required()->check(CLI::ExistingFile);
  cmpCmd->add_option("b", cmp.b, "Second .vdb")->required()->check(CLI::ExistingFile);

  BenchSettings bench;
  CLI::App* benchCmd = app.add_subcommand(
      "bench", "Time rtsdf's builders against their anchors in one run and write a Markdown table with ratios");
  benchCmd->add_option("scenes", bench.scenes, "Scenes or meshes (default: data/scenes/default.json and the bunny)");
  benchCmd->add_option("--res", bench.resolutions, "Resolutions (voxels along the longest axis)")
      ->check(CLI::Range(1, 8192))
      ->capture_default_str();
  benchCmd->add_option("--band-fraction", bench.bandFraction, "Band half-width as a fraction of the scene's extent")
      ->check(CLI::Range(1e-6, 10.0))
      ->capture_default_str();
  benchCmd->add_option("--repeats", bench.repeats,
                       "Timed runs per point, the median is reported (--sweep: timed frames after a warm-up frame, "
                       "and runs of each anchor)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  benchCmd->add_option("-o,--output", bench.output, "Also write the Markdown report to this file");
  benchCmd->add_option("--suite", bench.suite,
                       "reference: exact SDF vs OpenVDB meshToLevelSet; coarse: GPU voxelize + jump flooding per "
                       "pass vs CPU jump flooding, exact EDT and OpenVDB meshToSignedDistanceField; refine: the paper's "
                       "ray-trace tables (sizes x rays, band x rays) with errors, vs OpenVDB meshToLevelSet; render: per-pass "
                       "times of SDF shadows and shadow maps at 640x360 and 1280x720 with their image error against "
                       "the ray-traced truth, and the ray tracer's time per sample count (PNGs beside --output)")
      ->check(CLI::IsMember({"reference", "coarse", "refine", "render"}))
      ->capture_default_str();
  benchCmd->add_option("--device", bench.device, "Vulkan device by index or name (GPU suites and --sweep)");
  benchCmd->add_option("--sweep", bench.sweep,
                       "Run the speed/accuracy sweep on one scene instead of a suite: quick (tiny grids, a minute), "
                       "default (sizes S 64/128 and M 128/256, every knob at S), paper (S, M, L 256/512, every knob "
                       "at M: for a real GPU). Writes sweep.csv (row by row), report.md and PNG plots into --out")
      ->check(CLI::IsMember({"quick", "default", "paper"}));
  benchCmd->add_option("--out", bench.outDir, "The sweep's output folder (created; default: sweep-<scene name>)");
  benchCmd->add_option("--error-band", bench.errorBand,
                       "The sweep measures the field error where |exact| <= this (scene units)")
      ->check(CLI::Range(1e-9, 1e9))
      ->capture_default_str();
  benchCmd->add_flag("!--no-shadows", bench.shadows, "The sweep skips the shadow image error");
  benchCmd->add_option("--truth-samples", bench.truthSamples,
                       "Samples per pixel of the sweep's ray-traced shadow truth")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  rtsdf::initLogging(quiet ? -1 : verbosity);
  rtsdf::Progress::setEnabled(!quiet);
  try {
    if (*bakeCmd) return runBake(bake);
    if (app.got_subcommand("info")) return runInfo();
    if (*cmpCmd) return runCompare(cmp);
    if (*benchCmd) {
      for (int i = 0; i < argc; ++i) bench.command += (i ? " " : "") + std::string(i ? argv[i] : "rtsdf");
      return bench.sweep.empty() ? runBench(bench) : runSweep(bench);
    }
    if (*animCmd) return runAnimate(anim);
    if (*renderCmd) return runRender(render);
  } catch (const rtsdf::Error& e) {
    spdlog::error("{}", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    spdlog::error("out of memory (try a lower --res or a narrower --band)");
    return 1;
  } catch (const std::exception& e) {
    spdlog::error("unexpected failure: {}", e.what());
    return 1;
  }
  return 0;
}
