// levelfuse: the readers' memory check. Readers estimate the memory an input
// needs from the sizes it declares (and from the file's size) before they
// allocate, and refuse inputs that would not fit in the budget they are given
// (ScanLoadOptions::memoryBudget) with an InputError that says what to change,
// instead of dying for lack of memory half way through.
#pragma once

#include <levelfuse/core/MemoryBudget.h>

#include <string>

namespace levelfuse::io {

/// Throws InputError(file, budget.shortfall(bytes, what, advice)) if `bytes`
/// exceed `budget`.
void requireMemory(const MemoryBudget& budget, const std::string& file, double bytes, const std::string& what,
                   const std::string& advice);

}  // namespace levelfuse::io
