// levelfuse: items made in parallel a batch ahead of a calling thread that
// takes them in order (frames read while the last ones are packed, packed
// maps unpacked while the last ones are visited).
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/core/Parallel.h>

#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <exception>
#include <optional>
#include <vector>

namespace levelfuse {

/// Makes `count` items of type T, make(i) the i-th, a batch of itemsInFlight()
/// at a time with parallelFor, and calls take(i, T&&) for each in order from
/// the calling thread, asking `interrupter` before each. While the calling
/// thread takes a batch, the other threads make the next: no more than two
/// batches exist at once. Of the items that cannot be made, the first in
/// order throws when its turn comes: the same error whatever the number of
/// threads.
template <typename T, typename Make, typename Take>
void takeMadeAhead(std::size_t count, const Make& make, const Take& take, const Interrupter& interrupter = {}) {
  struct Batch {
    std::vector<std::optional<T>> items;
    std::vector<std::exception_ptr> failures;
  };
  const std::size_t size = itemsInFlight();
  std::array<Batch, 2> batches;
  for (Batch& b : batches) {
    b.items.resize(size);
    b.failures.resize(size);
  }
  const auto makeBatch = [&](Batch& b, std::size_t first) {
    parallelFor(std::min(size, count - first), 1, [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) try {
          b.items[k].emplace(make(first + k));
        } catch (...) {
          b.failures[k] = std::current_exception();
        }
    });
  };
  const auto takeBatch = [&](Batch& b, std::size_t first) {
    for (std::size_t k = 0; k < std::min(size, count - first); ++k) {
      checkInterrupter(interrupter);
      if (b.failures[k]) std::rethrow_exception(b.failures[k]);
      take(first + k, std::move(*b.items[k]));
      b.items[k].reset();
    }
  };
  checkInterrupter(interrupter);
  if (count > 0) makeBatch(batches[0], 0);
  for (std::size_t first = 0, current = 0; first < count; first += size, current ^= 1) {
    tbb::task_group next;
    if (first + size < count) next.run([&, first, current] { makeBatch(batches[current ^ 1], first + size); });
    try {
      takeBatch(batches[current], first);
    } catch (...) {
      next.cancel();
      next.wait();
      throw;
    }
    next.wait();
  }
}

}  // namespace levelfuse
