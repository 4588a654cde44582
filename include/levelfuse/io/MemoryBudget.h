// levelfuse: how much memory the readers may use.
//
// Readers estimate the memory an input needs from the sizes it declares (and
// from the file's size) before they allocate, and refuse inputs that would not
// fit with an InputError that says what to change, instead of dying for lack
// of memory half way through.
#pragma once

#include <cstdint>
#include <string>

namespace levelfuse::io {

/// Bytes the readers may allocate: the budget set with setMemoryBudget(), or
/// else the machine's physical memory (or the process's address-space or data
/// limit, if lower).
std::uint64_t memoryBudget();

/// Sets the budget in bytes (0 restores the automatic one); for all threads.
void setMemoryBudget(std::uint64_t bytes);

/// "512 MiB", "1.5 GiB": a size in bytes for people.
std::string describeBytes(double bytes);

/// "<what> needs about X of memory, more than the Y levelfuse may use:
/// <advice>" if `bytes` exceeds memoryBudget(); empty if they fit.
std::string memoryShortfall(double bytes, const std::string& what, const std::string& advice);

/// Throws InputError(file, memoryShortfall(bytes, what, advice)) if `bytes`
/// exceeds memoryBudget().
void requireMemory(const std::string& file, double bytes, const std::string& what, const std::string& advice);

}  // namespace levelfuse::io
