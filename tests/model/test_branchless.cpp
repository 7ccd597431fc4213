// branchless_max / branchless_min / branchless_clamp must be std::max / std::min /
// std::clamp bit for bit, NaN and signed zeros included (the joint law's bits rest on it).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

#include "model/branchless.hpp"

using namespace dsdem;

namespace {
std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }
}  // namespace

TEST(Branchless, MaxMinAndClampAreTheStandardOnesBitForBit) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> v{0.0, -0.0, 1.0, -1.0, 2.5, -3e300, 5e-324, -5e-324, inf, -inf, nan, -nan};
  for (const double a : v)
    for (const double b : v) {
      EXPECT_EQ(bits(branchless_max(a, b)), bits(std::max(a, b))) << a << " " << b;
      EXPECT_EQ(bits(branchless_min(a, b)), bits(std::min(a, b))) << a << " " << b;
      // The joint law clamps to [min(0, s), max(0, s)].
      const double lo = std::min(0.0, b), hi = std::max(0.0, b);
      EXPECT_EQ(bits(branchless_clamp(a, lo, hi)), bits(std::clamp(a, lo, hi))) << a << " " << b;
    }
}
