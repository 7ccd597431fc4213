// The bulk laws in the solver (fem/bulk_law.hpp): each material's kernel, the state at
// each step's start, and the plastic work of the laws with state in the energy ledger.
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "exec/deterministic_sums.hpp"
#include "law/registry.hpp"
#include "solver/solver.hpp"

namespace dsdem::solver {

void Solver::setup_laws() {
  const auto& tri = model_.triangles;
  std::vector<std::uint8_t> used(model_.materials.size(), 0);
  for (const Index m : tri.material) used[static_cast<std::size_t>(m)] = 1;
  laws_.assign(model_.materials.size(), {});
  for (std::size_t m = 0; m < model_.materials.size(); ++m) {
    const Material& mat = model_.materials[m];
    const law::LawDecl& decl = law::material_laws().get(mat.model);
    if (decl.state.empty()) {  // no state to keep: the parameters are the elastic constants
      laws_[m].kernel = fem::make_bulk_law(decl, mat.params, elastic_[m], mat.plane_stress || model_.plane_stress);
      continue;
    }
    if (!used[m]) continue;  // no triangle of it: elastic, never asked
    if (mat.params.size() != decl.params.size() || mat.state_columns.size() != decl.state.size())
      throw std::invalid_argument(fmt::format("material '{}' ({}): {} parameters and {} state columns, expected "
                                              "{} and {} (build it through the model builder)",
                                              mat.name, mat.model, mat.params.size(), mat.state_columns.size(),
                                              decl.params.size(), decl.state.size()));
    MaterialLaw& law = laws_[m];
    try {
      law.kernel = fem::make_bulk_law(decl, mat.params, elastic_[m], mat.plane_stress || model_.plane_stress);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("material '{}': {}", mat.name, e.what()));
    }
    std::copy(mat.state_columns.begin(), mat.state_columns.end(), law.columns.begin());
    if (const int k = law.kernel.dissipation(); k >= 0) law.dissipation = law.columns[static_cast<std::size_t>(k)];
    law_stride_ = std::max(law_stride_, decl.state.size());
    any_law_state_ = true;
  }
  if (!any_law_state_) return;
  law_start_.assign(law_stride_ * tri.size(), 0.0);
  commit_law_state();
}

void Solver::commit_law_state() {
  const auto& tri = model_.triangles;
  const auto& v = tri.state.values;
  exec::parallel_for(team_, tri.size(), [&](std::size_t t) {
    const MaterialLaw& law = laws_[tri.material[t]];
    double* start = &law_start_[law_stride_ * t];
    fem::with_state_size(law.kernel, [&](auto n) {
      for (std::size_t k = 0; k < n; ++k) start[k] = v[law.columns[k]][t];
    });
  });
}

double Solver::law_dissipation_sum() {
  const auto& tri = model_.triangles;
  const double thickness = model_.thickness;
  const auto [sum] = exec::deterministic_sums<1>(
      tri.size(),
      [&](std::size_t t) {
        const Index c = laws_[tri.material[t]].dissipation;
        return std::array<double, 1>{c != kNoIndex ? tri.area0[t] * thickness * tri.state.values[c][t] : 0.0};
      },
      plastic_scratch_, team_.parallel());
  return sum;
}

}  // namespace dsdem::solver
