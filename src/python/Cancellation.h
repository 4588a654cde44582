// levelfuse Python module: long work with the GIL released, stopped by Ctrl-C
// or by a progress callback, which Python sees as KeyboardInterrupt, as the
// callback's own exception, or as levelfuse.Cancelled.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/recon/Reconstructor.h>

#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstddef>
#include <optional>
#include <string>

namespace levelfuse::python {

namespace py = pybind11;

/// While it lives, on Python's main thread, SIGINT (Ctrl-C) sets a flag that
/// the work's interrupter reads instead of running Python's handler, which
/// cannot run while the work holds no GIL; Python's handler is back when it
/// ends. Construct and destroy with the GIL held.
class Cancellation {
 public:
  Cancellation();
  ~Cancellation();
  Cancellation(const Cancellation&) = delete;
  Cancellation& operator=(const Cancellation&) = delete;

  /// Asked by the work, from any thread: a signal came or stop() was called.
  Interrupter interrupter() const;
  bool stopped() const;
  /// Stops the work (a progress callback said so).
  void stop() { mStopped.store(true); }
  /// After the work stopped: Python's SIGINT handler (KeyboardInterrupt by
  /// default) is run as if the signal had come now, and its exception thrown.
  void raiseIfSignalled();

 private:
  bool mInstalled = false;
  struct sigaction mPrevious {};
  std::atomic<bool> mStopped{false};
};

/// A Python progress callable, called with the GIL held at most five times a
/// second, and at the start of each stage, with a dict of where the work is.
/// It stops the work by returning False or raising; its exception is kept and
/// raised once the work has stopped.
class ProgressRelay {
 public:
  ProgressRelay(py::object callback, Cancellation& cancellation)
      : mCallback(std::move(callback)), mCancellation(cancellation) {}
  /// For Reconstructor::run: false stops it.
  bool report(const ReconstructionProgress& progress);
  /// For loading and integrating: `done` of `total` items of `stage`.
  void count(const char* stage, std::size_t done, std::size_t total);
  /// Raises the callback's exception, if it raised one.
  void rethrowCallbackError();

 private:
  /// Calls the callback with `progress` (GIL held) unless one was called
  /// within the last 0.2 s in the same stage; stops the work if it says so.
  void deliver(const char* stage, const std::function<py::dict()>& progress);

  py::object mCallback;
  Cancellation& mCancellation;
  std::optional<std::chrono::steady_clock::time_point> mLast;
  std::string mStage;
  std::optional<py::error_already_set> mError;
};

/// Runs `work` with the GIL released. If it stops (Interrupted), the
/// callback's exception is raised, else KeyboardInterrupt after Ctrl-C, else
/// levelfuse.Cancelled.
template <typename Work>
auto runReleased(Cancellation& cancellation, ProgressRelay* relay, Work&& work) -> decltype(work()) {
  try {
    py::gil_scoped_release released;
    return work();
  } catch (const Interrupted&) {
    if (relay) relay->rethrowCallbackError();
    cancellation.raiseIfSignalled();
    throw;
  }
}

}  // namespace levelfuse::python
