// levelfuse: the one place where levelfuse's own parallel loops are dispatched.
//
// parallelFor(n, grain, body) runs body(begin, end) over [0, n) in chunks,
// with TBB. A grain of 0 runs serially: one switch for debugging and
// determinism checks. Under ThreadSanitizer, whose view of synchronisation
// inside the (uninstrumented) TBB library is blind, the chunks run on plain
// std::threads (at least two, whatever TBB is limited to) that are joined at
// the end, so TSan sees the fork and the join and checks levelfuse's own code
// for races. The TSan test runs limit TBB itself to one thread, so that
// OpenVDB's internal parallel algorithms, whose synchronisation TSan cannot
// see, run on the calling thread.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

#if defined(__SANITIZE_THREAD__)
#define LEVELFUSE_THREAD_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define LEVELFUSE_THREAD_SANITIZER 1
#endif
#endif

namespace levelfuse {

/// How many items (frames, maps) a pass that prepares them in parallel and
/// hands them on in order holds at once: twice as many as there are threads.
inline std::size_t itemsInFlight() {
  return 2 * static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
}

template <typename Body>
void parallelFor(std::size_t n, std::size_t grain, const Body& body) {
  if (n == 0) return;
  if (grain == 0) {
    body(std::size_t(0), n);
    return;
  }
#if defined(LEVELFUSE_THREAD_SANITIZER)
  const std::size_t threads = std::max<std::size_t>(
      1, std::min<std::size_t>(std::max(2u, std::min(4u, std::thread::hardware_concurrency())), (n + grain - 1) / grain));
  const std::size_t chunk = (n + threads - 1) / threads;
  std::vector<std::thread> workers;
  for (std::size_t t = 1; t < threads; ++t)
    workers.emplace_back([&, t] { body(std::min(n, t * chunk), std::min(n, (t + 1) * chunk)); });
  body(std::size_t(0), std::min(n, chunk));
  for (std::thread& w : workers) w.join();
#else
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                    [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
#endif
}

}  // namespace levelfuse
