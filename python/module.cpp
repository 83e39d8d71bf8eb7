// The Python module `rtsdf` (pybind11): scenes and meshes from arrays, bakes as Fields (numpy arrays, samples,
// gradients), exact point distances and pipeline frames, each one call into the library. The bindings live by
// concern in SceneBindings.cpp, FieldBindings.cpp and JobBindings.cpp; docs/python.md shows a session.
#include "Bindings.h"

#include "util/Error.h"
#include "util/Log.h"

namespace py = pybind11;
using namespace rtsdf;

void bindBatch(py::module_& m); // batch.cpp

PYBIND11_MODULE(_rtsdf, m) {
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
  error.doc() = "Bad input or a failed job: the message names the file, key or setting and the problem";
  settingError.doc() = "A setting out of range or not known: the message names it";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Interrupted&) {
      PyErr_SetNone(PyExc_KeyboardInterrupt);
    } catch (const SettingError& e) {
      settingError(e.what());
    } catch (const Error& e) {
      error(e.what());
    }
  });
  python::bindScenes(m);
  python::bindFields(m);
  python::bindJobs(m);
  python::bindCascades(m);
  bindBatch(m);
}
