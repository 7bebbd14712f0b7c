// Counts heap allocations while `g_counting` is set, for the tests that check the haptic path
// allocates nothing. Replaces the global operator new and delete: include it from exactly one
// file of a test binary (GCC cannot see that the replaced delete matches the replaced new and
// warns falsely).
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
inline std::atomic<bool> g_counting{false};
inline std::atomic<long> g_allocations{0};
void* operator new(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// The nothrow form too: the standard library's temporary buffers (std::stable_sort's, for one)
// come from it and go back through the delete above, so both must use malloc (the sanitizers
// report the mismatch otherwise).
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) ++g_allocations;
  return std::malloc(n ? n : 1);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
