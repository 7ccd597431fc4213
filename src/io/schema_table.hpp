#pragma once
// Internal to src/io: the table of scenario keys (schema_table.cpp).
#include <vector>

#include "io/schema.hpp"

namespace dsdem::io::detail {

// Keys in the order of docs/scenario-reference.md.
std::vector<KeySpec> build_schema();

}  // namespace dsdem::io::detail
