// levelfuse Python module: Ctrl-C and progress callbacks during long work.

#include "Cancellation.h"

#include <pybind11/stl.h>

#include <csignal>
#include <cstdlib>
#include <cstring>

namespace levelfuse::python {
namespace {

std::atomic<bool> gSignalled{false};
std::atomic<int> gScopes{0};

extern "C" void onInterrupt(int) { gSignalled.store(true); }

bool onMainThread() {
  const py::module_ threading = py::module_::import("threading");
  return threading.attr("current_thread")().is(threading.attr("main_thread")());
}

const char* stageName(ReconstructionProgress::Stage stage) {
  switch (stage) {
    case ReconstructionProgress::Stage::kInitialModel: return "initial model";
    case ReconstructionProgress::Stage::kIntegrating: return "integrating";
    case ReconstructionProgress::Stage::kEvolving: return "evolving";
    case ReconstructionProgress::Stage::kResampling: return "resampling";
    case ReconstructionProgress::Stage::kDone: return "done";
  }
  return "";
}

}  // namespace

Cancellation::Cancellation() {
  // Only the outermost scope on the main thread takes SIGINT over.
  if (gScopes.fetch_add(1) != 0 || !onMainThread()) return;
  gSignalled.store(false);
  // Test hook: Ctrl-C just before the work takes SIGINT over (tests/python).
  if (std::getenv("LEVELFUSE_TEST_SIGNAL_BEFORE_WORK")) std::raise(SIGINT);
  struct sigaction action {};
  action.sa_handler = onInterrupt;
  sigemptyset(&action.sa_mask);
  mInstalled = sigaction(SIGINT, &action, &mPrevious) == 0;
  // A Ctrl-C that came before the handler above, while Python held it, waits
  // for Python's next bytecode, after the work: it is raised now, before the work.
  if (PyErr_CheckSignals() != 0) {
    if (mInstalled) sigaction(SIGINT, &mPrevious, nullptr);
    gScopes.fetch_sub(1);
    throw py::error_already_set();
  }
}

Cancellation::~Cancellation() {
  if (mInstalled) sigaction(SIGINT, &mPrevious, nullptr);
  gScopes.fetch_sub(1);
}

bool Cancellation::stopped() const { return mStopped.load() || (mInstalled && gSignalled.load()); }

Interrupter Cancellation::interrupter() const {
  return [this] { return stopped(); };
}

void Cancellation::raiseIfSignalled() {
  if (!mInstalled || !gSignalled.exchange(false)) return;
  sigaction(SIGINT, &mPrevious, nullptr);
  mInstalled = false;
  PyErr_SetInterrupt();
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

bool ProgressRelay::report(const ReconstructionProgress& p) {
  if (!mCallback.is_none()) {
    deliver(stageName(p.stage), 
        [&p] {
          py::dict d;
          d["stage"] = stageName(p.stage);
          d["scan"] = p.scan;
          d["scans"] = p.scans;
          d["level"] = p.level;
          d["levels"] = p.levels;
          d["voxel_size"] = p.voxelSize;
          d["iteration"] = p.iteration;
          d["max_iterations"] = p.maxIterations;
          d["active_set_voxels"] = p.activeSetVoxels;
          d["speed"] = p.speed;
          d["drift"] = p.drift;
          d["seconds"] = p.seconds;
          return d;
        });
  }
  return !mCancellation.stopped();
}

void ProgressRelay::count(const char* stage, std::size_t done, std::size_t total) {
  if (mCallback.is_none()) return;
  deliver(stage, [&] {
    py::dict d;
    d["stage"] = stage;
    d["done"] = done;
    d["total"] = total;
    return d;
  });
}

void ProgressRelay::deliver(const char* stage, const std::function<py::dict()>& progress) {
  const auto now = std::chrono::steady_clock::now();
  const bool newStage = mStage != stage;
  if (!newStage && mLast && now - *mLast < std::chrono::milliseconds(200)) return;
  if (mCancellation.stopped()) return;
  mLast = now;
  mStage = stage;
  py::gil_scoped_acquire held;
  try {
    const py::object answer = mCallback(progress());
    if (answer.is(py::bool_(false))) mCancellation.stop();
  } catch (py::error_already_set& e) {
    mError.emplace(std::move(e));
    mCancellation.stop();
  }
}

void ProgressRelay::rethrowCallbackError() {
  if (!mError) return;
  py::error_already_set error = std::move(*mError);
  mError.reset();
  throw error;
}

}  // namespace levelfuse::python
