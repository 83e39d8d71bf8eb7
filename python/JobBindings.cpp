// bake, distance and Pipeline: each one call into the library, without the GIL, stopped by Ctrl-C.
#include "Bindings.h"

#include "gpu/VulkanContext.h"
#include "grid/VdbIO.h"
#include "jobs/Bake.h"
#include "jobs/Compare.h"
#include "jobs/JobSupport.h"
#include "jobs/SettingUse.h"
#include "reference/ExactSdf.h"
#include "scene/SceneGeometry.h"
#include "sdf/SdfPipeline.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>

namespace rtsdf::python {
namespace {

py::object bakeField(const py::handle& sceneOrPath, const std::string& method, int res, const py::object& band,
                const py::object& progress, const std::string& up, const py::kwargs& kw) {
  const UpAxis upAxis = parseEnum<UpAxis>(up); // before any work, as the command line refuses --up w
  const ScenePtr scene = sceneOf(sceneOrPath);
  BakeOptions o;
  o.scene = scene->path;
  o.method = parseEnum<BakeMethod>(method);
  if (!band.is_none()) o.pipeline.band = lengthOf(band);
  // res is the result's resolution: the coarse grid's for jfa, the fine grid's for rtsdf (coarse: half of it).
  setOutputResolution(o, res);
  applySettings(kw, nullptr, o.pipeline, o); // the bake's device is a knob of BakeOptions
  // A keyword the bake would ignore is refused, as the command line refuses its flag (jobs/SettingUse.h); the bake
  // refuses a full domain itself, naming the exact method.
  refuseIgnoredKeywords(
      kw, [&o](const std::string& s) { return s == "full domain" ? std::string() : bakeIgnores(o, s); }, o.pipeline, o);
  PythonJob job(progress);
  const BakeResult r = job.run([&] { return bake(*scene, o, job.control()); });
  if (r.levels.size() <= 1)
    return py::cast(Field{r.grid, r.spec, double(r.options.pipeline.band), toString(o.method), upAxis});
  // Cascade levels: one Field each, finest first, each on its own voxels with its own band (level 0's times 2^i).
  py::list levels;
  for (std::size_t i = 0; i < r.levels.size(); ++i)
    levels.append(Field{r.levels[i], gridSpecOf(*r.levels[i]),
                        std::ldexp(double(r.options.pipeline.band), int(i)), toString(o.method), upAxis});
  return levels;
}

/// Exact signed distances (negative inside) at points of shape (..., 3), in parallel without the GIL, in the
/// points' precision (float32 stays float32, the rest float64).
template <class Real> py::array distancesAs(const ScenePtr& scene, const py::array& points, double time,
                                            const py::object& progress) {
  const auto p = py::array_t<Real, py::array::c_style | py::array::forcecast>::ensure(points);
  const std::size_t n = std::size_t(p.size() / 3);
  const Real* xyz = p.data();
  for (std::size_t i = 0; i < 3 * n; ++i)
    if (!std::isfinite(xyz[i])) throw py::value_error(fmt::format("points: row {} is not finite", i / 3));
  py::array_t<Real> out(std::vector<py::ssize_t>(p.shape(), p.shape() + p.ndim() - 1));
  Real* d = out.mutable_data();
  PythonJob job(progress);
  job.run([&] {
    const SceneGeometry geometry = buildSceneGeometry(*scene, time);
    const ExactDistanceField field(geometry);
    JobPoll poll(&job.control(), "distance", n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
      if (poll.stopping()) return;
      for (std::size_t i = r.begin(); i != r.end(); ++i)
        d[i] = Real(field.signedDistance(glm::vec3(float(xyz[3 * i]), float(xyz[3 * i + 1]), float(xyz[3 * i + 2]))));
      poll.done(r.size());
    });
    if (poll.stopping()) throw Interrupted();
    return 0;
  });
  return std::move(out);
}

py::array distances(const py::handle& sceneOrPath, const py::handle& points, double time, const py::object& progress) {
  const py::array a = py::module_::import("numpy").attr("asarray")(points);
  if (a.ndim() < 1 || a.shape(a.ndim() - 1) != 3)
    throw py::value_error("points: must be an (N, 3) array (shape (..., 3): the last axis holds x, y, z)");
  const ScenePtr scene = sceneOf(sceneOrPath);
  if (a.dtype().kind() == 'f' && a.itemsize() == 4) return distancesAs<float>(scene, a, time, progress);
  return distancesAs<double>(scene, a, time, progress);
}

py::dict comparisonDict(const FileComparison& c) {
  py::dict d;
  d["mean_abs"] = c.error.meanAbs;
  d["rms"] = c.error.rms;
  d["max_abs"] = c.error.maxAbs;
  d["sign_disagreement"] = c.error.signErrorRate();
  d["voxels"] = c.error.voxels;
  d["active_a"] = c.activeA;
  d["active_b"] = c.activeB;
  d["voxel_size"] = c.voxelSize;
  d["a"] = c.nameA;
  d["b"] = c.nameB;
  d["warning"] = c.warning;
  py::list levels;
  for (const FileComparison& level : c.levels) levels.append(comparisonDict(level));
  d["levels"] = levels;
  d["report"] = c.report();
  return d;
}

/// `rtsdf compare`: A against B or against an anchor baked on A's voxels.
py::dict compareLevelSets(const std::filesystem::path& a, const std::optional<std::filesystem::path>& b,
                          const std::optional<std::string>& against, const std::optional<std::string>& scene,
                          const std::optional<std::string>& grid, const py::object& progress) {
  CompareOptions o;
  o.a = a;
  if (b) o.b = *b;
  if (against) o.against = parseEnum<CompareAnchor>(*against);
  if (scene) o.scene = *scene;
  if (grid) o.grid = *grid;
  PythonJob job(progress);
  return comparisonDict(job.run([&] { return compare(o, job.control()); }));
}

} // namespace

Field pipelineField(const SdfPipeline& pipe, const char* method) {
  const GridSpec& spec = pipe.fineSpec();
  const float band = float(pipe.settings().band > 0.0 ? double(pipe.settings().band) : spec.voxelSize);
  return {pipe.levelSet(band), spec, band, method};
}

py::dict frameStatsDict(const FrameStats& st) {
  py::dict d;
  d["time"] = st.time;
  d["mask_voxels"] = st.maskFineVoxels;
  d["refined_voxels"] = st.refinedFineVoxels;
  d["cut_voxels"] = st.cutVoxels; // refinements a CPU device's loop budget ended (FrameStats::cutVoxels)
  d["moved_kept_voxels"] = st.movedKeptVoxels; // listed for a moving instance that came near none of them
  d["near_half_voxels"] = st.nearHalfVoxels; // signed by the exact winding number (FrameStats::nearHalfVoxels)
  d["near_half_kept"] = st.nearHalfKept;
  d["active_bricks"] = st.activeBricks;     // bricks under the band, each with a pool slot...
  d["overflow_bricks"] = st.overflowBricks; // ...but these (the pool was full)
  d["pool_bricks"] = st.poolBricks;
  d["device_bytes"] = st.deviceBytes;
  d["moved_instances"] = st.movedInstances;
  d["upsampled_voxels"] = st.upsampledFineVoxels; // the dense fine voxels the upsampling wrote (0: it did not run)
  d["coarse_rebuilt_voxels"] = st.coarseRebuiltVoxels; // the coarse voxels the coarse SDF's build wrote (0: none)
  d["mask_visited_voxels"] = st.maskVisitedVoxels;     // the coarse voxels the mask's compaction visited (0: none)
  d["coarse_voxelized_voxels"] = st.coarseVoxelizedVoxels; // the coarse voxels whose seeds were voxelized (0: none)
  d["skipped_passes"] = st.skippedPasses;
  d["host_ms"] = st.hostMs;
  d["wall_ms"] = st.wallMs;
  py::dict passes;
  for (const auto& [name, ms] : st.passMs) passes[py::str(name)] = ms;
  d["pass_ms"] = passes;
  return d;
}

namespace {

/// Frames of the GPU pipeline on one scene, its grids covering `frames` frames at `fps` from time 0.
class Pipeline {
public:
  Pipeline(const py::handle& sceneOrPath, int frames, double fps, const py::kwargs& kw) : mScene(sceneOf(sceneOrPath)) {
    if (frames < 1 || !(fps > 0.0)) throw SettingError("frames", "frames must be >= 1 and fps > 0");
    PipelineSettings s;
    std::string device;
    applySettings(kw, &device, s);
    refuseIgnoredKeywords(kw, [&s](const std::string& setting) { return pipelineIgnores(s, setting); }, s);
    Bounds bounds;
    for (int f = 0; f < frames; ++f) bounds.add(buildSceneGeometry(*mScene, f / fps).bounds);
    mCtx = std::make_unique<gpu::VulkanContext>(deviceContextOptions(device));
    mPipe = std::make_unique<SdfPipeline>(*mCtx, *mScene, bounds, s);
  }
  py::dict frame(double time) {
    FrameStats st;
    {
      py::gil_scoped_release release;
      st = mPipe->runFrame(time);
    }
    if (mCtx->validationErrors()) throw Error(std::to_string(mCtx->validationErrors()) + " Vulkan validation errors");
    mFrames += 1;
    return frameStatsDict(st);
  }
  Field fine() const { return pipelineField(*mPipe, "pipeline"); }
  std::string repr() const {
    const GridSpec& c = mPipe->coarseSpec();
    const GridSpec& f = mPipe->fineSpec();
    const std::string scene = mScene->path.empty() ? fmt::format("<mesh '{}'>", mScene->meshes.front().name)
                                                   : fmt::format("'{}'", mScene->path);
    return fmt::format("rtsdf.Pipeline({}, coarse {} x {} x {}, fine {} x {} x {}, {} refinement, {} frames run, "
                       "on {})", scene, c.dims.x, c.dims.y, c.dims.z, f.dims.x, f.dims.y, f.dims.z,
                       toString(mPipe->settings().mode), mFrames, mCtx->info().name);
  }

private:
  ScenePtr mScene;
  std::unique_ptr<gpu::VulkanContext> mCtx;
  std::unique_ptr<SdfPipeline> mPipe;
  int mFrames = 0;
};

} // namespace

void bindJobs(py::module_& m) {
  static const std::string bakeDoc =
      "Bake the signed distance field of a scene, an rtsdf.Mesh or a scene/mesh path; returns a Field (with "
      "method='rtsdf' and cascades=K > 1: a list of K Fields, the camera-centred levels, finest first).\n\n"
      "method exact|openvdb|jfa|rtsdf, res voxels across the longest side (the fine grid for rtsdf, the coarse "
      "grid for jfa), band d (a number in scene units or a string such as '3vox'; default: the pipeline's, 6 voxels); "
      "progress: None (quiet) or callable(stage, fraction); up: 'y' or 'z', the up axis of the .vdb Field.write "
      "writes (as the command line's --up: 'z' turns it upright for Blender; the arrays stay in the scene's frame). "
      "Ctrl-C raises KeyboardInterrupt within a second. Settings (docs/settings.md): " +
      keywordsOf<PipelineSettings>() + ", " + keywordsOf<BakeOptions>();
  m.def("bake", &bakeField, py::arg("scene"), py::arg("method") = "exact", py::arg("res") = 128,
        py::arg("band") = py::none(), py::kw_only(), py::arg("progress") = py::none(), py::arg("up") = "y",
        bakeDoc.c_str());
  m.def("distance", &distances, py::arg("scene"), py::arg("points"), py::arg("time") = 0.0, py::kw_only(),
        py::arg("progress") = py::none(),
        "Exact signed distances (negative inside) at world points of shape (..., 3) to a scene, an rtsdf.Mesh or "
        "a scene/mesh path at a time (seconds); shape (...), float32 for float32 points, else float64. Ctrl-C "
        "raises KeyboardInterrupt");
  m.def("compare", &compareLevelSets, py::arg("a"), py::arg("b") = py::none(), py::kw_only(),
        py::arg("against") = py::none(), py::arg("scene") = py::none(), py::arg("grid") = py::none(),
        py::arg("progress") = py::none(),
        "Compare the level set of .vdb file a with b's, or with the anchor against='exact'|'openvdb' baked on a's "
        "voxels, band and time from a's scene (or scene=), as `rtsdf compare`. grid: the grid to read from each "
        "file (default: the one named 'surface' or the only level set). Returns a dict: mean_abs, rms, max_abs "
        "(in a's voxels), sign_disagreement (a fraction), voxels, active_a, active_b, voxel_size, a, b, warning, "
        "levels (a file of cascade levels: one such dict each), report (the command's lines). Raises rtsdf.Error "
        "naming the file and listing its grids when there is no grid of that name");
  static const std::string pipelineDoc =
      "Frames of the GPU SDF pipeline on a scene, an rtsdf.Mesh or a scene/mesh path, its grids covering `frames` "
      "frames at `fps` from time 0. Settings (docs/settings.md): " + keywordsOf<PipelineSettings>() + ", device";
  py::class_<Pipeline>(m, "Pipeline", pipelineDoc.c_str())
      .def(py::init<const py::handle&, int, double, const py::kwargs&>(), py::arg("scene"), py::arg("frames") = 60,
           py::arg("fps") = 30.0)
      .def("frame", &Pipeline::frame, py::arg("time"),
           "Run the frame at a time (seconds); returns its statistics: time, mask_voxels, refined_voxels, host_ms, "
           "wall_ms, pass_ms (per pass)")
      .def("fine", &Pipeline::fine, "The last frame's fine SDF as a Field (the refined voxels)")
      .def("__repr__", &Pipeline::repr);
}

} // namespace rtsdf::python
