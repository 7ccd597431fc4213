#pragma once
// Counts calls of the global operator new (replaced in alloc_counter.cpp for the
// whole test_contact binary), to check that hot loops allocate nothing after warm-up.
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
