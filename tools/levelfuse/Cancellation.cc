#include "Cancellation.h"

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <cstring>

namespace levelfuse::cli {
namespace {
std::atomic<bool> gCancelled{false};
const char* gPhase = "starting";
PhaseClock gClock;
extern "C" void onSignal(int) { gCancelled.store(true); }
}  // namespace

void installCancellationHandlers() {
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
}

bool cancellationRequested() { return gCancelled.load(); }

Interrupter cancellationInterrupter() {
  return [] { return cancellationRequested(); };
}

void checkCancellation() {
  if (cancellationRequested()) throw Interrupted();
}

void enterPhase(const char* phase) {
  checkCancellation();
  gPhase = phase;
  gClock.enter(phase);
  const char* signalAt = std::getenv("LEVELFUSE_TEST_SIGNAL_AT");
  if (signalAt && std::strcmp(signalAt, phase) == 0) std::raise(SIGINT);
}

std::string currentPhase() { return gPhase; }

std::vector<PhaseTime> phaseTimes() {
  PhaseClock soFar = gClock;
  soFar.stop();
  return soFar.phases();
}

}  // namespace levelfuse::cli
