// The Mohr-Coulomb bulk law in the solver (DESIGN.md §12): its models per material, the
// state at each step's start, and its plastic work in the energy ledger.
#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "exec/deterministic_sums.hpp"
#include "law/laws.hpp"
#include "solver/solver.hpp"

namespace dsdem::solver {

void Solver::setup_plasticity() {
  plastic_.assign(model_.materials.size(), {});
  for (std::size_t m = 0; m < model_.materials.size(); ++m) {
    const Material& mat = model_.materials[m];
    if (mat.model != "mohr_coulomb") continue;
    namespace mc = law::mohr_coulomb;
    if (mat.params.size() != mc::kParams || mat.state_columns.size() != mc::kStates)
      throw std::invalid_argument(fmt::format("material '{}' (mohr_coulomb): {} parameters and {} state columns, expected "
                                              "{} and {} (build it through the model builder)",
                                              mat.name, mat.params.size(), mat.state_columns.size(), +mc::kParams,
                                              +mc::kStates));
    fem::MohrCoulombParameters p;
    p.c = mat.params[mc::cohesion];
    p.phi = law::radians(mat.params[mc::friction_angle]);
    p.psi = law::radians(mat.params[mc::dilation_angle]);
    // The declared default is the envelope's apex c / tan(phi): no cut-off of its own.
    const double ft = mat.params[mc::tensile_strength];
    p.ft = std::isfinite(ft) && ft < law::envelope_apex(p.c, p.phi) ? ft : std::numeric_limits<double>::infinity();
    if (const std::string why = fem::validate(p, mat.plane_stress || model_.plane_stress); !why.empty())
      throw std::invalid_argument(fmt::format("material '{}': {}", mat.name, why));
    PlasticMaterial& pm = plastic_[m];
    pm.on = true;
    pm.model = fem::make_mohr_coulomb(p, elastic_[m]);
    for (int k = 0; k < mc::kStates; ++k) pm.columns[static_cast<std::size_t>(k)] = mat.state_columns[static_cast<std::size_t>(k)];
    any_plastic_ = true;
  }
  if (!any_plastic_) return;
  plastic_start_.assign(model_.triangles.size(), {});
  commit_plastic_state();
}

fem::MohrCoulombState Solver::plastic_state(std::size_t t) const {
  const PlasticMaterial& pm = plastic_[model_.triangles.material[t]];
  const auto& v = model_.triangles.state.values;
  return {v[pm.columns[0]][t], v[pm.columns[1]][t], v[pm.columns[2]][t], v[pm.columns[3]][t], v[pm.columns[4]][t]};
}

void Solver::commit_plastic_state() {
  const auto& tri = model_.triangles;
  exec::parallel_for(team_, tri.size(), [&](std::size_t t) {
    if (plastic_[tri.material[t]].on) plastic_start_[t] = plastic_state(t);
  });
}

double Solver::plastic_dissipation_sum() {
  const auto& tri = model_.triangles;
  const double thickness = model_.thickness;
  const auto [sum] = exec::deterministic_sums<1>(
      tri.size(),
      [&](std::size_t t) {
        const PlasticMaterial& pm = plastic_[tri.material[t]];
        return std::array<double, 1>{pm.on ? tri.area0[t] * thickness * tri.state.values[pm.columns[4]][t] : 0.0};
      },
      plastic_scratch_, team_.parallel());
  return sum;
}

}  // namespace dsdem::solver
