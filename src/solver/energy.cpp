#include "solver/energy.hpp"

#include <algorithm>
#include <cmath>

namespace dsdem::solver {

double EnergyLedger::balance_error() const {
  const double residual = mechanical() - verlet_kinetic_offset - initial_total + dissipated() - work_in();
  const double scale = std::max({std::abs(kinetic), std::abs(strain), std::abs(gravity_potential),
                                 std::abs(joint_elastic), std::abs(external_work), std::abs(water_work),
                                 std::abs(moving_water_work), std::abs(dissipated()),
                                 std::abs(initial_total), 1e-300});
  return std::abs(residual) / scale;
}

}  // namespace dsdem::solver
