#include "Options.h"

#include "util/EnumNames.h"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <optional>

namespace rtsdf::app {
namespace {

/// The number in @a text, or nothing when it is not one (trailing characters included).
std::optional<double> number(const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE) return std::nullopt;
  return v;
}

/// A numeric check whose message says the range in plain numbers (CLI11's own prints the largest double in full).
CLI::Validator numberCheck(std::function<bool(double)> ok, const std::string& range) {
  return CLI::Validator(
      [ok = std::move(ok), range](std::string& text) -> std::string {
        const std::optional<double> v = number(text);
        if (!v) return "'" + text + "' is not a number (or is beyond the range of a double)";
        if (!ok(*v)) return text + " is out of range: it must be " + range;
        return {};
      },
      range, range);
}
CLI::Validator inRange(double lo, double hi) {
  return numberCheck([lo, hi](double v) { return v >= lo && v <= hi; }, fmt::format("in [{:g}, {:g}]", lo, hi));
}
CLI::Validator atLeast(double lo) {
  return numberCheck([lo](double v) { return v >= lo && std::isfinite(v); }, fmt::format(">= {:g}", lo));
}
CLI::Validator positive() {
  return numberCheck([](double v) { return v > 0.0 && std::isfinite(v); }, "> 0");
}

/// An enum option: its choices come from the enum's name table (names only), its default is printed by name.
template <class E> CLI::Option* addEnum(CLI::App* cmd, const std::string& flag, E& value, const std::string& help) {
  const CLI::Validator byName(
      [](std::string& text) -> std::string {
        for (const auto& [name, v] : EnumNames<E>::kValues)
          if (text == name) {
            text = std::to_string(static_cast<int>(v));
            return {};
          }
        return "'" + text + "' is not one of " + enumChoices<E>();
      },
      "", "enum name");
  std::string names;
  for (const auto& entry : EnumNames<E>::kValues) names += std::string(names.empty() ? "" : "|") + entry.first;
  return cmd->add_option(flag, value, help)
      ->transform(byName)
      ->type_name("{" + names + "}")
      ->default_str(toString(value));
}

/// The GPU pipeline's knobs, shared by bake, animate and render.
void bindPipeline(CLI::App* cmd, PipelineSettings& p, std::string& device) {
  cmd->add_option("--coarse", p.coarseRes, "Coarse SDF resolution: voxels across the scene (methods jfa, rtsdf)")
      ->check(inRange(1, 1024))->capture_default_str();
  cmd->add_option("--fine", p.fineRes, "Fine SDF resolution (method rtsdf), at least --coarse")
      ->check(inRange(1, 1024))->capture_default_str();
  cmd->add_option("--rays", p.rays, "Rays per masked fine voxel per frame (x)")->check(inRange(0, 1024))
      ->capture_default_str();
  cmd->add_option("--alpha", p.alpha, "History decay: f = min(alpha f' + (1 - alpha) c, r)")
      ->check(inRange(0.0, 1.0))->capture_default_str();
  addEnum(cmd, "--refine", p.mode, "rays: the paper's random rays; closest: exact closest-point distance");
  addEnum(cmd, "--closest-search", p.closestSearch,
          "Closest mode: cell (one BVH walk per box of fine voxels collects the triangles they test), voxel (one "
          "walk per fine voxel) or auto (cell on a CPU device such as lavapipe, voxel on a GPU: the faster on each); "
          "the same distances");
  cmd->add_option("--seed", p.seed, "Random seed of the ray directions")->capture_default_str();
  addEnum(cmd, "--coarse-method,--jfa", p.coarseMethod,
          "How the coarse SDF finds each voxel's nearest seed: edt (exact separable transform, the default) or the "
          "jump-flooding variants jfa, 1+jfa (the paper's) and jfa+2; --jfa is the older name");
  cmd->add_option("--beta", p.beta, "Coarse SDF shell: distance minus beta, in scene units (default: half a coarse "
                                    "voxel)")->check(atLeast(0.0));
  cmd->add_flag("--full-recompute", p.fullRecompute, "Refine every masked voxel every frame (the paper's frame); "
                                                      "default: only voxels new to the band, near a moving instance "
                                                      "or not yet settled");
  cmd->add_option("--settle-frames", p.settleFrames, "Refinements in a row after which a voxel is settled and kept "
                                                     "(default: 1 closest with --rays 0, 4 closest, 32 rays)")
      ->check(inRange(1, 1000000));
  cmd->add_option("--refresh-period", p.refreshPeriod, "A settled voxel is refined again every this many frames, 0: "
                                                       "never (default: 0 closest, 8 rays)")
      ->check(inRange(0, 1000000));
  cmd->add_option("--device", device, "Vulkan device by index or name (see 'rtsdf info')");
}

/// Where the fine SDF lives (bake and animate: they read it back; render's shading samples it densely).
void bindFineStorage(CLI::App* cmd, FineStorage& f) {
  addEnum(cmd, "--fine-storage", f, "dense: the bricks under the band and a dense fine SDF resolved every frame (what "
                                    "shading samples); sparse: the bricks only (memory grows with the band, not the "
                                    "grid: size L on small devices)");
}

void bindBake(CLI::App& app, BakeCommand& c) {
  BakeOptions& o = c.options;
  CLI::App* cmd = app.add_subcommand("bake", "Build the signed distance field of a scene and write it as a .vdb");
  cmd->add_option("scene", o.scene, "Scene (.json) or mesh file (.obj, .ply, .stl, .gltf, ...)")->required();
  cmd->add_option("-o,--output", c.output, "Output .vdb file (written atomically)")->required();
  addEnum(cmd, "-m,--method", o.method,
          "exact: CPU exact reference; openvdb: OpenVDB's meshToLevelSet; jfa: GPU coarse SDF (voxelization, nearest "
          "seeds by --coarse-method: the exact transform by default, or jump flooding; distance minus beta); rtsdf: coarse SDF, ray mask compacted on the GPU and fine SDF refined through the GPU "
          "BVH");
  cmd->add_option("-r,--res", o.resolution, "Voxels along the scene's longest axis (other axes follow)")
      ->check(inRange(1, 8192))->capture_default_str();
  cmd->add_option("-d,--band", o.pipeline.band, "Narrow-band half-width in scene units (active voxels: |d| <= band); "
                                                "for rtsdf the ray-mask band d (0: no refinement)")
      ->check(atLeast(0.0))->capture_default_str();
  cmd->add_flag("--full", o.fullDomain, "Full-domain field: every voxel active (exact method only)");
  cmd->add_option("--padding", o.pipeline.padding, "Margin around the scene bounds in scene units, at most the "
                                                   "scene's longest side (default: the band, at most a quarter of "
                                                   "that side)")
      ->check(atLeast(0.0));
  cmd->add_option("-t,--time", o.time, "Animation time in seconds")->capture_default_str();
  addEnum(cmd, "--sign", o.sign, "Sign rule of the exact method: auto (pseudo-normal for closed meshes, winding "
                                 "number for open ones), pseudonormal, winding");
  bindPipeline(cmd, o.pipeline, o.device);
  bindFineStorage(cmd, o.pipeline.fineStorage);
  cmd->add_option("--frames", o.frames, "Frames of refinement to accumulate (method rtsdf)")
      ->check(inRange(1, 100000))->capture_default_str();
  cmd->add_flag("--allow-empty", o.allowEmpty, "Write the level set even when no voxel is active (else an error)");
  cmd->add_flag("--fog", c.written.fog, "Also write a 'density' fog grid so Blender shows the volume");
  cmd->add_flag("--half", c.written.vdb.halfFloat, "Store values as 16-bit halves");
  addEnum(cmd, "--compression", c.written.vdb.compression, "blosc, zip or none");
}

void bindAnimate(CLI::App& app, AnimateCommand& c) {
  AnimateOptions& o = c.options;
  CLI::App* cmd = app.add_subcommand(
      "animate", "Run the RTSDF pipeline over an animation: per-frame mask size, pass times and error against the "
                 "exact field of the same moment (ghosting), optionally per-frame .vdb files");
  cmd->add_option("scene", o.scene, "Scene (.json) or mesh file")->required();
  cmd->add_option("--frames", o.frames, "Frames to run")->check(inRange(1, 100000))->capture_default_str();
  cmd->add_option("--fps", o.fps, "Frames per second of scene time")->check(positive())->capture_default_str();
  cmd->add_option("--csv", c.csv, "Write per-frame statistics to this CSV file");
  cmd->add_option("--vdb-dir", o.vdbDir, "Write frameNNNN.vdb files (fine SDF band) into this folder");
  cmd->add_flag("!--no-error", o.measureError, "Skip the per-frame comparison with the exact field");
  cmd->add_option("--focus", o.focus,
                  "Measure the error only in the box this instance sweeps (e.g. teapot: ghosting behind it)");
  cmd->add_option("-d,--band", o.pipeline.band, "Band d in scene units")->check(atLeast(0.0))
      ->capture_default_str();
  bindPipeline(cmd, o.pipeline, o.device);
  bindFineStorage(cmd, o.pipeline.fineStorage);
}

void bindSdfShadows(CLI::App* cmd, SdfShadowSettings& s) {
  addEnum(cmd, "--penumbra", s.penumbra, "SDF penumbra estimate: classic (k h / t), improved (triangulated between "
                                         "samples), centered (marches through occluders: penumbra centred on the "
                                         "shadow boundary), umbra (--light-samples centered marches towards "
                                         "jittered points of the light, averaged: the SDF-simulated umbra)");
  addEnum(cmd, "--sdf-sampling", s.sampling, "How the SDF march reads the fine SDF: texture (a 3D texture, hardware "
                                             "trilinear filtering, one fetch per step), buffer (filtered in the "
                                             "shader like the CPU reference, eight fetches) or bricks (no dense "
                                             "fine SDF: the brick pool and the coarse SDF, eight fetches)");
  cmd->add_option("--epsilon", s.epsilonVoxels, "SDF hit threshold and march start in fine voxels (>= 1)")
      ->check(inRange(1.0, 64.0))->capture_default_str();
  cmd->add_option("--bias", s.biasVoxels, "Subtracted from SDF samples, in fine voxels: against leaks through thin "
                                          "surfaces and the filtered field's overestimate at convex edges")
      ->check(inRange(0.0, 64.0))->capture_default_str();
  cmd->add_option("--min-step", s.minStepVoxels, "Shortest SDF march step in fine voxels: how densely the march "
                                                 "samples near occluders")
      ->check(inRange(0.05, 64.0))->capture_default_str();
  cmd->add_option("--max-step", s.maxStep, "Longest SDF march step, against banding (scene units)")
      ->check(positive())->capture_default_str();
  cmd->add_option("--max-steps", s.maxSteps, "SDF march steps at most")->check(inRange(1, 4096))
      ->capture_default_str();
  cmd->add_option("--normal-offset", s.normalOffset,
                  "SDF march start off the surface along its normal (scene units; default: the bias)")
      ->check(atLeast(0.0));
  cmd->add_option("--lateral-probes", s.lateralProbes,
                  "Centered estimate: SDF samples around the light's cone where the march came closest to an "
                  "occluder, so that thin plates hold their umbra (0: off)")
      ->check(inRange(0, 64))->capture_default_str();
  cmd->add_option("--light-samples", s.lightSamples,
                  "--penumbra umbra: marches per pixel, light and frame, each over its share of the light")
      ->check(inRange(1, 64))->capture_default_str();
  cmd->add_option("--contact-rays", s.contactRays,
                  "Short rays per pixel and light through the scene's BVH near the surface, where the SDF is too "
                  "coarse to see (contacts, creases, gaps thinner than a voxel); traced only where the SDF shows "
                  "something near the receiver (0: off)")
      ->check(inRange(0, 64))->capture_default_str();
  cmd->add_option("--contact-distance", s.contactVoxels, "How far the contact rays reach, in fine voxels")
      ->check(inRange(0.0, 64.0))->capture_default_str();
  cmd->add_flag("!--no-jitter", s.jitter, "Do not jitter the SDF march's start per pixel and frame (nor the "
                                          "lateral probes', umbra samples' and contact rays' turn)");
}

/// The picture's flags, shared by render and view: shadows, size, SDF march, shadow maps, TAA, truth, pipeline.
void bindRenderSettings(CLI::App* cmd, RenderSettings& r, std::string& device) {
  addEnum(cmd, "--shadows", r.technique, "sdf: sphere tracing of the RTSDF fine SDF; shadowmap: depth maps with "
                                         "PCF; raytraced: distributed ray tracing on the CPU (the truth)");
  cmd->add_option("--width", r.width, "Image width in pixels")->check(inRange(1, 16384))->capture_default_str();
  cmd->add_option("--height", r.height, "Image height in pixels")->check(inRange(1, 16384))->capture_default_str();
  bindSdfShadows(cmd, r.sdf);
  cmd->add_option("--shadow-map-res", r.shadowMap.resolution, "Shadow map texels per side (per cube face)")
      ->check(inRange(1, 8192))->capture_default_str();
  cmd->add_option("--pcf-radius", r.shadowMap.pcfRadius, "PCF kernel radius in texels")->check(inRange(0, 16))
      ->capture_default_str();
  cmd->add_option("--shadow-bias", r.shadowMap.depthBiasTexels, "Shadow map depth bias in texels")
      ->check(atLeast(0.0))->capture_default_str();
  cmd->add_flag("!--no-taa", r.taa.enabled, "Turn temporal accumulation off");
  cmd->add_option("--taa-blend", r.taa.blend, "TAA weight of the newest frame")->check(inRange(1e-6, 1.0))
      ->capture_default_str();
  cmd->add_option("--samples", r.rayTraced.samples, "Ray-traced shadows: samples per pixel and light")
      ->check(inRange(1, 65536))->capture_default_str();
  cmd->add_option("-d,--band", r.pipeline.band, "SDF ray-mask band d in scene units")->check(atLeast(0.0))
      ->capture_default_str();
  bindPipeline(cmd, r.pipeline, device);
}

void bindRender(CLI::App& app, RenderCommand& c) {
  RenderJobOptions& o = c.options;
  RenderSettings& r = o.render;
  CLI::App* cmd = app.add_subcommand(
      "render", "Render the scene camera's view with soft shadows (SDF sphere tracing, shadow maps or ray-traced "
                "truth) to a linear EXR (R, G, B and each light's visibility) and an sRGB PNG");
  cmd->add_option("scene", o.scene, "Scene (.json) with a camera and lights")->required();
  cmd->add_option("-o,--output", c.output, "Output .exr (written atomically)")->required();
  cmd->add_option("--png", c.png, "Output .png (default: the .exr's name with .png)");
  cmd->add_option("--frames", o.frames, "Frames rendered (SDF refinement and TAA accumulate); the last one is "
                                        "written")->check(inRange(1, 100000))->capture_default_str();
  cmd->add_option("--fps", o.fps, "Frames per second of scene time")->check(positive())->capture_default_str();
  cmd->add_option("-t,--time", o.time, "Scene time of the written frame in seconds")->capture_default_str();
  cmd->add_flag("--compare", o.compare, "Also ray trace the truth and print the visibility RMSE and FLIP of the "
                                        "picture");
  bindRenderSettings(cmd, r, o.device);
  // The ray tracer's random seed follows the pipeline's.
  cmd->callback([&r] { r.rayTraced.seed = r.pipeline.seed; });
}

void bindView(CLI::App& app, ViewOptions& o) {
  RenderSettings& r = o.render;
  CLI::App* cmd = app.add_subcommand(
      "view", "Open a window on the scene with its soft shadows as the instances animate. Drag: orbit; wheel: zoom; "
              "1/2/3: sdf/shadowmap/raytraced shadows; V: shaded, SDF slice or ray mask; Up/Down: the slice; "
              "X/D/A (Shift: down): rays x, band d, alpha; M: closest/rays refinement; R: scene camera; Space: pause; "
              "Esc: quit");
  cmd->add_option("scene", o.scene, "Scene (.json) with a camera and lights")->required();
  cmd->add_option("--frames", o.frames, "Show this many frames at fixed steps of 1/fps ending at --time (the "
                                        "frames render renders), then close; 0: until the window is closed")
      ->check(inRange(0, 1000000))->capture_default_str();
  cmd->add_option("--fps", o.fps, "Frames per second of scene time with --frames")->check(positive())
      ->capture_default_str();
  cmd->add_option("-t,--time", o.time, "Scene time of the last frame with --frames")->capture_default_str();
  cmd->add_option("--screenshot", o.screenshot, "Write the last frame's picture to this .png");
  addEnum(cmd, "--view", o.view, "What the picture shows first: the shaded scene, a horizontal slice of the fine "
                                 "SDF, or the ray mask on that slice");
  cmd->add_option("--slice-height", o.sliceHeight, "World height (y) of the slice (default: the scene's middle)");
  cmd->add_flag("!--no-overlay", o.overlay, "No line of text (settings, pass times, frame rate) at the top");
  cmd->add_option("--keys", o.keys, "Key presses replayed one per frame (a letter presses its key, upper case with "
                                    "Shift; + - move the slice, < > turn the camera)");
  bindRenderSettings(cmd, r, o.device);
  cmd->callback([&r] { r.rayTraced.seed = r.pipeline.seed; });
}

void bindBench(CLI::App& app, BenchCommand& c) {
  bench::BenchOptions& s = c.suite;
  bench::SweepRunOptions& run = c.sweepOptions.run;
  CLI::App* cmd = app.add_subcommand(
      "bench", "Time rtsdf's builders against their anchors in one run and write a Markdown table with ratios");
  cmd->add_option("scenes", s.scenes, "Scenes or meshes (default: data/scenes/default.json and the bunny)");
  cmd->add_option("--res", s.resolutions, "Resolutions (voxels along the longest axis)")->check(inRange(1, 8192))
      ->capture_default_str();
  cmd->add_option("--band-fraction", s.bandFraction, "Band half-width as a fraction of the scene's extent")
      ->check(inRange(1e-6, 10.0))->capture_default_str();
  cmd->add_option("--repeats", s.repeats, "Timed runs per point, the median is reported (--sweep: timed frames after "
                                          "a warm-up frame, and runs of each anchor)")
      ->check(inRange(1, 100))->capture_default_str();
  cmd->add_option("-o,--output", s.output, "Also write the Markdown report to this file");
  addEnum(cmd, "--suite", s.suite, "reference: exact SDF vs OpenVDB meshToLevelSet (with the default scenes "
                                   "also a 230k-triangle scan with holes); coarse: GPU voxelize + exact EDT or jump flooding per "
                                   "pass vs CPU jump flooding, exact EDT and OpenVDB "
                                   "meshToSignedDistanceField; refine: the paper's ray-trace tables (sizes x rays, "
                                   "band x rays) with errors, vs OpenVDB meshToLevelSet; render: per-pass times of SDF "
                                   "shadows and shadow maps at 640x360 and 1280x720 with their image error against the "
                                   "ray-traced truth, and the ray tracer's time per sample count (PNGs beside "
                                   "--output); frame: the pipeline frame by frame on one scene (host, GPU and wall "
                                   "time, mask, error against the exact field; --csv writes a row per frame)");
  addEnum(cmd, "--size", s.frameSize, "Frame suite: S (coarse 64 / fine 128), M (128/256) or L (256/512)");
  cmd->add_option("--frames", s.frames, "Frame suite: frames run (medians over frames 2..N)")
      ->check(inRange(1, 100000))->capture_default_str();
  addEnum(cmd, "--refine", s.refine, "Frame suite: refinement mode");
  cmd->add_option("--rays", s.rays, "Frame suite: rays per masked voxel per frame (x)")->check(inRange(0, 1024))
      ->capture_default_str();
  cmd->add_flag("--still", s.still, "Frame suite: every frame at time 0 (a static scene)");
  cmd->add_flag("--full-recompute", s.fullRecompute, "Frame suite: refine every masked voxel every frame (the "
                                                     "paper's frame, the anchor of incremental refinement)");
  bindFineStorage(cmd, s.fineStorage);
  cmd->add_option("--csv", s.csv, "Frame suite: write one CSV row per frame to this file");
  cmd->add_option("--warm-up", s.warmUpSeconds, "Seconds of untimed GPU work before each timed run (GPU suites, not --sweep), "
                                                "so that a GPU's clocks have risen; 0: none")
      ->check(inRange(0.0, 60.0))->capture_default_str();
  cmd->add_option("--device", s.device, "Vulkan device by index or name (GPU suites and --sweep)");
  cmd->add_option("--sweep", c.sweep,
                  "Run the speed/accuracy sweep on one scene instead of a suite: quick (tiny grids, a minute), "
                  "default (sizes S 64/128 and M 128/256, every knob at S), paper (S, M, L 256/512, every knob at M: "
                  "for a real GPU). Writes sweep.csv (row by row), report.md and PNG plots into --out")
      ->check(CLI::IsMember(enumMap<bench::SweepPreset>()));
  cmd->add_option("--out", c.sweepOptions.outDir, "The sweep's output folder (created; default: sweep-<scene name>)");
  cmd->add_option("--error-band", run.errorBand, "The sweep measures the field error where |exact| <= this (scene "
                                                 "units)")->check(inRange(1e-9, 1e9))->capture_default_str();
  cmd->add_flag("!--no-shadows", run.shadows, "The sweep skips the shadow image error");
  cmd->add_option("--truth-samples", run.truthSamples, "Samples per pixel of the sweep's ray-traced shadow truth")
      ->check(inRange(1, 65536))->capture_default_str();
  cmd->callback([&c] {
    c.sweepOptions.run.device = c.suite.device;
    c.sweepOptions.run.repeats = c.suite.repeats;
  });
}

void bindCompare(CLI::App& app, CompareCommand& c) {
  CLI::App* cmd = app.add_subcommand("compare", "Compare two level sets of the same space in A's voxels: mean/RMS/"
                                                "max |difference| in voxels and the rate of sign disagreement (B is "
                                                "resampled when its voxels differ); or A against the exact field or "
                                                "OpenVDB's, baked on A's voxels and band");
  cmd->add_option("a", c.options.a, "The level set measured (.vdb)")->required()->check(CLI::ExistingFile);
  CLI::Option* b = cmd->add_option("b", c.options.b, "The level set it is compared with (.vdb)")
                       ->check(CLI::ExistingFile);
  c.againstFlag = addEnum(cmd, "--against", c.anchor, "Instead of B, bake this anchor on A's voxels, band and time "
                                                      "from A's scene and compare with it");
  c.againstFlag->default_str("")->excludes(b);
  cmd->add_option("--scene", c.options.scene, "The anchor's scene (default: the one A records)")
      ->needs(c.againstFlag);
}

} // namespace

void bindCommands(CLI::App& app, Commands& c, int& verbosity, bool& quiet) {
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("rtsdf ") + RTSDF_VERSION);
  app.add_flag("-v,--verbose", verbosity, "More log output (repeat for trace)");
  app.add_flag("-q,--quiet", quiet, "Only warnings and errors; no progress bar");
  bindBake(app, c.bake);
  bindAnimate(app, c.animate);
  bindRender(app, c.render);
  bindView(app, c.view);
  app.add_subcommand("info", "Print versions, Vulkan devices with their limits, and embedded shaders");
  bindCompare(app, c.compare);
  bindBench(app, c.bench);
}

std::string flagOf(const std::string& setting) {
  static const std::map<std::string, std::string> flags = {
      {"band", "--band"}, {"coarse resolution", "--coarse"}, {"fine resolution", "--fine"}, {"alpha", "--alpha"},
      {"rays", "--rays"}, {"beta", "--beta"}, {"frames", "--frames"}, {"resolution", "--res"}, {"time", "--time"},
      {"padding", "--padding"}, {"full domain", "--full"}, {"fps", "--fps"}, {"vdb folder", "--vdb-dir"},
      {"focus", "--focus"}, {"image width", "--width"}, {"image height", "--height"}, {"epsilon", "--epsilon"},
      {"bias", "--bias"}, {"min step", "--min-step"}, {"max step", "--max-step"}, {"max steps", "--max-steps"},
      {"normal offset", "--normal-offset"}, {"lateral probes", "--lateral-probes"},
      {"light samples", "--light-samples"}, {"shadow map resolution", "--shadow-map-res"},
      {"PCF radius", "--pcf-radius"}, {"shadow bias", "--shadow-bias"}, {"TAA blend", "--taa-blend"},
      {"samples", "--samples"}, {"error band", "--error-band"}, {"repeats", "--repeats"},
      {"truth samples", "--truth-samples"}, {"band fraction", "--band-fraction"}, {"output folder", "--out"},
      {"device", "--device"}, {"anchor", "--against"}, {"scene", "--scene"}, {"settle frames", "--settle-frames"},
      {"refresh period", "--refresh-period"}, {"slice height", "--slice-height"}, {"keys", "--keys"},
      {"view", "--view"}, {"fine storage", "--fine-storage"}, {"SDF sampling", "--sdf-sampling"}};
  const auto it = flags.find(setting);
  return it == flags.end() ? setting : it->second;
}

} // namespace rtsdf::app
