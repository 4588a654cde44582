// levelfuse: how much memory levelfuse may use.
//
// Readers and the reconstruction estimate the memory a stage needs before
// they allocate, and refuse what would not fit with a message that says what
// to change, instead of dying for lack of memory half way through. The budget
// is a setting like any other, passed in: ScanLoadOptions for the readers,
// ReconstructionOptions for the reconstruction.
#pragma once

#include <cstdint>
#include <string>

namespace levelfuse {

class MemoryBudget {
 public:
  /// The machine's: its physical memory, or the process's address-space or
  /// data limit if lower.
  MemoryBudget() = default;
  /// `bytes`; 0 is the machine's.
  explicit MemoryBudget(std::uint64_t bytes) : mGiven(bytes) {}

  /// The bytes levelfuse may use.
  std::uint64_t bytes() const;
  /// Set by whoever runs levelfuse, not the machine's.
  bool given() const { return mGiven != 0; }

  /// "<what> needs about X of memory, more than the Y levelfuse may use:
  /// <advice>" if `bytes` exceed the budget; empty if they fit.
  std::string shortfall(double bytes, const std::string& what, const std::string& advice) const;

 private:
  std::uint64_t mGiven = 0;
};

/// "512 MiB", "1.5 GiB": a size in bytes for people.
std::string describeBytes(double bytes);

}  // namespace levelfuse
