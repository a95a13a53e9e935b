#include "LongCall.h"

#include <tbb/task_arena.h>

#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "d2vdb/core/Error.h"

namespace d2vdb::python {

namespace {

// One arena per thread count, made on first use and kept: a new arena per call cost 25 ms of a
// 68 ms surface fit on two threads (its workers join it anew each time).
tbb::task_arena& arenaOf(int threads) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<tbb::task_arena>> arenas;
  const std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<tbb::task_arena>& arena = arenas[threads];
  if (!arena) arena = std::make_unique<tbb::task_arena>(threads);
  return *arena;
}

void runInArena(int threads, const std::function<void()>& work) {
  if (threads < 0) {
    throw InputError("threads must be 0 (all cores) or positive; got " + std::to_string(threads));
  }
  if (threads == 0) {
    work();
    return;
  }
  arenaOf(threads).execute(work);
}

// What the worker and the waiting thread share.
struct CallState {
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::atomic<bool> stop{false};
  std::exception_ptr failure;
  // The Python exception of a progress callable that raised (restored on the calling thread).
  std::unique_ptr<py::error_already_set> callbackError;
};

}  // namespace

void runWithoutGil(int threads, const std::function<void()>& work) {
  const py::gil_scoped_release release;
  runInArena(threads, work);
}

void runLongCall(const py::object& progress, int threads,
                 const std::function<void(const ProgressCallback&)>& work) {
  if (!progress.is_none() && !PyCallable_Check(progress.ptr())) {
    throw InputError("progress must be None or a callable(stage, fraction)");
  }
  auto state = std::make_shared<CallState>();
  const ProgressCallback report = [state, &progress](std::string_view stage, double fraction) {
    if (state->stop.load()) throw CallStopped();
    if (progress.is_none()) return;
    const py::gil_scoped_acquire acquire;
    try {
      progress(std::string(stage), fraction);
    } catch (py::error_already_set& error) {
      state->callbackError = std::make_unique<py::error_already_set>(std::move(error));
      state->stop.store(true);
      throw CallStopped();
    }
  };

  bool interrupted = false;
  {
    const py::gil_scoped_release release;
    std::thread worker([&] {
      try {
        runInArena(threads, [&] { work(report); });
      } catch (...) {
        state->failure = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(state->mutex);
      state->done = true;
      state->finished.notify_all();
    });
    std::unique_lock<std::mutex> lock(state->mutex);
    while (!state->finished.wait_for(lock, std::chrono::milliseconds(50),
                                     [&] { return state->done; })) {
      lock.unlock();
      if (!interrupted) {
        const py::gil_scoped_acquire acquire;
        if (PyErr_CheckSignals() != 0) {
          interrupted = true;  // the Python error (KeyboardInterrupt) stays set
          state->stop.store(true);
        }
      }
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (interrupted) throw py::error_already_set();
  if (state->callbackError) {
    const std::unique_ptr<py::error_already_set> error = std::move(state->callbackError);
    error->restore();
    throw py::error_already_set();
  }
  if (state->failure) std::rethrow_exception(state->failure);
}

}  // namespace d2vdb::python
