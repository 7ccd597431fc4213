#pragma once
// Dashpot mass of a contact (docs/theory.md §4, contact damping): the pair's reduced mass
// m_i m_j / (m_i + m_j) of the two triangles (a contact softer than the elements moves
// each element as a whole, so the set restitution holds for element impacts), capped so
// the dashpot on the contact point's own mass stays explicit-stable (c dt <= m_point):
//   m_eff = min(m_pair, (m_point / dt)^2 / (4 zeta^2 kn)),  1 / m_point = sum N_k^2 / m_k.
// The cap costs a chain of divisions per contact (six N_k^2 / m_k, then three in series).
// A bound per pair proves it inactive without dividing (the usual case); the result is
// then m_pair, the same bits as the chain.
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
  // The shortcut. sum_k N_k^2 / m_k <= S / m_min per triangle (S = sum_k N_k^2, m_min its
  // smallest node mass), so inv_m <= B = S_i / a + S_j / b (a, b: the two m_min), and
  // B need <= 1 - kMargin with need = dt sqrt(m_pair cap_den) (1 + kMargin) puts the cap
  // above m_pair by ~4e-9 relative, far beyond the ~30 ulps the chain rounds by. Tested
  // without dividing or a root: (S_i b + S_j a)^2 need^2 <= (1 - kMargin)^2 (a b)^2.
  bool shortcut = false;
  double need2 = 0.0;                 // need^2 = dt^2 m_pair cap_den (1 + kMargin)^2
  double min_i = 0.0, min_j = 0.0;    // a, b, kg/m
  double limit = 0.0;                 // (1 - kMargin)^2 (a b)^2
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
  d.min_i = std::min({mass[ci[0]], mass[ci[1]], mass[ci[2]]});
  d.min_j = std::min({mass[cj[0]], mass[cj[1]], mass[cj[2]]});
  const double max_m = std::max({mass[ci[0]], mass[ci[1]], mass[ci[2]], mass[cj[0]], mass[cj[1]], mass[cj[2]]});
  // Every node movable (no N_k^2 / m_k term left out), and masses in a range where no
  // product below over- or underflows (then also inv_m > 0 whenever some N_k^2 >= 0.03).
  d.shortcut = d.capped && d.m_pair > 0.0 && d.min_i >= 1e-60 && d.min_j >= 1e-60 && max_m <= 1e60;
  if (d.shortcut) {
    constexpr double up = 1.0 + PairDashpotMass::kMargin, down = 1.0 - PairDashpotMass::kMargin;
    d.need2 = dt * dt * d.m_pair * d.cap_den * (up * up);
    const double ab = d.min_i * d.min_j;
    d.limit = (down * down) * (ab * ab);
    d.shortcut = std::isnormal(d.need2) && std::isnormal(d.limit);
  }
  return d;
}

// True when the bound proves the cap above m_pair at the point Ni, Nj (false: not known).
inline bool cap_above_pair_mass(const PairDashpotMass& d, const Vec3& Ni, const Vec3& Nj) {
  if (!d.shortcut) return false;
  const double si = Ni.squaredNorm(), sj = Nj.squaredNorm();
  const double l = si * d.min_j + sj * d.min_i;
  // si >= 0.1: some N_k^2 >= 0.03, so inv_m > 0 (m_point is not the 0 of no movable node).
  // A NaN fails both tests, an overflow the second.
  return si >= 0.1 && (l * l) * d.need2 <= d.limit;
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
