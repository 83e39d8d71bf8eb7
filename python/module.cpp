// The Python module `rtsdf` (pybind11): scenes, bakes as numpy arrays, exact point distances and pipeline frames,
// each one call into the library. docs/python.md shows a session.
#include "gpu/VulkanContext.h"
#include "grid/VdbIO.h"
#include "jobs/Bake.h"
#include "jobs/JobSupport.h"
#include "reference/ExactSdf.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/SdfPipeline.h"
#include "util/EnumNames.h"
#include "util/Error.h"
#include "util/Knobs.h"
#include "util/Log.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

namespace py = pybind11;
using namespace rtsdf;

namespace {

/// A loaded scene, shared by the objects made from it (a Pipeline keeps its scene alive).
using ScenePtr = std::shared_ptr<const Scene>;

ScenePtr sceneOf(const py::object& sceneOrPath) {
  if (py::isinstance<Scene>(sceneOrPath)) return sceneOrPath.cast<std::shared_ptr<Scene>>();
  return std::make_shared<const Scene>(loadScene(py::str(sceneOrPath).cast<std::string>()));
}

/// A baked field: the level set with its voxels. values/active are (nx, ny, nz) arrays, index [i, j, k] = x, y, z.
struct Field {
  openvdb::FloatGrid::Ptr grid;
  GridSpec spec;
  double band = 0.0;
  py::array_t<float> values() const {
    const std::vector<float> dense = levelSetToDense(*grid, spec);
    return toArray<float>(dense);
  }
  py::array_t<bool> active() const {
    std::vector<char> on(spec.voxelCount(), 0);
    for (auto it = grid->cbeginValueOn(); it; ++it) {
      const openvdb::Coord c = it.getCoord();
      if (c.x() >= 0 && c.y() >= 0 && c.z() >= 0 && c.x() < spec.dims.x && c.y() < spec.dims.y && c.z() < spec.dims.z)
        on[spec.linear(c.x(), c.y(), c.z())] = 1;
    }
    py::array_t<bool> out = emptyArray<bool>();
    std::copy(on.begin(), on.end(), out.mutable_data());
    return out;
  }
  /// An x-fastest (Fortran-order) array of the grid's shape.
  template <class T> py::array_t<T> emptyArray() const {
    const std::vector<py::ssize_t> shape{spec.dims.x, spec.dims.y, spec.dims.z};
    const std::vector<py::ssize_t> strides{py::ssize_t(sizeof(T)), py::ssize_t(sizeof(T)) * spec.dims.x,
                                           py::ssize_t(sizeof(T)) * spec.dims.x * spec.dims.y};
    return py::array_t<T>(shape, strides);
  }
  template <class T> py::array_t<T> toArray(const std::vector<T>& dense) const {
    py::array_t<T> out = emptyArray<T>();
    std::copy(dense.begin(), dense.end(), out.mutable_data());
    return out;
  }
};

/// A length from Python: a number (scene units) or a string such as "3vox" (util/Length.h).
Length lengthOf(const py::handle& value) {
  if (!py::isinstance<py::str>(value)) return Length(value.cast<double>());
  const std::string text = value.cast<std::string>();
  if (const std::optional<Length> l = Length::parse(text)) return *l;
  throw py::value_error("'" + text + "' is not a length (" + std::string(kLengthSyntax) + ")");
}

/// Sets the member of the knob named by a Python keyword (util/Knobs.h) from a Python value.
struct SetFromPython {
  const py::handle& value;
  template <class K, class T> void operator()(const K&, T& member) const {
    if constexpr (IsNamedEnum<T>::value) member = parseEnum<T>(value.cast<std::string>());
    else if constexpr (std::is_same_v<T, Length>) member = lengthOf(value);
    else member = value.cast<T>();
  }
};

/// The keyword settings of bake() and Pipeline() onto the pipeline's (and a bake's) knobs, by the keywords of
/// their tables (docs/settings.md); unknown keys refused.
void applySettings(const py::kwargs& kw, PipelineSettings& p, BakeOptions* bake, std::string* device) {
  for (const auto& [key, value] : kw) {
    const std::string k = py::str(key);
    const SetFromPython set{value};
    if (visitKnobByKeyword(p, k, set) || (bake && visitKnobByKeyword(*bake, k, set))) continue;
    if (device && k == "device") *device = value.cast<std::string>();
    else throw py::type_error("unknown setting '" + k + "'");
  }
}

/// The keywords of S's table, "a, b, c".
template <class S> std::string keywordsOf() {
  std::string s;
  forEachKnob<S>([&](const auto& k) { s += (s.empty() ? "" : ", ") + keywordOf(k); });
  return s;
}

Field bakeField(const py::object& sceneOrPath, const std::string& method, int res, const py::object& band,
                const py::kwargs& kw) {
  const ScenePtr scene = sceneOf(sceneOrPath);
  BakeOptions o;
  o.scene = scene->path;
  o.method = parseEnum<BakeMethod>(method);
  if (!band.is_none()) o.pipeline.band = lengthOf(band);
  // res is the result's resolution: the coarse grid's for jfa, the fine grid's for rtsdf (coarse: half of it).
  setOutputResolution(o, res);
  applySettings(kw, o.pipeline, &o, nullptr); // the bake's device is a knob of BakeOptions
  BakeResult r;
  {
    py::gil_scoped_release release;
    r = bake(*scene, o);
  }
  return {r.grid, r.spec, r.options.pipeline.band};
}

/// Exact signed distances of (N, 3) points (the exact bake's sign rules), in parallel without the GIL.
py::array_t<float> distances(const py::object& sceneOrMesh, const py::array_t<double, py::array::c_style |
                             py::array::forcecast>& points, double time) {
  if (points.ndim() != 2 || points.shape(1) != 3) throw py::value_error("points must be an (N, 3) array");
  const ScenePtr scene = sceneOf(sceneOrMesh);
  const SceneGeometry geometry = buildSceneGeometry(*scene, time);
  const std::size_t n = std::size_t(points.shape(0));
  py::array_t<float> out{py::ssize_t(n)};
  const double* p = points.data();
  float* d = out.mutable_data();
  for (std::size_t i = 0; i < 3 * n; ++i)
    if (!std::isfinite(p[i])) throw py::value_error("points: coordinate " + std::to_string(i) + " is not finite");
  {
    py::gil_scoped_release release;
    const ExactDistanceField field(geometry);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
      d[i] = field.signedDistance(glm::vec3(float(p[3 * i]), float(p[3 * i + 1]), float(p[3 * i + 2])));
    });
  }
  return out;
}

/// Frames of the GPU pipeline on one scene, its grids covering `frames` frames at `fps` from time 0.
class Pipeline {
public:
  Pipeline(const py::object& sceneOrPath, int frames, double fps, const py::kwargs& kw) : mScene(sceneOf(sceneOrPath)) {
    if (frames < 1 || !(fps > 0.0)) throw SettingError("frames", "frames must be >= 1 and fps > 0");
    PipelineSettings s;
    std::string device;
    applySettings(kw, s, nullptr, &device);
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
    py::dict d;
    d["time"] = st.time;
    d["mask_voxels"] = st.maskFineVoxels;
    d["refined_voxels"] = st.refinedFineVoxels;
    d["host_ms"] = st.hostMs;
    d["wall_ms"] = st.wallMs;
    py::dict passes;
    for (const auto& [name, ms] : st.passMs) passes[py::str(name)] = ms;
    d["pass_ms"] = passes;
    return d;
  }
  Field fine() const {
    const GridSpec& spec = mPipe->fineSpec();
    const float band = float(mPipe->settings().band > 0.0 ? double(mPipe->settings().band) : spec.voxelSize);
    return {mPipe->levelSet(band), spec, band};
  }

private:
  ScenePtr mScene;
  std::unique_ptr<gpu::VulkanContext> mCtx;
  std::unique_ptr<SdfPipeline> mPipe;
};

} // namespace

PYBIND11_MODULE(rtsdf, m) {
  m.doc() = "rtsdf: signed distance fields of triangle-mesh scenes (exact, OpenVDB, GPU jump flooding / exact "
            "transform, and the RTSDF pipeline)";
  openvdb::initialize();
  initLogging(-1); // a library in someone's program: warnings only, on stderr (set_verbosity says more)
  m.def("set_verbosity", [](int level) {
    spdlog::set_level(level < 0 ? spdlog::level::warn : level == 0 ? spdlog::level::info
                                                     : level == 1 ? spdlog::level::debug : spdlog::level::trace);
  }, py::arg("level"), "Log to stderr: -1 warnings only (the default), 0 info, 1 debug, 2 trace");
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<SettingError> settingError(m, "SettingError", error.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const SettingError& e) {
      settingError(e.what());
    } catch (const Error& e) {
      error(e.what());
    }
  });

  py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", "A loaded scene (load_scene)")
      .def_property_readonly("path", [](const Scene& s) { return s.path; })
      .def_property_readonly("instances", [](const Scene& s) { return s.instances.size(); })
      .def_property_readonly("triangles", [](const Scene& s) {
        std::size_t n = 0;
        for (const Instance& i : s.instances) n += s.meshes.at(i.mesh).triangles.size();
        return n;
      });
  m.def("load_scene", [](const std::string& path) { return std::make_shared<Scene>(loadScene(path)); },
        py::arg("path"), "Load a scene (.json) or a mesh file (OBJ, PLY, STL, glTF ...); raises rtsdf.Error");

  py::class_<Field>(m, "Field", "A baked signed distance field on a grid of voxels")
      .def_property_readonly("values", &Field::values, "float32 (nx, ny, nz), [i, j, k] = x, y, z; +-band outside it")
      .def_property_readonly("active", &Field::active, "bool (nx, ny, nz): the narrow band's voxels")
      .def_property_readonly("origin", [](const Field& f) {
        return py::make_tuple(f.spec.origin.x, f.spec.origin.y, f.spec.origin.z); }, "world corner of voxel 0")
      .def_property_readonly("voxel_size", [](const Field& f) { return f.spec.voxelSize; })
      .def_property_readonly("band", [](const Field& f) { return f.band; })
      .def("write", [](const Field& f, const std::filesystem::path& path) { writeVdb(path, {f.grid}); },
           py::arg("path"), "Write the level set to a .vdb file")
      .def("to_pyopenvdb", [](const Field& f) {
        // Through a file: pyopenvdb's grids are its own build's objects.
        const py::module_ vdb = py::module_::import("pyopenvdb");
        const py::module_ tempfile = py::module_::import("tempfile");
        const py::object dir = tempfile.attr("TemporaryDirectory")();
        const std::string path = py::str(dir.attr("name")).cast<std::string>() + "/field.vdb";
        writeVdb(path, {f.grid});
        py::object grid = vdb.attr("read")(path, f.grid->getName());
        dir.attr("cleanup")();
        return grid;
      }, "The level set as a pyopenvdb.FloatGrid (needs pyopenvdb)");

  static const std::string bakeDoc =
      "Bake a scene's SDF: method exact|openvdb|jfa|rtsdf, res voxels of the output grid across its longest side (rtsdf: the fine grid, jfa: the coarse), "
      "band d (a length: a number in scene units or a string such as '3vox'; default: the pipeline's); settings "
      "(docs/settings.md): " + keywordsOf<PipelineSettings>() + ", " + keywordsOf<BakeOptions>();
  m.def("bake", &bakeField, py::arg("scene"), py::arg("method") = "exact", py::arg("res") = 128,
        py::arg("band") = py::none(), bakeDoc.c_str());
  m.def("distance", &distances, py::arg("scene"), py::arg("points"), py::arg("time") = 0.0,
        "Exact signed distances (negative inside) of an (N, 3) array of points to a scene or mesh file");
  static const std::string pipelineDoc =
      "Frames of the GPU SDF pipeline; settings (docs/settings.md): " + keywordsOf<PipelineSettings>() + ", device";
  py::class_<Pipeline>(m, "Pipeline", pipelineDoc.c_str())
      .def(py::init<const py::object&, int, double, const py::kwargs&>(), py::arg("scene"), py::arg("frames") = 60,
           py::arg("fps") = 30.0)
      .def("frame", &Pipeline::frame, py::arg("time"), "Run the frame at a time (seconds); returns its statistics")
      .def("fine", &Pipeline::fine, "The last frame's fine SDF as a Field");
}
