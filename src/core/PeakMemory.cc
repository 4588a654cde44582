#include <levelfuse/core/PeakMemory.h>

#include <sys/resource.h>

namespace levelfuse {

std::size_t peakResidentBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // kilobytes on Linux
}

}  // namespace levelfuse
