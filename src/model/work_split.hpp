#pragma once
// Splitting a loop between threads by their measured speed (issue 7). On a VM one core
// often runs slower than the other for a while (another guest on it), and a split by
// count then leaves the faster thread waiting at every barrier. The phases that may give
// any thread any item (the contact pair loop, the element loops: every item writes its
// own slots or its own nodes) keep each thread on a contiguous share, tuned each step;
// which thread computes an item never changes a result.
#include <span>
#include <vector>

namespace dsdem {

// The shares that would make every thread finish together if each kept the rate it
// showed (share / busy seconds), moved `gain` of the way there (one step's timing is
// noisy), each at least 0.1 / T and summing to 1. No timing (busy <= 0 or not finite)
// or sizes that differ: unchanged.
void balance_shares(std::span<double> share, std::span<const double> busy, double gain = 0.1);

// Cumulative shares, normalised: cum[0] = 0, cum[T] = 1 (T = share.size()).
void cumulative_shares(std::span<const double> share, std::vector<double>& cum);

}  // namespace dsdem
