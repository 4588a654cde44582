// levelfuse: stopping long work from outside (a signal, a user, a deadline).
#pragma once

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

}  // namespace levelfuse
