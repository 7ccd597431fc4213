// Dashpot mass of a contact (docs/theory.md §4): the shortcut that proves the cap inactive
// must give the chain's bits, and must never fire where the cap could bind.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "contact/dashpot_mass.hpp"

using namespace dsdem;
using namespace dsdem::contact;

namespace {

const std::array<Index, 3> kNodesI{0, 1, 2}, kNodesJ{3, 4, 5};

// The definition without the shortcut.
double chain(const PairDashpotMass& d, const Vec3& Ni, const Vec3& Nj, std::span<const double> mass) {
  const double inv_m = point_inverse_mass(Ni, kNodesI, mass) + point_inverse_mass(Nj, kNodesJ, mass);
  return capped_dashpot_mass(d.m_pair, inv_m, d.capped, d.dt, d.cap_den);
}

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

// Barycentric coordinates of a point anywhere within ~1.5 triangle sizes (some negative).
Vec3 random_shape_functions(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-0.6, 1.4);
  const double n1 = u(rng), n2 = u(rng);
  return Vec3(1.0 - n1 - n2, n1, n2);
}

}  // namespace

TEST(DashpotMass, ShortcutGivesTheChainsBitsWhetherTheCapBindsOrNot) {
  std::mt19937_64 rng(20261124);
  std::lognormal_distribution<double> node_mass(std::log(2.0e4), 1.5);  // kg/m, spread of 10^3
  std::uniform_real_distribution<double> log_dt(-6.0, -2.0), zeta(0.0, 0.9), log_kn(7.0, 11.0);
  long shortcuts = 0, binding = 0, not_binding_without_shortcut = 0;
  const int kPairs = 20000;
  for (int s = 0; s < kPairs; ++s) {
    std::vector<double> mass(6);
    for (double& m : mass) m = node_mass(rng);
    const PairDashpotMass d =
        pair_dashpot_mass(kNodesI, kNodesJ, mass, std::pow(10.0, log_dt(rng)), zeta(rng), std::pow(10.0, log_kn(rng)));
    for (int c = 0; c < 3; ++c) {
      const Vec3 Ni = random_shape_functions(rng), Nj = random_shape_functions(rng);
      const double exact = chain(d, Ni, Nj, mass);
      ASSERT_EQ(bits(contact_dashpot_mass(d, Ni, kNodesI, Nj, kNodesJ, mass)), bits(exact)) << "pair " << s;
      if (cap_above_pair_mass(d, Ni, Nj)) {
        ++shortcuts;
        ASSERT_EQ(bits(exact), bits(d.m_pair));  // the shortcut fired only where the cap does not bind
      }
      if (exact != d.m_pair) ++binding;
      else if (!cap_above_pair_mass(d, Ni, Nj)) ++not_binding_without_shortcut;
    }
  }
  // Both regimes are covered, and the bound is tight enough to take most non-binding points.
  EXPECT_GT(binding, 3000);
  EXPECT_GT(shortcuts, 20000);
  EXPECT_LT(not_binding_without_shortcut, shortcuts);
}

TEST(DashpotMass, NoShortcutWhereTheCapIsWithinTheMarginOfThePairMass) {
  // Equal node masses and a point at a vertex of each triangle: inv_m = 3/mi + 3/mj exactly
  // the bound, so the margin alone decides. dt puts the cap at m_pair (1 + eps).
  const std::vector<double> mass{1000.0, 1000.0, 1000.0, 3000.0, 3000.0, 3000.0};
  const double zeta = 0.3, kn = 1e9;
  const double m_pair = 3000.0 * 9000.0 / 12000.0;
  const double m_point = 1.0 / (1.0 / 1000.0 + 1.0 / 3000.0);
  const Vec3 Ni(1.0, 0.0, 0.0), Nj(0.0, 0.0, 1.0);
  for (const double eps : {-1e-6, -1e-12, 0.0, 1e-12, 1e-10, 1e-6, 1e-3}) {
    // (m_point / dt)^2 / (4 zeta^2 kn) = m_pair (1 + eps)
    const double dt = m_point / std::sqrt(m_pair * (1.0 + eps) * 4.0 * zeta * zeta * kn);
    const PairDashpotMass d = pair_dashpot_mass(kNodesI, kNodesJ, mass, dt, zeta, kn);
    const double exact = chain(d, Ni, Nj, mass);
    EXPECT_EQ(bits(contact_dashpot_mass(d, Ni, kNodesI, Nj, kNodesJ, mass)), bits(exact)) << eps;
    // Within ~1e-8 of binding the chain decides; well clear of it the bound does.
    EXPECT_EQ(cap_above_pair_mass(d, Ni, Nj), eps > 1e-7) << eps;
  }
}

TEST(DashpotMass, ImmovableNodesAndNoDampingTakeTheChain) {
  const Vec3 Ni(0.2, 0.5, 0.3), Nj(0.1, 0.1, 0.8);
  // A node without mass (a support) is left out of inv_m: no bound by the smallest mass.
  const std::vector<double> pinned{0.0, 1000.0, 1000.0, 1000.0, 1000.0, 1000.0};
  PairDashpotMass d = pair_dashpot_mass(kNodesI, kNodesJ, pinned, 1e-5, 0.2, 1e9);
  EXPECT_FALSE(d.shortcut);
  EXPECT_EQ(bits(contact_dashpot_mass(d, Ni, kNodesI, Nj, kNodesJ, pinned)), bits(chain(d, Ni, Nj, pinned)));
  // A triangle without mass: m_pair = 0, no dashpot.
  const std::vector<double> massless{0.0, 0.0, 0.0, 1000.0, 1000.0, 1000.0};
  d = pair_dashpot_mass(kNodesI, kNodesJ, massless, 1e-5, 0.2, 1e9);
  EXPECT_EQ(d.m_pair, 0.0);
  EXPECT_EQ(contact_dashpot_mass(d, Ni, kNodesI, Nj, kNodesJ, massless), 0.0);
  // No damping: m_pair uncapped, and no shortcut needed.
  const std::vector<double> mass(6, 1000.0);
  d = pair_dashpot_mass(kNodesI, kNodesJ, mass, 1e-5, 0.0, 1e9);
  EXPECT_FALSE(d.capped);
  EXPECT_EQ(contact_dashpot_mass(d, Ni, kNodesI, Nj, kNodesJ, mass), 1000.0 * 3.0 / 2.0);
  // Shape functions that are not numbers: whatever the chain gives, not the shortcut.
  d = pair_dashpot_mass(kNodesI, kNodesJ, mass, 1e-5, 0.2, 1e9);
  ASSERT_TRUE(d.shortcut);
  const Vec3 bad(std::nan(""), 0.5, 0.5);
  EXPECT_FALSE(cap_above_pair_mass(d, bad, Nj));
  EXPECT_EQ(bits(contact_dashpot_mass(d, bad, kNodesI, Nj, kNodesJ, mass)), bits(chain(d, bad, Nj, mass)));
}
