#pragma once
// What the binding files of the Python module share: how a Python argument becomes a scene, the Field a bake
// returns, keyword settings onto the knob tables, and the control of a long call (Ctrl-C, progress).
#include "grid/GridSpec.h"
#include "grid/VdbIO.h"
#include "scene/Scene.h"
#include "sdf/pipeline/FrameStats.h"
#include "util/JobControl.h"
#include "util/Knobs.h"
#include "util/Length.h"
#include "util/EnumNames.h"

#include <openvdb/openvdb.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace rtsdf {
class SdfPipeline;
}

namespace rtsdf::python {

namespace py = pybind11;

/// A scene in memory, shared by the objects made from it (a Pipeline keeps its scene alive).
using ScenePtr = std::shared_ptr<const Scene>;

/// rtsdf.Mesh: triangles handed over as arrays, validated and oriented as a mesh file's (sceneFromMesh).
struct ArrayMesh {
  ScenePtr scene;
};

/// The scene an argument names: an rtsdf.Scene, an rtsdf.Mesh, or a path (str or os.PathLike) to load.
/// @throw py::type_error for anything else, naming @a argument.
ScenePtr sceneOf(const py::handle& sceneOrPath, const char* argument = "scene");

/// A baked field: the level set with its voxels.
struct Field {
  openvdb::FloatGrid::Ptr grid;
  GridSpec spec;
  double band = 0.0;
  std::string method; ///< what made it: a bake method, "pipeline", or "file" (read from a .vdb)
  UpAxis up = UpAxis::Y; ///< how write() turns the file it writes (bake's up=, as the command line's --up)
};

/// The keyword settings of bake() and Pipeline() onto the pipeline's (and a bake's) knobs, by the keywords of
/// their tables (docs/settings.md); "device" into @a device where given; unknown keys refused.
template <class... Structs> void applySettings(const py::kwargs& kw, std::string* device, Structs&... structs);

/// The setting (SettingError::setting(), the knob tables' name) of the Python keyword @a keyword in @a structs'
/// tables; "" where none has it.
template <class... Structs> std::string settingOfKeyword(const std::string& keyword, Structs&... structs) {
  std::string setting;
  const auto name = [&](const auto& k, auto&) { setting = k.setting; };
  (visitKnobByKeyword(structs, keyword, name) || ...);
  return setting;
}

/// Refuse the first keyword of @a kw whose setting (in @a structs' tables) the job would ignore: @a ignores(setting)
/// says why ("" where it acts), as the command line's refuseIgnoredFlags does for flags.
/// @throw py::value_error "<keyword>= <why>".
template <class Ignores, class... Structs>
void refuseIgnoredKeywords(const py::kwargs& kw, const Ignores& ignores, Structs&... structs) {
  for (const auto& [key, value] : kw) {
    const std::string keyword = py::str(key);
    const std::string setting = settingOfKeyword(keyword, structs...);
    if (setting.empty()) continue;
    if (const std::string why = ignores(setting); !why.empty()) throw py::value_error(keyword + "= " + why);
  }
}

/// The keywords of S's table, "a, b, c".
template <class S> std::string keywordsOf() {
  std::string s;
  forEachKnob<S>([&](const auto& k) { s += (s.empty() ? "" : ", ") + keywordOf(k); });
  return s;
}

/// The JobControl of one long call from Python. The job runs without the GIL; its stop predicate, on the calling
/// thread at most every 100 ms, takes the GIL and runs Python's signal handlers (PyErr_CheckSignals), so Ctrl-C
/// stops it; progress goes to a Python callable(stage, fraction). The Python error that stopped the job (the
/// KeyboardInterrupt, or what the callable raised) is raised when the call returns.
class PythonJob {
public:
  /// @param progress None or a callable(stage: str, fraction: float).
  explicit PythonJob(py::object progress);
  PythonJob(const PythonJob&) = delete;
  PythonJob& operator=(const PythonJob&) = delete;

  const JobControl& control() const { return mControl; }

  /// Run @a job (a call into the library taking control()) without the GIL; raise the Python error that stopped it.
  template <class F> auto run(F&& job) -> decltype(job()) {
    std::optional<decltype(job())> result;
    try {
      py::gil_scoped_release release;
      result.emplace(job());
    } catch (...) {
      raisePending();
      throw;
    }
    raisePending(); // a signal seen on the last poll of a job that then finished
    return std::move(*result);
  }

private:
  bool stopRequested();
  void report(const std::string& stage, std::uint64_t done, std::uint64_t total);
  void keepError(); ///< the current Python error, kept (the first one) to raise later; the job is asked to stop
  void raisePending();

  py::object mProgress;
  std::thread::id mCaller = std::this_thread::get_id();
  std::chrono::steady_clock::time_point mLastCheck = std::chrono::steady_clock::now();
  std::atomic<bool> mStop{false};
  std::mutex mErrorMutex;
  std::unique_ptr<py::error_already_set> mError;
  JobControl mControl;
};

/// The last frame's fine SDF of @a pipe as a Field: its refined voxels within the band (a voxel where d = 0), made by
/// @a method.
Field pipelineField(const SdfPipeline& pipe, const char* method);

/// One pipeline frame's statistics as Pipeline.frame() returns them: time, mask_voxels, refined_voxels, cut_voxels,
/// moved_kept_voxels, near_half_voxels, near_half_kept, host_ms, wall_ms, pass_ms (per pass).
py::dict frameStatsDict(const FrameStats& stats);

void bindScenes(py::module_& m);
void bindFields(py::module_& m);
void bindJobs(py::module_& m);
void bindCascades(py::module_& m);

// ---------------------------------------------------------------------------------------------------------------

/// Sets the member of the knob named by a Python keyword (util/Knobs.h) from a Python value.
/// @brief A length from Python: a number (scene units) or a string such as "3vox" (util/Length.h).
/// @throw py::value_error naming the text when it is not a length.
inline Length lengthOf(const py::handle& value) {
  if (!py::isinstance<py::str>(value)) return Length(value.cast<double>());
  const std::string text = value.cast<std::string>();
  if (const std::optional<Length> l = Length::parse(text)) return *l;
  throw py::value_error("'" + text + "' is not a length (" + std::string(kLengthSyntax) + ")");
}

struct SetFromPython {
  const py::handle& value;
  template <class K, class T> void operator()(const K&, T& member) const {
    if constexpr (IsNamedEnum<T>::value) member = parseEnum<T>(value.cast<std::string>());
    else if constexpr (std::is_same_v<T, Length>) member = lengthOf(value);
    else member = value.cast<T>();
  }
};

template <class... Structs> void applySettings(const py::kwargs& kw, std::string* device, Structs&... structs) {
  for (const auto& [key, value] : kw) {
    const std::string k = py::str(key);
    const SetFromPython set{value};
    if ((visitKnobByKeyword(structs, k, set) || ...)) continue;
    if (device && k == "device") *device = py::cast<std::string>(value);
    else throw py::type_error("unknown setting '" + k + "'");
  }
}

} // namespace rtsdf::python
