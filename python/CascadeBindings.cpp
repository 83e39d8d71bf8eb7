// Cascades: camera-centred levels that follow a camera, each one call into the library, without the GIL.
#include "Bindings.h"

#include "gpu/VulkanContext.h"
#include "jobs/CascadeBake.h"
#include "jobs/JobSupport.h"
#include "jobs/SettingUse.h"
#include "scene/SceneGeometry.h"
#include "sdf/cascade/CascadeSet.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <array>

namespace rtsdf::python {
namespace {

glm::dvec3 toVec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

/// K levels around a camera that moves (CascadeSet): move_to() scrolls the levels whose box moved, frame() runs every
/// level's frame.
class Cascades {
public:
  Cascades(const py::handle& sceneOrPath, const std::optional<std::array<double, 3>>& camera, double time,
           const py::kwargs& kw)
      : mScene(sceneOf(sceneOrPath)) {
    PipelineSettings s;
    std::string device;
    applySettings(kw, &device, s);
    refuseIgnoredKeywords(kw, [&s](const std::string& setting) { return pipelineIgnores(s, setting); }, s);
    if (s.cascades < 2) throw SettingError("cascades", "rtsdf.Cascades needs cascades >= 2 (one box: rtsdf.Pipeline)");
    const glm::dvec3 centre = camera ? toVec(*camera) : cascadeCentre(*mScene, time);
    const CascadeShape shape = cascadeShapeFor(buildSceneGeometry(*mScene, time).bounds, centre, s);
    mCtx = std::make_unique<gpu::VulkanContext>(deviceContextOptions(device));
    mSet = std::make_unique<CascadeSet>(*mCtx, *mScene, CascadeLayout::around(centre, shape), s);
  }
  py::dict moveTo(const std::array<double, 3>& camera, const std::array<double, 3>& lookAhead,
                  const std::optional<std::array<double, 3>>& target, double fov, double aspect) {
    CascadeMove move;
    Camera eye;
    eye.position = toVec(camera);
    if (target) {
      eye.target = toVec(*target);
      eye.verticalFov = fov;
      viewReachOf(eye, aspect, 0.0); // refused before the levels move
    }
    {
      py::gil_scoped_release release;
      move = mSet->moveTo(eye.position, toVec(lookAhead));
      if (target) mSet->setView(eye, aspect);
    }
    py::dict d;
    d["moved"] = move.moved;
    d["recut"] = move.recut;
    d["rebuilt"] = move.rebuilt;
    return d;
  }
  py::list frame(double time) {
    std::vector<FrameStats> levels;
    {
      py::gil_scoped_release release;
      levels = mSet->runFrame(time);
    }
    if (mCtx->validationErrors()) throw Error(std::to_string(mCtx->validationErrors()) + " Vulkan validation errors");
    py::list out;
    for (const FrameStats& level : levels) out.append(frameStatsDict(level));
    return out;
  }
  Field level(int i) const {
    if (i < 0 || i >= mSet->levels())
      throw py::index_error(fmt::format("level {}: the cascades have {} levels", i, mSet->levels()));
    return pipelineField(mSet->level(i), "cascades");
  }
  std::string repr() const {
    const CascadeLayout& l = mSet->layout();
    return fmt::format("rtsdf.Cascades({} levels of coarse {} / fine {}, level 0 {:g} wide around ({:g}, {:g}, {:g}), "
                       "on {})", l.shape.levels, l.shape.coarseRes, l.shape.fineRes, l.shape.levelZeroExtent,
                       l.camera.x, l.camera.y, l.camera.z, mCtx->info().name);
  }
  int levels() const { return mSet->levels(); }
  std::uint64_t deviceBytes() const { return mCtx->deviceBytesInUse(); }

private:
  ScenePtr mScene;
  std::unique_ptr<gpu::VulkanContext> mCtx;
  std::unique_ptr<CascadeSet> mSet;
};

} // namespace

void bindCascades(py::module_& m) {
  static const std::string doc =
      "Camera-centred cascade levels of the GPU SDF pipeline on a scene, an rtsdf.Mesh or a scene/mesh path "
      "(docs/cascades.md): cascades=K levels (K >= 2) around `camera` (default: the scene camera at `time`, or the "
      "centre of the scene's bounds). Settings (docs/settings.md): " + keywordsOf<PipelineSettings>() + ", device";
  py::class_<Cascades>(m, "Cascades", doc.c_str())
      .def(py::init<const py::handle&, const std::optional<std::array<double, 3>>&, double, const py::kwargs&>(),
           py::arg("scene"), py::arg("camera") = py::none(), py::arg("time") = 0.0)
      .def("move_to", &Cascades::moveTo, py::arg("camera"), py::arg("look_ahead") = std::array<double, 3>{0, 0, 0},
           py::arg("target") = py::none(), py::arg("fov") = Camera{}.verticalFov, py::arg("aspect") = 16.0 / 9.0,
           "Centre the levels on a camera position (levels below the outermost on camera + look_ahead 2^i, each "
           "component of look_ahead clamped so that the levels nest). A level "
           "whose box moved scrolls: it keeps what it knows and the next frame refines what entered. With `target` "
           "(the point the camera looks at; `fov`: vertical field of view in radians, `aspect`: the image's width "
           "over height), levels above 0 refine only near that view (cascade_view_margin) from the next frame on. "
           "Returns a dict "
           "of level indices: moved, recut (scrolled with their part of the scene cut again), rebuilt (from scratch)")
      .def("frame", &Cascades::frame, py::arg("time"),
           "Run every level's frame at a time (seconds); returns each level's statistics, finest first (as "
           "Pipeline.frame)")
      .def("level", &Cascades::level, py::arg("index"), "Level `index`'s fine SDF as a Field (the refined voxels)")
      .def_property_readonly("levels", &Cascades::levels, "The number of levels")
      .def_property_readonly("device_bytes", &Cascades::deviceBytes,
                             "The device memory the levels hold, as allocated (buffers and textures, all levels)")
      .def("__repr__", &Cascades::repr);
}

} // namespace rtsdf::python
