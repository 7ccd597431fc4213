#pragma once
// Dashpot mass of a contact (DESIGN.md §4, contact damping): the pair's reduced mass
// m_i m_j / (m_i + m_j) of the two triangles (a contact softer than the elements moves
// each element as a whole, so the set restitution holds for element impacts), capped so
// the dashpot on the contact point's own mass stays explicit-stable (c dt <= m_point):
//   m_eff = min(m_pair, (m_point / dt)^2 / (4 zeta^2 kn)),  1 / m_point = sum N_k^2 / m_k.
// The cap costs a chain of divisions per contact (six N_k^2 / m_k, then three in series;
// a quarter of process_pair's samples in a late Dr2 perf profile). A bound per pair
// proves it inactive without dividing (every contact of late Dr2); the result is then
// m_pair, the same bits as the chain. Late Dr2 step on one thread -5.7 % (issue 7).
#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "contact/shape_map.hpp"
#include "model/types.hpp"

namespace dsdem::contact {

// The exact definition: min(m_pair, (m_point / dt)^2 / cap_den), cap_den = 4 zeta^2 kn;
// m_point = 1 / inv_m (0 when inv_m is 0: no movable node, no dashpot).
inline double capped_dashpot_mass(double m_pair, double inv_m, bool capped, double dt, double cap_den) {
  const double m_point = inv_m > 0.0 ? 1.0 / inv_m : 0.0;
  double m_eff = m_pair;
  if (capped) {
    const double c_max = m_point / dt;
    m_eff = std::min(m_eff, c_max * c_max / cap_den);
  }
  return m_eff;
}

// What the contacts of one pair share.
struct PairDashpotMass {
  double m_pair = 0.0;   // reduced mass of the two triangles, kg/m (0: no dashpot)
  bool capped = false;   // zeta > 0 and kn > 0
  double dt = 0.0;
  double cap_den = 0.0;  // 4 zeta^2 kn
  // The shortcut: with sum_k N_k^2 (one triangle) times its largest node inverse mass
  // bounding that triangle's part of inv_m from above, inv_m * need <= 1 - kMargin proves
  // the cap above m_pair by ~4e-9 relative, far beyond the ~30 ulps the chain rounds by.
  bool shortcut = false;
  double need = 0.0;                // dt sqrt(m_pair cap_den) (1 + kMargin): m_point above it keeps m_pair
  double inv_max_i = 0.0, inv_max_j = 0.0;  // 1 / the smallest node mass of i, of j
  static constexpr double kMargin = 1e-9;
};

inline PairDashpotMass pair_dashpot_mass(const std::array<Index, 3>& ci, const std::array<Index, 3>& cj,
                                         std::span<const double> mass, double dt, double damping_ratio,
                                         double kn) {
  PairDashpotMass d;
  const double mi = mass[ci[0]] + mass[ci[1]] + mass[ci[2]];
  const double mj = mass[cj[0]] + mass[cj[1]] + mass[cj[2]];
  d.m_pair = mi > 0.0 && mj > 0.0 ? mi * mj / (mi + mj) : 0.0;
  d.capped = damping_ratio > 0.0 && kn > 0.0;
  d.dt = dt;
  d.cap_den = 4.0 * damping_ratio * damping_ratio * kn;
  const double min_i = std::min({mass[ci[0]], mass[ci[1]], mass[ci[2]]});
  const double min_j = std::min({mass[cj[0]], mass[cj[1]], mass[cj[2]]});
  const double max_m = std::max({mass[ci[0]], mass[ci[1]], mass[ci[2]], mass[cj[0]], mass[cj[1]], mass[cj[2]]});
  // Every node movable (no N_k^2 / m_k term left out) and no term that could underflow
  // (then inv_m > 0 whenever some N_k^2 >= 0.03, see contact_dashpot_mass).
  d.shortcut = d.capped && d.m_pair > 0.0 && dt > 0.0 && min_i > 0.0 && min_j > 0.0 && max_m < 1e300;
  if (d.shortcut) {
    d.need = dt * std::sqrt(d.m_pair * d.cap_den) * (1.0 + PairDashpotMass::kMargin);
    d.inv_max_i = 1.0 / min_i;
    d.inv_max_j = 1.0 / min_j;
    d.shortcut = std::isfinite(d.need);
  }
  return d;
}

// True when the bound proves the cap above m_pair at the point Ni, Nj (false: not known).
inline bool cap_above_pair_mass(const PairDashpotMass& d, const Vec3& Ni, const Vec3& Nj) {
  if (!d.shortcut) return false;
  const double si = Ni.squaredNorm(), sj = Nj.squaredNorm();
  // si >= 0.1: some N_k^2 >= 0.03, so inv_m > 0 (m_point is not the 0 of no movable node).
  // A NaN fails both tests.
  return si >= 0.1 && (si * d.inv_max_i + sj * d.inv_max_j) * d.need <= 1.0 - PairDashpotMass::kMargin;
}

// m_eff of a contact at shape functions Ni (triangle i, nodes ci) and Nj (j, cj): bit for
// bit capped_dashpot_mass(m_pair, point_inverse_mass(Ni) + point_inverse_mass(Nj), ...).
inline double contact_dashpot_mass(const PairDashpotMass& d, const Vec3& Ni, const std::array<Index, 3>& ci,
                                   const Vec3& Nj, const std::array<Index, 3>& cj, std::span<const double> mass) {
  if (cap_above_pair_mass(d, Ni, Nj)) return d.m_pair;
  const double inv_m = point_inverse_mass(Ni, ci, mass) + point_inverse_mass(Nj, cj, mass);
  return capped_dashpot_mass(d.m_pair, inv_m, d.capped, d.dt, d.cap_den);
}

}  // namespace dsdem::contact
