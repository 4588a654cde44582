// The largest single allocation: global operator new and delete, replaced for
// the io test program (malloc and free underneath, so sanitizers still see
// every block; the aligned forms stay the runtime's own).

#include "LargestAllocation.h"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

std::atomic<bool> gMeasuring{false};
std::atomic<std::size_t> gLargest{0};

void* allocate(std::size_t bytes) noexcept {
  if (gMeasuring.load(std::memory_order_relaxed)) {
    std::size_t seen = gLargest.load(std::memory_order_relaxed);
    while (bytes > seen && !gLargest.compare_exchange_weak(seen, bytes, std::memory_order_relaxed)) {
    }
  }
  return std::malloc(bytes == 0 ? 1 : bytes);
}

void* allocateOrThrow(std::size_t bytes) {
  void* p = allocate(bytes);
  if (!p) throw std::bad_alloc();
  return p;
}

}  // namespace

void* operator new(std::size_t bytes) { return allocateOrThrow(bytes); }
void* operator new[](std::size_t bytes) { return allocateOrThrow(bytes); }
void* operator new(std::size_t bytes, const std::nothrow_t&) noexcept { return allocate(bytes); }
void* operator new[](std::size_t bytes, const std::nothrow_t&) noexcept { return allocate(bytes); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace levelfuse::test {

LargestAllocation::LargestAllocation() {
  gLargest.store(0);
  gMeasuring.store(true);
}

LargestAllocation::~LargestAllocation() { gMeasuring.store(false); }

std::size_t LargestAllocation::bytes() const { return gLargest.load(); }

}  // namespace levelfuse::test
