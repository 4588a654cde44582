// levelfuse: the readers' memory check.

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/MemoryBudget.h>

namespace levelfuse::io {

void requireMemory(const MemoryBudget& budget, const std::string& file, double bytes, const std::string& what,
                   const std::string& advice) {
  const std::string shortfall = budget.shortfall(bytes, what, advice);
  if (!shortfall.empty()) throw InputError(file, shortfall);
}

}  // namespace levelfuse::io
