// levelfuse: how much memory the readers may use.

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/MemoryBudget.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>

namespace levelfuse::io {

namespace {

std::atomic<std::uint64_t> gBudget{0};

std::uint64_t limitOf(int resource) {
  rlimit limit{};
  if (getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return UINT64_MAX;
  return static_cast<std::uint64_t>(limit.rlim_cur);
}

std::uint64_t automaticBudget() {
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
  const std::uint64_t physical =
      pages > 0 && pageSize > 0 ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(pageSize) : UINT64_MAX;
  return std::min({physical, limitOf(RLIMIT_AS), limitOf(RLIMIT_DATA)});
}

}  // namespace

std::uint64_t memoryBudget() {
  const std::uint64_t set = gBudget.load(std::memory_order_relaxed);
  return set != 0 ? set : automaticBudget();
}

void setMemoryBudget(std::uint64_t bytes) { gBudget.store(bytes, std::memory_order_relaxed); }

std::string describeBytes(double bytes) {
  static const char* const kUnits[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int unit = 0;
  while (bytes >= 1024.0 && unit < 6) {
    bytes /= 1024.0;
    ++unit;
  }
  char text[64];
  std::snprintf(text, sizeof(text), unit == 0 ? "%.0f %s" : "%.3g %s", bytes, kUnits[unit]);
  return text;
}

std::string memoryShortfall(double bytes, const std::string& what, const std::string& advice) {
  const double budget = static_cast<double>(memoryBudget());
  if (bytes <= budget) return {};
  return what + " needs about " + describeBytes(bytes) + " of memory, more than the " + describeBytes(budget) +
         " levelfuse may use: " + advice;
}

void requireMemory(const std::string& file, double bytes, const std::string& what, const std::string& advice) {
  const std::string shortfall = memoryShortfall(bytes, what, advice);
  if (!shortfall.empty()) throw InputError(file, shortfall);
}

}  // namespace levelfuse::io
