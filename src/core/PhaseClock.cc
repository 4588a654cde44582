// levelfuse: where a run's time goes, phase by phase.

#include <levelfuse/core/PhaseClock.h>

#include <sys/resource.h>

#include <algorithm>

namespace levelfuse {

double processCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

void PhaseClock::enter(const std::string& name) {
  stop();
  mCurrent = name;
  mStart = Clock::now();
  mCpuStart = processCpuSeconds();
}

void PhaseClock::stop() {
  if (mCurrent.empty()) return;
  const double seconds = std::chrono::duration<double>(Clock::now() - mStart).count();
  const double cpuSeconds = processCpuSeconds() - mCpuStart;
  auto phase = std::find_if(mPhases.begin(), mPhases.end(), [&](const PhaseTime& p) { return p.name == mCurrent; });
  if (phase == mPhases.end()) phase = mPhases.insert(mPhases.end(), PhaseTime{mCurrent, 0.0, 0.0});
  phase->seconds += seconds;
  phase->cpuSeconds += cpuSeconds;
  mCurrent.clear();
}

}  // namespace levelfuse
