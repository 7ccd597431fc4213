// Strength reduction (docs/theory.md §9): every strength divided by F, the stiffnesses and
// the softening lengths kept, the reduced properties still admissible.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "law/laws.hpp"
#include "law/strength_reduction.hpp"

using namespace dsdem;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

JointProperties joint() {
  JointProperties p;
  p.name = "plane";
  p.kn = 5e9;
  p.ks = 2e9;
  p.ft = 1e5;
  p.c = 3e5;
  p.phi = 35 * kDeg;
  p.GI = 50;
  p.GII = 400;
  return p;
}

Material mohr_coulomb(double ft) {
  namespace mc = law::mohr_coulomb;
  Material m;
  m.name = "soil";
  m.model = "mohr_coulomb";
  m.E = 5e7;
  m.nu = 0.3;
  m.rho = 1900;
  m.params.assign(mc::kParams, 0.0);
  m.params[mc::E] = m.E;
  m.params[mc::nu] = m.nu;
  m.params[mc::rho] = m.rho;
  m.params[mc::cohesion] = 2e4;
  m.params[mc::friction_angle] = 30;
  m.params[mc::dilation_angle] = 10;
  m.params[mc::tensile_strength] = ft;
  return m;
}

}  // namespace

TEST(StrengthReduction, JointStrengthsOverFStiffnessAndSofteningLengthsKept) {
  const JointProperties p = joint();
  const double F = 1.6;
  const JointProperties r = law::reduce_joint(p, F);
  EXPECT_DOUBLE_EQ(r.c, p.c / F);
  EXPECT_DOUBLE_EQ(std::tan(r.phi), std::tan(p.phi) / F);
  EXPECT_DOUBLE_EQ(r.ft, p.ft / F);
  EXPECT_EQ(r.kn, p.kn);
  EXPECT_EQ(r.ks, p.ks);
  // wn = 2 GI/ft and the shear softening length in compression 2 GII/c are kept.
  EXPECT_DOUBLE_EQ(2 * r.GI / r.ft, 2 * p.GI / p.ft);
  EXPECT_DOUBLE_EQ(2 * r.GII / r.c, 2 * p.GII / p.c);
  EXPECT_EQ(validate(r), "");
}

TEST(StrengthReduction, FactorOneChangesNothing) {
  const JointProperties p = joint();
  const JointProperties r = law::reduce_joint(p, 1.0);
  EXPECT_EQ(r.c, p.c);
  EXPECT_EQ(r.ft, p.ft);
  EXPECT_EQ(r.GI, p.GI);
  EXPECT_EQ(r.GII, p.GII);
  EXPECT_NEAR(r.phi, p.phi, 1e-15);
  const Material m = mohr_coulomb(1e4);
  const Material rm = law::reduce_material(m, 1.0);
  for (std::size_t k = 0; k < m.params.size(); ++k) EXPECT_NEAR(rm.params[k], m.params[k], 1e-12 * std::abs(m.params[k]));
}

TEST(StrengthReduction, KeepTensionLeavesFtAndGI) {
  const JointProperties p = joint();
  const JointProperties r = law::reduce_joint(p, 2.0, {.keep_tension = true});
  EXPECT_EQ(r.ft, p.ft);
  EXPECT_EQ(r.GI, p.GI);
  EXPECT_DOUBLE_EQ(r.c, p.c / 2.0);
  EXPECT_EQ(validate(r), "");
}

TEST(StrengthReduction, BelowOneTheJointStaysAdmissible) {
  // F < 1 raises ft; past c'/tan(phi') eq. 8 would leave no shear strength: capped.
  JointProperties p = joint();
  p.ft = 0.9 * p.c / std::tan(p.phi);
  const JointProperties r = law::reduce_joint(p, 0.5);
  EXPECT_LT(r.ft, r.c / std::tan(r.phi));
  EXPECT_EQ(validate(r), "");
}

TEST(StrengthReduction, MohrCoulombMaterial) {
  namespace mc = law::mohr_coulomb;
  const Material m = mohr_coulomb(1e4);
  const double F = 1.5;
  const Material r = law::reduce_material(m, F);
  EXPECT_DOUBLE_EQ(r.params[mc::cohesion], 2e4 / F);
  EXPECT_NEAR(std::tan(r.params[mc::friction_angle] * kDeg), std::tan(30 * kDeg) / F, 1e-14);
  EXPECT_NEAR(std::tan(r.params[mc::dilation_angle] * kDeg), std::tan(10 * kDeg) / F, 1e-14);
  EXPECT_LE(r.params[mc::dilation_angle], r.params[mc::friction_angle]);
  EXPECT_DOUBLE_EQ(r.params[mc::tensile_strength], 1e4 / F);
  EXPECT_EQ(r.params[mc::E], m.params[mc::E]);
  // The apex c/tan(phi) does not move with F: a cut-off at the apex stays there (F < 1 too).
  const double apex = 2e4 / std::tan(30 * kDeg);
  const Material at_apex = law::reduce_material(mohr_coulomb(apex), 0.7);
  EXPECT_LE(at_apex.params[mc::tensile_strength], apex);
  // phi = 0 (undrained clay): c/F, no cut-off stays none.
  Material clay = mohr_coulomb(std::numeric_limits<double>::infinity());
  clay.params[mc::friction_angle] = 0;
  clay.params[mc::dilation_angle] = 0;
  const Material rc = law::reduce_material(clay, 2.0);
  EXPECT_DOUBLE_EQ(rc.params[mc::cohesion], 1e4);
  EXPECT_EQ(rc.params[mc::friction_angle], 0.0);
  EXPECT_TRUE(std::isinf(rc.params[mc::tensile_strength]));
}

// Drucker-Prager reduces the same envelope: c / F, tan(phi) / F, tan(psi) / F.
TEST(StrengthReduction, DruckerPragerMaterial) {
  namespace dp = law::drucker_prager;
  Material m;
  m.name = "soil";
  m.model = std::string(dp::kName);
  m.params = {5e7, 0.3, 1900, 2e4, 30, 10};
  ASSERT_EQ(m.params.size(), static_cast<std::size_t>(dp::kParams));
  const Material r = law::reduce_material(m, 1.5);
  EXPECT_DOUBLE_EQ(r.params[dp::cohesion], 2e4 / 1.5);
  EXPECT_NEAR(std::tan(r.params[dp::friction_angle] * kDeg), std::tan(30 * kDeg) / 1.5, 1e-14);
  EXPECT_NEAR(std::tan(r.params[dp::dilation_angle] * kDeg), std::tan(10 * kDeg) / 1.5, 1e-14);
  EXPECT_EQ(r.params[dp::E], 5e7);
}

TEST(StrengthReduction, ElasticMaterialUntouchedContactFrictionReduced) {
  Material e;
  e.name = "rock";
  e.E = 1e10;
  e.params = {1e10, 0.25, 2600};
  const Material r = law::reduce_material(e, 2.0);
  EXPECT_EQ(r.params, e.params);
  ContactProperties c;
  c.kn = 1e9;
  c.mu = 0.6;
  EXPECT_DOUBLE_EQ(law::reduce_contact(c, 1.5).mu, 0.4);
  EXPECT_EQ(law::reduce_contact(c, 1.5).kn, c.kn);
}

TEST(StrengthReduction, ApplyToModelFromTheFullStrengths) {
  Model model;
  model.joint_properties = {joint()};
  model.materials = {mohr_coulomb(1e4)};
  model.contact.defaults.mu = 0.5;
  model.contact.pairs.push_back({0, 0, ContactProperties{1e9, 1e9, 0.7, 1.0}});
  const law::FullStrengths full = law::full_strengths(model);
  law::apply_reduction(full, 2.0, {}, model);
  law::apply_reduction(full, 1.25, {}, model);  // from the full strengths, not compounded
  EXPECT_DOUBLE_EQ(model.joint_properties[0].c, joint().c / 1.25);
  EXPECT_DOUBLE_EQ(model.materials[0].params[law::mohr_coulomb::cohesion], 2e4 / 1.25);
  EXPECT_DOUBLE_EQ(model.contact.defaults.mu, 0.4);
  EXPECT_DOUBLE_EQ(model.contact.pairs[0].props.mu, 0.7 / 1.25);
}
