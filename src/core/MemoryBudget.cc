// levelfuse: how much memory levelfuse may use.

#include <levelfuse/core/MemoryBudget.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace levelfuse {

namespace {

std::uint64_t limitOf(int resource) {
  rlimit limit{};
  if (getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return UINT64_MAX;
  return static_cast<std::uint64_t>(limit.rlim_cur);
}

std::uint64_t machineBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
  const std::uint64_t physical =
      pages > 0 && pageSize > 0 ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(pageSize) : UINT64_MAX;
  return std::min({physical, limitOf(RLIMIT_AS), limitOf(RLIMIT_DATA)});
}

}  // namespace

std::uint64_t MemoryBudget::bytes() const { return given() ? mGiven : machineBytes(); }

std::string MemoryBudget::shortfall(double bytes, const std::string& what, const std::string& advice) const {
  const double budget = static_cast<double>(this->bytes());
  if (bytes <= budget) return {};
  return what + " needs about " + describeBytes(bytes) + " of memory, more than the " + describeBytes(budget) +
         " levelfuse may use: " + advice;
}

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

}  // namespace levelfuse
