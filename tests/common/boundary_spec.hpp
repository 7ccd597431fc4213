#pragma once
// A boundary condition on a named group, for tests that build their constraints in code.
#include <string>

#include "io/scenario.hpp"

namespace dsdem::test {

inline io::BoundarySpec boundary_spec(const std::string& group, io::BoundaryType type, int direction = 0) {
  io::BoundarySpec b;
  b.group = group;
  b.type = type;
  b.direction = direction;
  return b;
}

}  // namespace dsdem::test
