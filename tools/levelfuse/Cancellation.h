// levelfuse CLI: cooperative cancellation on SIGINT and SIGTERM.
#pragma once

namespace levelfuse::cli {

/// Installs handlers that turn SIGINT/SIGTERM into a cancellation request.
void installCancellationHandlers();
/// True once SIGINT or SIGTERM arrived; long loops check it and stop cleanly.
bool cancellationRequested();

}  // namespace levelfuse::cli
