// Ctrl-C and progress for long calls from Python (Bindings.h: PythonJob).
#include "Bindings.h"

namespace rtsdf::python {

PythonJob::PythonJob(py::object progress) : mProgress(std::move(progress)) {
  if (!mProgress.is_none() && !PyCallable_Check(mProgress.ptr()))
    throw py::type_error("progress must be a callable(stage, fraction) or None");
  mControl.stopRequested = [this] { return stopRequested(); };
  if (!mProgress.is_none())
    mControl.progress = [this](const std::string& stage, std::uint64_t done, std::uint64_t total) {
      report(stage, done, total);
    };
}

bool PythonJob::stopRequested() {
  if (mStop.load(std::memory_order_relaxed)) return true;
  // Python runs signal handlers on its main thread only: the caller's thread polls, every 100 ms at most (a poll
  // takes the GIL); worker threads read the flag.
  if (std::this_thread::get_id() != mCaller) return false;
  const auto now = std::chrono::steady_clock::now();
  if (now - mLastCheck < std::chrono::milliseconds(100)) return false;
  mLastCheck = now;
  const py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0) keepError();
  return mStop.load();
}

void PythonJob::report(const std::string& stage, std::uint64_t done, std::uint64_t total) {
  if (mStop.load(std::memory_order_relaxed)) return;
  const py::gil_scoped_acquire gil;
  try {
    mProgress(stage, total ? double(done) / double(total) : 1.0);
  } catch (py::error_already_set& e) {
    e.restore();
    keepError();
  }
}

void PythonJob::keepError() {
  const std::lock_guard<std::mutex> lock(mErrorMutex);
  if (!mError) mError = std::make_unique<py::error_already_set>();
  else PyErr_Clear();
  mStop = true;
}

void PythonJob::raisePending() {
  std::unique_ptr<py::error_already_set> error;
  {
    const std::lock_guard<std::mutex> lock(mErrorMutex);
    error = std::move(mError);
  }
  if (error) throw py::error_already_set(*error);
}

} // namespace rtsdf::python
