// tests/support/allocation_counter.hpp: counts the heap allocations one thread makes while a
// piece of code runs, so tests can prove that hot paths (Krylov iterations, the haptic force
// path) allocate nothing. Include it from exactly one translation unit per test executable.
// Ordinary builds wrap malloc (glibc's __libc_malloc), which sees operator new, Eigen's aligned
// allocations and std::vector growth alike; AddressSanitizer and ThreadSanitizer own malloc, so
// there the counter uses the sanitizer's allocation hooks instead and the check stays just as strict.
#pragma once

#include <atomic>
#include <cstddef>
#include <thread>

namespace bemsurg_test {

inline std::atomic<long> g_allocations{0};
inline std::atomic<bool> g_counting{false};
inline std::atomic<std::thread::id> g_counted_thread{};

inline void count_allocation() {
  if (g_counting.load(std::memory_order_relaxed) && std::this_thread::get_id() == g_counted_thread.load()) ++g_allocations;
}

/// Allocations made by the calling thread while f runs.
template <class F>
long allocations_during(F&& f) {
  g_counted_thread = std::this_thread::get_id();
  g_allocations = 0;
  g_counting = true;
  f();
  g_counting = false;
  return g_allocations.load();
}

}  // namespace bemsurg_test

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*, std::size_t),
                                                         void (*free_hook)(const volatile void*));
namespace bemsurg_test {
inline void on_malloc(const volatile void*, std::size_t) { count_allocation(); }
inline void on_free(const volatile void*) {}
inline const int hooks_installed = __sanitizer_install_malloc_and_free_hooks(on_malloc, on_free);
}  // namespace bemsurg_test
#else
extern "C" void* __libc_malloc(std::size_t size);
// Exported (the project builds with hidden visibility) so that malloc calls from inside the shared
// libraries, operator new in libstdc++ among them, reach this wrapper too.
extern "C" __attribute__((visibility("default"))) void* malloc(std::size_t size) {
  bemsurg_test::count_allocation();
  return __libc_malloc(size);
}
#endif
