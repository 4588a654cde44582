// levelfuse CLI: cooperative cancellation on SIGINT and SIGTERM, phase by phase.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/core/PhaseClock.h>

#include <string>
#include <vector>

namespace levelfuse::cli {

/// Installs handlers that turn SIGINT/SIGTERM into a cancellation request:
/// first thing in main, so that a request before the work starts is kept
/// (before it, the signal's default action ends the process). A signal the
/// process began with ignored stays ignored.
void installCancellationHandlers();
/// True once SIGINT or SIGTERM arrived; long loops check it and stop cleanly.
bool cancellationRequested();
/// An Interrupter for the library's long loops: asks cancellationRequested().
Interrupter cancellationInterrupter();
/// Throws levelfuse::Interrupted if a cancellation was requested.
void checkCancellation();

/// Marks the start of a phase of a command ("loading", "solving" (the linear
/// solution), "evolving", "measuring", "meshing", "scanning", "reading",
/// "writing"): throws
/// Interrupted if a cancellation is pending, then makes `phase` the current one.
///
/// Test hook: if the environment variable LEVELFUSE_TEST_SIGNAL_AT names this
/// phase, the process sends itself SIGINT here, so that the phase runs with a
/// cancellation pending; tests/cli use it to interrupt each phase
/// deterministically.
void enterPhase(const char* phase);
/// The phase entered last ("starting" before any).
std::string currentPhase();
/// The time each phase entered so far took, the current one's up to now.
std::vector<PhaseTime> phaseTimes();

}  // namespace levelfuse::cli
