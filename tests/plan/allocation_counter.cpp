// Replaces the global operator new / delete of test_plan to count allocations (kept alone in
// this file so that no inlined new/delete pair mixes the replacement with the library's).
#include "plan/allocation_counter.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<long long> allocations{0};
}

long long starnav::test::allocation_count() { return allocations.load(std::memory_order_relaxed); }

void* operator new(std::size_t n) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
