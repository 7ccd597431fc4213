#pragma once
// A linear elastic material for tests that build a model from a mesh, and the elastic
// constants a kernel test takes.
#include <limits>
#include <string>

#include "fem/cst.hpp"
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

// A Mohr-Coulomb material with its parameters in declaration order (law/laws.hpp): angles
// in degrees, ft infinite for no cut-off of its own.
inline Material mohr_coulomb_material(std::string name, double E, double nu, double rho, double c, double phi_deg,
                                      double psi_deg, double ft = std::numeric_limits<double>::infinity()) {
  Material m = elastic_material(std::move(name), E, nu, rho);
  m.model = "mohr_coulomb";
  m.params = {E, nu, rho, c, phi_deg, psi_deg, ft};
  return m;
}

// The Lame constants (lambda, mu) of E and nu: plane strain's, which are the 3D ones.
inline fem::ElasticConstants elastic_constants(double E, double nu) {
  const Material m = elastic_material("", E, nu, 1000.0);
  return {m.lambda(), m.mu()};
}

}  // namespace dsdem::test
