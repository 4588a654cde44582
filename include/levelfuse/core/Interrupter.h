// levelfuse: stopping long work from outside (a signal, a user, a deadline).
#pragma once

#include <atomic>
#include <functional>
#include <stdexcept>
#include <string>

namespace levelfuse {

/// Asked now and then by long loops, from any thread: true means stop. It must
/// be cheap and thread-safe (typically the load of an atomic flag).
using Interrupter = std::function<bool()>;

/// Thrown by work that an Interrupter stopped; it leaves no partial result.
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(const std::string& what = "interrupted") : std::runtime_error(what) {}
};

/// Throws Interrupted if `interrupter` is set and asks to stop.
inline void checkInterrupter(const Interrupter& interrupter) {
  if (interrupter && interrupter()) throw Interrupted();
}

/// An interrupter asked from the tasks of a parallel loop. Once it says stop,
/// the remaining tasks skip their work, and the loop's caller throws after the
/// loop (throwIfStopped). A task must not throw itself: that cancels TBB's task
/// group, and with it the parallel loops OpenVDB runs inside the other tasks'
/// work (a tree's destructor frees its nodes in one), leaking what they hold.
class ParallelInterrupt {
 public:
  explicit ParallelInterrupt(const Interrupter& interrupter) : mInterrupter(interrupter) {}
  /// True once the interrupter has asked to stop.
  bool stop() const {
    if (mStopped.load(std::memory_order_relaxed)) return true;
    if (!mInterrupter || !mInterrupter()) return false;
    mStopped.store(true, std::memory_order_relaxed);
    return true;
  }
  /// Throws Interrupted if some task was told to stop.
  void throwIfStopped() const {
    if (mStopped.load()) throw Interrupted();
  }

 private:
  const Interrupter& mInterrupter;
  mutable std::atomic<bool> mStopped{false};
};

}  // namespace levelfuse
