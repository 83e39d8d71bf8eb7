#include "Options.h"

#include "KnobCli.h"
#include "util/EnumNames.h"
#include "util/Error.h"
#include "util/KnobDocs.h"
#include "jobs/SettingUse.h"
#include "view/ViewSettingUse.h"

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <string>

namespace rtsdf::app {
namespace {

/// The picture's knobs, shared by render and view: shadows, size, SDF march, shadow maps, TAA, truth, pipeline.
/// The fine storage follows the SDF sampling there (the renderer's choice), so it has no flag.
void bindRenderSettings(CLI::App* cmd, RenderSettings& r, SettingFlags& flags) {
  bindKnobs(cmd, r, flags);
  bindKnobs(cmd, r.sdf, flags);
  bindKnobs(cmd, r.shadowMap, flags);
  bindKnobs(cmd, r.taa, flags);
  bindKnobs(cmd, r.rayTraced, flags);
  forEachKnob<PipelineSettings>([&](const auto& k) {
    if (std::string(k.setting) != EnumNames<FineStorage>::kSetting) bindKnob(cmd, k, r.pipeline.*(k.member), flags);
  });
}

constexpr const char* kUpHelp = "The up axis of the .vdb written: y (as the scene is) or z (turned upright for "
                                "Blender and other Z-up tools; recorded as rtsdf:up)";

/// --allow-outside-references, on every command that loads a scene.
void bindMeshLoad(CLI::App* cmd, MeshLoadOptions& m) {
  cmd->add_flag("--allow-outside-references", m.allowOutsideReferences,
                "Let the scene's mesh paths and each mesh's references (glTF buffers and images, OBJ materials) "
                "resolve outside their folder ('..', absolute paths, symbolic links); refused without it");
}

void bindBake(CLI::App& app, BakeCommand& c, SettingFlags& flags) {
  BakeOptions& o = c.options;
  CLI::App* cmd = app.add_subcommand("bake", "Build the signed distance field of a scene and write it as a .vdb");
  cmd->add_option("scene", o.scene, "Scene (.json) or mesh file (.obj, .ply, .stl, .gltf, ...)")->required();
  bindMeshLoad(cmd, o.meshLoad);
  cmd->add_option("-o,--output", c.output, "Output .vdb file (written atomically)")->required();
  bindKnobs(cmd, o, flags);
  bindKnobs(cmd, o.pipeline, flags);
  cmd->add_flag("--fog", c.written.fog, "Also write a 'density' fog grid so Blender shows the volume");
  cmd->add_flag("--half", c.written.vdb.halfFloat, "Store values as 16-bit halves");
  addEnum(cmd, "--compression", c.written.vdb.compression, "blosc, zip or none");
  addEnum(cmd, "--up", c.written.vdb.up, kUpHelp);
  flags.add(EnumNames<UpAxis>::kSetting, "--up");
}

void bindAnimate(CLI::App& app, AnimateCommand& c, SettingFlags& flags) {
  AnimateOptions& o = c.options;
  CLI::App* cmd = app.add_subcommand(
      "animate", "Run the RTSDF pipeline over an animation: per-frame mask size, pass times and error against the "
                 "exact field of the same moment (ghosting), optionally per-frame .vdb files");
  cmd->add_option("scene", o.scene, "Scene (.json) or mesh file")->required();
  bindMeshLoad(cmd, o.meshLoad);
  cmd->add_option("--csv", c.csv, "Write per-frame statistics to this CSV file");
  bindKnobs(cmd, o, flags);
  bindKnobs(cmd, o.pipeline, flags);
  addEnum(cmd, "--up", o.vdb.up, kUpHelp);
  flags.add(EnumNames<UpAxis>::kSetting, "--up");
}

void bindRender(CLI::App& app, RenderCommand& c, SettingFlags& flags) {
  RenderJobOptions& o = c.options;
  RenderSettings& r = o.render;
  CLI::App* cmd = app.add_subcommand(
      "render", "Render the scene camera's view with soft shadows (SDF sphere tracing, shadow maps or ray-traced "
                "truth) to a linear EXR (R, G, B and each light's visibility) and an sRGB PNG");
  cmd->add_option("scene", o.scene, "Scene (.json) with a camera and lights")->required();
  bindMeshLoad(cmd, o.meshLoad);
  cmd->add_option("-o,--output", c.output, "Output .exr (written atomically)")->required();
  cmd->add_option("--png", c.png, "Output .png (default: the .exr's name with .png)");
  bindKnobs(cmd, o, flags);
  bindRenderSettings(cmd, r, flags);
  // The ray tracer's random seed follows the pipeline's.
  cmd->callback([&r] { r.rayTraced.seed = r.pipeline.seed; });
}

void bindView(CLI::App& app, ViewOptions& o, SettingFlags& flags) {
  RenderSettings& r = o.render;
  CLI::App* cmd = app.add_subcommand(
      "view", "Open a window on the scene with its soft shadows as the instances animate. Drag: orbit; wheel: zoom; "
              "1/2/3: sdf/shadowmap/raytraced shadows; V: shaded, SDF slice or ray mask; Up/Down: the slice; "
              "X/D/A (Shift: down): rays x, band d, alpha; M: closest/rays refinement; R: scene camera; Space: pause; "
              "Esc: quit");
  cmd->add_option("scene", o.scene, "Scene (.json) with a camera and lights")->required();
  bindMeshLoad(cmd, o.meshLoad);
  bindKnobs(cmd, o, flags);
  bindRenderSettings(cmd, r, flags);
  cmd->callback([&r] { r.rayTraced.seed = r.pipeline.seed; });
}

/// Options bound by hand (structs without a knob table) note their setting's flag here.
CLI::Option* noted(CLI::Option* option, const char* setting, SettingFlags& flags) {
  flags.add(setting, longFlag(option->get_name().c_str()));
  return option;
}

void bindBench(CLI::App& app, BenchCommand& c, SettingFlags& flags) {
  bench::BenchOptions& s = c.suite;
  bench::SweepRunOptions& run = c.sweepOptions.run;
  CLI::App* cmd = app.add_subcommand(
      "bench", "Time rtsdf's builders against their anchors in one run and write a Markdown table with ratios");
  cmd->add_option("scenes", s.scenes, "Scenes or meshes (default: data/scenes/default.json and the bunny)");
  noted(cmd->add_option("--res", s.resolutions, "Resolutions (voxels along the longest axis)"), "resolution", flags)
      ->check(inRange(1, 8192))->capture_default_str();
  noted(cmd->add_option("--band-fraction", s.bandFraction, "Band half-width as a fraction of the scene's extent"),
        "band fraction", flags)->check(inRange(1e-6, 10.0))->capture_default_str();
  noted(cmd->add_option("--repeats", s.repeats, "Timed runs per point, the median is reported (--sweep: timed frames "
                                                "after a warm-up frame, and runs of each anchor)"), "repeats", flags)
      ->check(inRange(1, 100))->capture_default_str();
  cmd->add_option("-o,--output", s.output, "Also write the Markdown report to this file");
  addEnum(cmd, "--suite", s.suite, "reference: exact SDF vs OpenVDB meshToLevelSet (with the default scenes "
                                   "also a 230k-triangle scan with holes); coarse: GPU voxelize + exact EDT or jump flooding per "
                                   "pass vs CPU jump flooding, exact EDT and OpenVDB "
                                   "meshToSignedDistanceField; refine: the paper's ray-trace tables (sizes x rays, "
                                   "band x rays) with errors, vs OpenVDB meshToLevelSet; render: per-pass times of SDF "
                                   "shadows and shadow maps at 640x360 and 1280x720 with their image error against the "
                                   "ray-traced truth, the SDF shadows' pass times with the scene moving at 30 fps "
                                   "(incremental and every pass), and the ray tracer's time per sample count (PNGs "
                                   "beside --output); frame: the pipeline frame by frame on one scene (host, GPU and wall "
                                   "time, mask, error against the exact field; --csv writes a row per frame); sign: every method's "
                                   "signs on generated meshes whose faces lie (inside-out, flipped, parts through "
                                   "each other, an inner shell; in two units) vs the clean solid and OpenVDB, at the "
                                   "first --res; cascade: --cascades levels following each scene's camera path "
                                   "(walking, then driving) against every level rebuilt each frame (--csv writes a "
                                   "row per frame)");
  addEnum(cmd, "--size", s.frameSize, "Frame and cascade suites: S (coarse 64 / fine 128), M (128/256) or L (256/512); per level for cascades");
  noted(cmd->add_option("--frames", s.frames, "Frame and cascade suites: frames run (per camera speed and build for cascades; medians over frames 2..N, and for cascades the GPU time's mean and largest)"), "frames", flags)
      ->check(inRange(1, 100000))->capture_default_str();
  addEnum(cmd, "--refine", s.refine, "Frame and cascade suites: refinement mode");
  noted(cmd->add_option("--rays", s.rays, "Frame and cascade suites: rays per masked voxel per frame [x]"), "rays", flags)
      ->check(inRange(0, 1024))->capture_default_str();
  cmd->add_flag("--still", s.still, "Frame suite: every frame at time 0 (a static scene)");
  cmd->add_flag("--full-recompute", s.fullRecompute, "Frame suite: refine every masked voxel every frame (the "
                                                     "paper's frame, the anchor of incremental refinement)");
  cmd->add_flag("--full-rebuild", s.fullRebuild, "Frame suite: run every pass of every frame over the whole grid "
                                                 "(incremental refinement, no pass skipped)");
  addEnum(cmd, "--fine-storage", s.fineStorage, "Frame suite: dense (a dense fine SDF resolved every frame) or "
                                                "sparse (the bricks only)");
  cmd->add_option("--csv", s.csv, "Frame and cascade suites: write one CSV row per frame to this file");
  noted(cmd->add_option("--cascades", s.cascades, "Cascade suite: camera-centred levels (2 or more)"), "cascades",
        flags)->check(inRange(1, kMaxCascades))->capture_default_str();
  noted(cmd->add_option("--cascade-extent", s.cascadeExtent, "Cascade suite: level 0's side in scene units (default: "
                                                            "the outermost level holds the scene)"),
        "cascade extent", flags);
  noted(cmd->add_option("--cascade-view-margin", s.cascadeViewMargin, "Cascade suite: levels above 0 refine within "
                                                                     "this many of their coarse voxels of the "
                                                                     "camera's view (-1: their whole band)"),
        "cascade view margin", flags)->capture_default_str();
  noted(cmd->add_option("--shade", s.shade, "Cascade suite: also render each camera's incremental frames at WIDTH "
                                            "HEIGHT pixels (SDF shadows at render's defaults) and time the levels and "
                                            "the shading together, e.g. --shade 1280 720"),
        "shade size", flags)->check(inRange(1, 16384));
  noted(cmd->add_option("--warm-up", s.warmUpSeconds, "Seconds of untimed GPU work before each timed run (GPU suites, "
                                                      "not --sweep), so that a GPU's clocks have risen; 0: none"),
        "warm-up seconds", flags)->check(inRange(0.0, 60.0))->capture_default_str();
  noted(cmd->add_option("--device", s.device, "Vulkan device by index or name (GPU suites and --sweep)"), "device",
        flags);
  cmd->add_option("--sweep", c.sweep,
                  "Run the speed/accuracy sweep on one scene instead of a suite: quick (tiny grids, a minute), "
                  "default (sizes S 64/128 and M 128/256, every knob at S), paper (S, M, L 256/512, every knob at M: "
                  "for a real GPU). Writes sweep.csv (row by row), report.md and PNG plots into --out")
      ->check(CLI::IsMember(enumMap<bench::SweepPreset>()));
  noted(cmd->add_option("--out", c.sweepOptions.outDir, "The sweep's output folder (created; default: "
                                                        "sweep-<scene name>)"), "output folder", flags);
  noted(cmd->add_option("--error-band", run.errorBand, "The sweep measures the field error where |exact| <= this "
                                                       "(scene units)"), "error band", flags)
      ->check(inRange(1e-9, 1e9))->capture_default_str();
  cmd->add_flag("!--no-shadows", run.shadows, "The sweep skips the shadow image error");
  noted(cmd->add_option("--truth-samples", run.truthSamples, "Samples per pixel of the sweep's ray-traced shadow "
                                                             "truth"), "truth samples", flags)
      ->check(inRange(1, 65536))->capture_default_str();
  cmd->callback([&c] {
    c.sweepOptions.run.device = c.suite.device;
    c.sweepOptions.run.repeats = c.suite.repeats;
  });
  // The flags by the settings bench::benchIgnores names (a flag every suite and the sweep read has none).
  static const std::pair<const char*, const char*> kBenchSettings[] = {
      {"--res", "resolution"},          {"--band-fraction", "band fraction"},     {"--repeats", "repeats"},
      {"--suite", "benchmark suite"},   {"--size", "frame size"},                 {"--frames", "frames"},
      {"--refine", "refinement mode"},  {"--rays", "rays"},                       {"--still", "still"},
      {"--full-recompute", "full recompute"}, {"--full-rebuild", "full rebuild"}, {"--fine-storage", "fine storage"},
      {"--csv", "frame csv"},           {"--warm-up", "warm-up seconds"},         {"--device", "device"},
      {"--cascades", "cascades"},       {"--cascade-extent", "cascade extent"},   {"--shade", "shade size"},
      {"--cascade-view-margin", "cascade view margin"},
      {"--out", "output folder"},       {"--error-band", "error band"},           {"--no-shadows", "shadows"},
      {"--truth-samples", "truth samples"}};
  for (const auto& [flag, setting] : kBenchSettings) c.flags.add(setting, flag);
}

void bindCompare(CLI::App& app, CompareCommand& c, SettingFlags& flags) {
  CLI::App* cmd = app.add_subcommand("compare", "Compare two level sets of the same space in A's voxels: mean/RMS/"
                                                "max |difference| in voxels and the rate of sign disagreement (B is "
                                                "resampled when its voxels differ); or A against the exact field or "
                                                "OpenVDB's, baked on A's voxels and band");
  cmd->add_option("a", c.options.a, "The level set measured (.vdb)")->required()->check(CLI::ExistingFile);
  CLI::Option* b = cmd->add_option("b", c.options.b, "The level set it is compared with (.vdb)")
                       ->check(CLI::ExistingFile);
  c.againstFlag = noted(addEnum(cmd, "--against", c.anchor, "Instead of B, bake this anchor on A's voxels, band and "
                                                             "time from A's scene and compare with it"),
                        EnumNames<CompareAnchor>::kSetting, flags);
  c.againstFlag->default_str("")->excludes(b);
  noted(cmd->add_option("--scene", c.options.scene, "The anchor's scene (default: the one A records)"), "scene", flags)
      ->needs(c.againstFlag);
  noted(cmd->add_option("--grid", c.options.grid, "The grid to read from each file (default: the one named 'surface' "
                                                  "or the only level set)"), "grid", flags);
}

void bindMesh(CLI::App& app, MeshOptions& o, SettingFlags& flags) {
  CLI::App* cmd = app.add_subcommand("mesh", "Write the zero level set of a .vdb as a triangle mesh (OpenVDB's "
                                             "volumeToMesh; .obj, .ply or .stl by the output's extension)");
  cmd->add_option("input", o.input, "The level set (.vdb)")->required();
  cmd->add_option("-o,--output", o.output, "Output mesh: .obj, .ply or .stl (written atomically)")->required();
  bindKnobs(cmd, o, flags);
}

/// Whether @a flag ("--res") was given on @a cmd's command line.
bool given(const CLI::App* cmd, const std::string& flag) {
  const CLI::Option* o = cmd->get_option_no_throw(flag);
  return o && o->count() > 0;
}

/// --res as the method's output grid, --coarse and --fine over it.
void resolveBakeGrids(const CLI::App* cmd, BakeOptions& o, Preset preset) {
  const int coarse = o.pipeline.coarseRes, fine = o.pipeline.fineRes;
  int res = o.resolution;
  if (!given(cmd, "--res") && preset != Preset::Default) res = pipelinePreset(preset).fineRes;
  setOutputResolution(o, res);
  if (given(cmd, "--fine")) {
    o.pipeline.fineRes = fine;
    if (o.method == BakeMethod::Rtsdf) o.pipeline.coarseRes = std::max(1, fine / 2);
  }
  if (given(cmd, "--coarse")) o.pipeline.coarseRes = coarse;
}

/// Refuse the first flag given on @a cmd whose setting the job would ignore: "<flag> <why>", @a ignores saying why
/// (the library's rules, jobs/SettingUse.h) or "" when the job reads it.
void refuseIgnoredFlags(const CLI::App* cmd, const SettingFlags& flags,
                        const std::function<std::string(const std::string& setting)>& ignores) {
  for (const CLI::Option* opt : cmd->get_options()) {
    if (opt->count() == 0) continue;
    const std::string flag = longFlag(opt->get_name().c_str());
    const std::string setting = flags.settingOf(flag);
    if (setting.empty()) continue;
    if (const std::string why = ignores(setting); !why.empty()) throw Error(flag + " " + why);
  }
}

} // namespace

void finishCommands(CLI::App& app, Commands& c) {
  const CLI::App* cmd = app.get_subcommand(c.which);
  const PipelineSettings preset = pipelinePreset(c.preset);
  if (c.which == "bake") {
    if (c.preset != Preset::Default) applyPreset(cmd, c.bake.options.pipeline, preset);
    resolveBakeGrids(cmd, c.bake.options, c.preset);
    // The bake refuses a full domain itself, naming the exact method (BakeOptions::validate).
    refuseIgnoredFlags(cmd, c.flags, [&o = c.bake.options](const std::string& setting) {
      return setting == "full domain" ? std::string() : bakeIgnores(o, setting);
    });
    return;
  }
  if (c.preset != Preset::Default) {
    if (c.which == "animate") applyPreset(cmd, c.animate.options.pipeline, preset);
    if (c.which == "render") applyPreset(cmd, c.render.options.render.pipeline, preset);
    if (c.which == "view") applyPreset(cmd, c.view.render.pipeline, preset);
  }
  if (c.which == "animate")
    refuseIgnoredFlags(cmd, c.flags, [&o = c.animate.options](const std::string& s) { return animateIgnores(o, s); });
  if (c.which == "render")
    refuseIgnoredFlags(cmd, c.flags, [&o = c.render.options](const std::string& s) { return renderIgnores(o, s); });
  if (c.which == "view")
    refuseIgnoredFlags(cmd, c.flags, [&o = c.view](const std::string& s) { return viewIgnores(o, s); });
  if (c.which == "bench")
    refuseIgnoredFlags(cmd, c.bench.flags, [&b = c.bench](const std::string& s) {
      return bench::benchIgnores(b.suite, !b.sweep.empty(), s);
    });
}

std::string helpSettings() {
  const BakeOptions bake;
  const AnimateOptions animate;
  const RenderJobOptions render;
  // One set of defaults: a job whose pipeline differed from the struct's would need its own column again.
  for (const PipelineSettings* p : {&bake.pipeline, &animate.pipeline, &render.render.pipeline})
    if (knobMarkdown<PipelineSettings>({{"", *p}}, false) != knobMarkdown<PipelineSettings>({{"", {}}}, false))
      throw Error("help-settings: a job's pipeline defaults differ from PipelineSettings'");
  const ViewOptions view;
  std::string md = "# Settings\n\n<!-- Generated by `rtsdf help-settings --markdown` from the knob tables "
                   "(KnobTable<S>, util/Knobs.h); the test Docs.SettingsAreGenerated fails when it differs. -->\n\n"
                   "Every knob of the library's settings structs, one row per knob of its struct's table: the name "
                   "a `SettingError` gives it, the command-line flag, the default (the struct's own initializer, the "
                   "same in every command, in Python and in the library), the range `validate()` accepts (the command "
                   "line refuses the special values, which mean \"leave the flag out\") and what it does, the "
                   "paper's symbol in brackets. Python's `bake()` and `Pipeline()` take the keywords shown. A length "
                   "is a number in scene units or a number of voxels of the output grid followed by `vox` (Python: "
                   "the string `\"3vox\"`); `--preset paper` sets the paper's values (its column) under the flags "
                   "given. docs/results.md (\"Defaults\") says why these defaults.\n";
  md += "\n## PipelineSettings (sdf/PipelineSettings.h): the SDF pipeline of bake, animate, render and view\n\n";
  md += knobMarkdown<PipelineSettings>({{"default", PipelineSettings{}},
                                        {"--preset paper", pipelinePreset(Preset::Paper)}}, true);
  md += "\n## BakeOptions (jobs/Bake.h): `rtsdf bake`, `rtsdf.bake()`\n\n";
  md += knobMarkdown<BakeOptions>({{"default", bake}}, true);
  md += "\n## AnimateOptions (jobs/Animate.h): `rtsdf animate`\n\n";
  md += knobMarkdown<AnimateOptions>({{"default", animate}}, false);
  md += "\n## RenderJobOptions (jobs/RenderJob.h): `rtsdf render`\n\n";
  md += knobMarkdown<RenderJobOptions>({{"default", render}}, false);
  md += "\n## ViewOptions (view/Viewer.h): `rtsdf view`\n\n";
  md += knobMarkdown<ViewOptions>({{"default", view}}, false);
  md += "\n## MeshOptions (jobs/MeshJob.h): `rtsdf mesh`\n\n";
  md += knobMarkdown<MeshOptions>({{"default", MeshOptions{}}}, false);
  md += "\n## RenderSettings (render/Renderer.h): the picture of `render` and `view`\n\n";
  md += knobMarkdown<RenderSettings>({{"render", render.render}, {"view", view.render}}, false);
  md += "\n### SdfShadowSettings: the SDF march\n\n";
  md += knobMarkdown<SdfShadowSettings>({{"default", render.render.sdf}}, false);
  md += "\n### ShadowMapSettings: the shadow-map baseline\n\n";
  md += knobMarkdown<ShadowMapSettings>({{"default", render.render.shadowMap}}, false);
  md += "\n### TaaSettings: temporal anti-aliasing\n\n";
  md += knobMarkdown<TaaSettings>({{"default", render.render.taa}}, false);
  md += "\n### RayTracedShadowSettings: the ray-traced truth\n\n";
  md += knobMarkdown<RayTracedShadowSettings>({{"default", render.render.rayTraced}}, false);
  return md;
}

void bindCommands(CLI::App& app, Commands& c, int& verbosity, bool& quiet) {
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("rtsdf ") + RTSDF_VERSION);
  app.add_flag("-v,--verbose", verbosity, "More log output (repeat for trace)");
  app.add_flag("-q,--quiet", quiet, "Only warnings and errors; no progress bar");
  bindBake(app, c.bake, c.flags);
  bindAnimate(app, c.animate, c.flags);
  bindRender(app, c.render, c.flags);
  bindView(app, c.view, c.flags);
  app.add_subcommand("info", "Print versions, Vulkan devices with their limits, and embedded shaders");
  bindCompare(app, c.compare, c.flags);
  bindBench(app, c.bench, c.flags);
  bindMesh(app, c.mesh, c.flags);
  // Hidden: writes docs/settings.md (the test Docs.SettingsAreGenerated compares).
  CLI::App* settings = app.add_subcommand("help-settings", "Print every settings struct's knobs")->group("");
  settings->add_flag("--markdown", "As Markdown (the only form)");
  for (const char* name : {"bake", "animate", "render", "view"})
    addEnum(app.get_subcommand(name), "--preset", c.preset,
            "Settings under the flags given: default (fast on a CPU device and accurate: closest refinement, coarse 64 "
            "/ fine 128, band 6 voxels) or paper (the paper's: rays x = 10, alpha 0.95, 1+JFA, coarse 128 / fine 256"
            "; bake: 16 frames)");
  // The global flags (-v, -q) are taken after the subcommand too.
  for (CLI::App* sub : app.get_subcommands({})) sub->fallthrough();
}

} // namespace rtsdf::app
