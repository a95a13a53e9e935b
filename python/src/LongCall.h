// Running a long engine call from Python: without the GIL, on `threads` TBB threads, with an
// optional progress callable and Ctrl-C (KeyboardInterrupt) honoured within a fraction of a second
// wherever the engine reports progress.
#pragma once

#include <pybind11/pybind11.h>

#include <atomic>
#include <exception>
#include <functional>
#include <memory>
#include <optional>

#include "d2vdb/core/Progress.h"

namespace d2vdb::python {

namespace py = pybind11;

/// Thrown through the engine from its progress callback when the call is to stop (Ctrl-C, or the
/// Python progress callable raised); never escapes to Python.
class CallStopped : public std::exception {
 public:
  const char* what() const noexcept override { return "the call was interrupted"; }
};

/// Runs work(progress) on a worker thread inside a TBB arena of `threads` threads (0: all cores)
/// while the calling thread, holding the GIL only briefly, checks for signals every 50 ms.
/// `progress` (None or callable(stage: str, fraction: float)) is called with the GIL held. On
/// Ctrl-C, or when the callable raises, the engine is stopped at its next progress report and the
/// Python exception (KeyboardInterrupt, or the callable's) is raised here; engine exceptions are
/// rethrown as they are (the module translates them). Outputs are written atomically by the
/// engine, so a stopped call leaves no half-written file.
void runLongCall(const py::object& progress, int threads,
                 const std::function<void(const ProgressCallback&)>& work);

/// runLongCall() returning work's value.
template <typename Result, typename Work>
Result runLong(const py::object& progress, int threads, Work&& work) {
  std::optional<Result> result;
  runLongCall(progress, threads,
              [&](const ProgressCallback& report) { result.emplace(work(report)); });
  return std::move(*result);
}

/// Runs work() without the GIL in a TBB arena of `threads` threads (short calls: no worker
/// thread, no progress).
void runWithoutGil(int threads, const std::function<void()>& work);

}  // namespace d2vdb::python
