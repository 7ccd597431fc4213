// `dsdem check`'s resource estimates (run/check.hpp).
#include "run/check.hpp"

#include <gtest/gtest.h>

namespace {

TEST(Check, ResourceWarningsCompareWithAvailableMemoryAndOneDay) {
  using dsdem::run::resource_warnings;
  EXPECT_TRUE(resource_warnings(1u << 30, 8ull << 30, 3600.0).empty());
  const auto mem = resource_warnings(16ull << 30, 8ull << 30, 10.0);
  ASSERT_EQ(mem.size(), 1u);
  EXPECT_NE(mem[0].find("17.18 GB of memory but the machine has 8.59 GB available"), std::string::npos) << mem[0];
  const auto slow = resource_warnings(1, 0, 30 * 3600.0);
  ASSERT_EQ(slow.size(), 1u);
  EXPECT_NE(slow[0].find("30.0 h"), std::string::npos) << slow[0];
  EXPECT_GT(dsdem::run::available_memory_bytes(), 0u);
}

}  // namespace
