#pragma once
// A linear elastic material for tests that build a model from a mesh.
#include <string>

#include "model/model.hpp"

namespace dsdem::test {

inline Material elastic_material(std::string name, double E, double nu, double rho) {
  Material m;
  m.name = std::move(name);
  m.E = E;
  m.nu = nu;
  m.rho = rho;
  return m;
}

}  // namespace dsdem::test
