#pragma once
// Counts calls of the global operator new, to check that hot loops allocate nothing
// after warm-up. The replacement allocation functions must be defined once
// per binary: exactly one source file of a test binary defines
// DSDEM_DEFINE_ALLOC_COUNTER before including this header (tests/contact/alloc_counter.cpp,
// tests/solver/test_no_allocation.cpp); the others include it plainly.
#include <atomic>
#include <cstddef>

namespace dsdem::test {

extern std::atomic<long> g_allocations;

// Allocations made while the object lives.
class AllocationScope {
 public:
  AllocationScope() : start_(g_allocations.load()) {}
  long count() const { return g_allocations.load() - start_; }

 private:
  long start_;
};

}  // namespace dsdem::test

#ifdef DSDEM_DEFINE_ALLOC_COUNTER
#include <cstdlib>
#include <new>

namespace dsdem::test {
std::atomic<long> g_allocations{0};
}

namespace {
void* counted_alloc(std::size_t n) {
  dsdem::test::g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* counted_aligned_alloc(std::size_t n, std::align_val_t al) {
  dsdem::test::g_allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t a = static_cast<std::size_t>(al);
  const std::size_t size = ((n ? n : 1) + a - 1) / a * a;  // aligned_alloc wants a multiple
  if (void* p = std::aligned_alloc(a, size)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) { return counted_alloc(n); }
void* operator new[](std::size_t n) { return counted_alloc(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return counted_alloc(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return counted_alloc(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(std::size_t n, std::align_val_t al) { return counted_aligned_alloc(n, al); }
void* operator new[](std::size_t n, std::align_val_t al) { return counted_aligned_alloc(n, al); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
#endif  // DSDEM_DEFINE_ALLOC_COUNTER
