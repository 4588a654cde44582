// levelfuse: where a run's time goes, phase by phase.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace levelfuse {

/// The time one phase of a run took: wall time, and the CPU time of all the
/// process's threads in it (seconds).
struct PhaseTime {
  std::string name;
  double seconds = 0.0;
  double cpuSeconds = 0.0;
};

/// The CPU time of all the process's threads so far (user and system, seconds).
double processCpuSeconds();

/// Times the phases of a run, entered one after another: entering a phase
/// ends the one before. A phase entered again adds to its time, so the
/// phases are listed once each, in the order first entered.
class PhaseClock {
 public:
  /// Ends the current phase, if any, and starts `name`.
  void enter(const std::string& name);
  /// Ends the current phase, if any.
  void stop();
  /// The phases ended so far.
  const std::vector<PhaseTime>& phases() const { return mPhases; }

 private:
  using Clock = std::chrono::steady_clock;
  std::vector<PhaseTime> mPhases;
  std::string mCurrent;
  Clock::time_point mStart;
  double mCpuStart = 0.0;
};

}  // namespace levelfuse
