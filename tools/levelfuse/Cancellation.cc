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

/// Makes `signal` a cancellation request, unless the process began with it
/// ignored: a command that a non-interactive shell runs in the background
/// starts with SIGINT ignored, and keeps ignoring it from its first moment to
/// its last, as POSIX shells intend (no handler could catch what arrives
/// before it is installed, so honouring the later ones would be a lottery).
void takeOver(int signal) {
  struct sigaction current {};
  if (sigaction(signal, nullptr, &current) != 0 || current.sa_handler == SIG_IGN) return;
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  sigaction(signal, &action, nullptr);
}
}  // namespace

void installCancellationHandlers() {
  takeOver(SIGINT);
  takeOver(SIGTERM);
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
