// Sets the readers' memory budget for one scope of a test; the automatic
// budget is back after it.
#pragma once

#include <levelfuse/io/MemoryBudget.h>

#include <cstdint>

namespace levelfuse::test {

class MemoryBudgetScope {
 public:
  explicit MemoryBudgetScope(std::uint64_t bytes) { io::setMemoryBudget(bytes); }
  ~MemoryBudgetScope() { io::setMemoryBudget(0); }
  MemoryBudgetScope(const MemoryBudgetScope&) = delete;
  MemoryBudgetScope& operator=(const MemoryBudgetScope&) = delete;
};

}  // namespace levelfuse::test
