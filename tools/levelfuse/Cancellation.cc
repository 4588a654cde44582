#include "Cancellation.h"

#include <atomic>
#include <csignal>

namespace levelfuse::cli {
namespace {
std::atomic<bool> gCancelled{false};
extern "C" void onSignal(int) { gCancelled.store(true); }
}  // namespace

void installCancellationHandlers() {
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
}

bool cancellationRequested() { return gCancelled.load(); }

}  // namespace levelfuse::cli
