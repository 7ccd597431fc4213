#pragma once
// Bit-for-bit comparisons of two runs' states (restart and determinism tests): equal as
// bytes, so -0.0 against +0.0 or two different NaNs count as different.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "model/model.hpp"

namespace dsdem::test {

inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The nodes' displacements and velocities of two models, and two times, bit for bit;
// the failure names the first node that differs.
inline ::testing::AssertionResult same_motion(const Model& a, double time_a, const Model& b, double time_b) {
  if (!same_bits(time_a, time_b))
    return ::testing::AssertionFailure() << "times differ: " << time_a << " and " << time_b << " s";
  if (a.nodes.size() != b.nodes.size()) return ::testing::AssertionFailure() << "node counts differ";
  for (std::size_t n = 0; n < a.nodes.size(); ++n)
    if (std::memcmp(a.nodes.u[n].data(), b.nodes.u[n].data(), 2 * sizeof(double)) != 0 ||
        std::memcmp(a.nodes.v[n].data(), b.nodes.v[n].data(), 2 * sizeof(double)) != 0)
      return ::testing::AssertionFailure() << "node " << n << " differs: u (" << a.nodes.u[n].transpose() << ") / ("
                                           << b.nodes.u[n].transpose() << ")";
  return ::testing::AssertionSuccess();
}

}  // namespace dsdem::test
