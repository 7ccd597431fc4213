// The law registries (docs/developer-guide.md §5): lookup by name with a loud error, and declarations
// complete enough to build the schema, the state arrays and the outputs from.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "law/laws.hpp"
#include "law/registry.hpp"

using namespace dsdem;

namespace {

const law::Category kCategories[] = {law::Category::Material, law::Category::Joint, law::Category::Contact};

}  // namespace

TEST(LawRegistry, UnknownNameNamesTheValidOnes) {
  try {
    law::material_laws().get("mohr_colomb");
    FAIL() << "no exception";
  } catch (const law::UnknownLaw& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("unknown material law 'mohr_colomb'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("linear_elastic, mohr_coulomb"), std::string::npos) << msg;
  }
  EXPECT_THROW(law::joint_laws().get("linear_elastic"), law::UnknownLaw);
  EXPECT_THROW(law::contact_laws().get(""), law::UnknownLaw);
  EXPECT_EQ(law::material_laws().find("nope"), nullptr);
  EXPECT_EQ(law::material_laws().index("nope"), -1);
}

TEST(LawRegistry, RegisteredLawsAndDefaults) {
  EXPECT_EQ(law::material_laws().names(), (std::vector<std::string>{"linear_elastic", "mohr_coulomb", "drucker_prager"}));
  EXPECT_EQ(law::joint_laws().names(), (std::vector<std::string>{"cohesive"}));
  EXPECT_EQ(law::contact_laws().names(), (std::vector<std::string>{"spring_dashpot_coulomb"}));
  // The default law of each category is the first registered (Material::law = 0).
  EXPECT_EQ(law::material_laws().index(law::kDefaultMaterialLaw), 0);
  EXPECT_EQ(law::joint_laws().index(law::kDefaultJointLaw), 0);
  EXPECT_EQ(law::contact_laws().index(law::kDefaultContactLaw), 0);
  for (const auto c : kCategories) EXPECT_EQ(&law::registry(c), &law::registry(c));
  EXPECT_EQ(&law::registry(law::Category::Joint), &law::joint_laws());
}

TEST(LawRegistry, AddRefusesDuplicatesAndOtherCategories) {
  law::Registry r(law::Category::Material);
  r.add(law::linear_elastic_decl());
  EXPECT_THROW(r.add(law::linear_elastic_decl()), std::logic_error);
  EXPECT_THROW(r.add(law::cohesive_joint_decl()), std::logic_error);
  EXPECT_EQ(r.size(), 1u);
}

// Everything the schema, the docs, the state arrays and the outputs read is there.
TEST(LawRegistry, DeclarationsAreComplete) {
  for (const auto c : kCategories) {
    for (const auto& l : law::registry(c).laws()) {
      SCOPED_TRACE(l.name);
      EXPECT_EQ(l.category, c);
      EXPECT_FALSE(l.doc.empty());
      EXPECT_FALSE(l.params.empty());
      std::set<std::string> names;
      for (const auto& p : l.params) {
        SCOPED_TRACE(p.name);
        EXPECT_FALSE(p.name.empty());
        EXPECT_TRUE(names.insert(p.name).second) << "declared twice";
        EXPECT_FALSE(p.doc.empty());
        EXPECT_EQ(p.doc.back(), '.');
        EXPECT_LE(p.min, p.max);
        // A numeric default lies in the allowed range.
        if (!p.default_text.empty() && !p.required()) {
          try {
            const double d = std::stod(p.default_text);
            EXPECT_TRUE(p.min_exclusive ? d > p.min : d >= p.min) << d;
            EXPECT_TRUE(p.max_exclusive ? d < p.max : d <= p.max) << d;
          } catch (const std::invalid_argument&) {
            // a rule ("c / tan(phi)", "p*E/h"): the law or its caller computes it
          }
        }
      }
      for (const auto& s : l.state) {
        SCOPED_TRACE(s.name);
        EXPECT_FALSE(s.name.empty());
        EXPECT_TRUE(names.insert(s.name).second) << "a state variable named like a parameter or twice";
        EXPECT_FALSE(s.doc.empty());
      }
    }
  }
}

// Laws of one category that share a parameter name declare it alike (one schema key).
TEST(LawRegistry, SharedParametersAreDeclaredAlike) {
  for (const auto c : kCategories) {
    const auto& laws = law::registry(c).laws();
    for (const auto& a : laws)
      for (const auto& b : laws)
        for (const auto& p : a.params) {
          const int i = b.param_index(p.name);
          if (i < 0) continue;
          const auto& q = b.params[static_cast<std::size_t>(i)];
          EXPECT_EQ(p.unit, q.unit) << p.name;
          EXPECT_EQ(p.default_text, q.default_text) << p.name;
          EXPECT_EQ(p.min, q.min) << p.name;
          EXPECT_EQ(p.max, q.max) << p.name;
          EXPECT_EQ(p.doc, q.doc) << p.name;
        }
  }
}

// The elastic kernel and the stable time step read E, nu, rho of every bulk law.
TEST(LawRegistry, EveryMaterialLawDeclaresTheElasticConstantsFirst) {
  for (const auto& l : law::material_laws().laws()) {
    ASSERT_GE(l.params.size(), 3u) << l.name;
    EXPECT_EQ(l.params[0].name, "E") << l.name;
    EXPECT_EQ(l.params[1].name, "nu") << l.name;
    EXPECT_EQ(l.params[2].name, "rho") << l.name;
  }
}

TEST(LawRegistry, PositionsMatchTheDeclarations) {
  const auto& le = law::material_laws().get("linear_elastic");
  EXPECT_EQ(le.params.size(), std::size_t(law::linear_elastic::kParams));
  EXPECT_EQ(le.param_index("rho"), law::linear_elastic::rho);
  const auto& mc = law::material_laws().get("mohr_coulomb");
  namespace m = law::mohr_coulomb;
  ASSERT_EQ(mc.params.size(), std::size_t(m::kParams));
  EXPECT_EQ(mc.param_index("E"), m::E);
  EXPECT_EQ(mc.param_index("nu"), m::nu);
  EXPECT_EQ(mc.param_index("rho"), m::rho);
  EXPECT_EQ(mc.param_index("cohesion"), m::cohesion);
  EXPECT_EQ(mc.param_index("friction_angle"), m::friction_angle);
  EXPECT_EQ(mc.param_index("dilation_angle"), m::dilation_angle);
  EXPECT_EQ(mc.param_index("tensile_strength"), m::tensile_strength);
  ASSERT_EQ(mc.state.size(), std::size_t(m::kStates));
  EXPECT_EQ(mc.state[m::plastic_strain_xx].name, "plastic_strain_xx");
  EXPECT_EQ(mc.state[m::plastic_strain_yy].name, "plastic_strain_yy");
  EXPECT_EQ(mc.state[m::plastic_strain_xy].name, "plastic_strain_xy");
  EXPECT_EQ(mc.state[m::plastic_strain_zz].name, "plastic_strain_zz");
  EXPECT_EQ(mc.state[m::plastic_dissipation].name, "plastic_dissipation");
  EXPECT_EQ(mc.state[m::plastic_dissipation].unit, "J/m^3");
  const auto& dp = law::material_laws().get("drucker_prager");
  namespace d = law::drucker_prager;
  ASSERT_EQ(dp.params.size(), std::size_t(d::kParams));
  EXPECT_EQ(dp.param_index("cohesion"), d::cohesion);
  EXPECT_EQ(dp.param_index("friction_angle"), d::friction_angle);
  EXPECT_EQ(dp.param_index("dilation_angle"), d::dilation_angle);
  ASSERT_EQ(dp.state.size(), std::size_t(d::kStates));
  for (std::size_t k = 0; k < dp.state.size(); ++k) EXPECT_EQ(dp.state[k].name, mc.state[k].name) << k;
}

TEST(LawRegistry, MohrCoulombDeclaration) {
  const auto& mc = law::material_laws().get("mohr_coulomb");
  namespace m = law::mohr_coulomb;
  EXPECT_TRUE(mc.params[m::cohesion].required());
  EXPECT_TRUE(mc.params[m::friction_angle].required());
  EXPECT_TRUE(mc.params[m::friction_angle].max_exclusive);
  EXPECT_EQ(mc.params[m::friction_angle].max, 90.0);
  EXPECT_EQ(mc.params[m::dilation_angle].default_text, "0");
  EXPECT_EQ(mc.params[m::tensile_strength].default_text, "c / tan(phi)");
  // The default cut-off is the apex of the envelope, none for phi = 0.
  const auto& rule = mc.params[m::tensile_strength].rule;
  ASSERT_TRUE(rule);
  std::vector<double> v{1e9, 0.3, 2000, 1e5, 30, 0};
  EXPECT_DOUBLE_EQ(rule(mc, v), 1e5 / std::tan(30.0 * 3.14159265358979323846 / 180.0));
  v[m::friction_angle] = 0;
  EXPECT_EQ(rule(mc, v), std::numeric_limits<double>::infinity());
  // Cross-checks: psi <= phi, cut-off at most the apex.
  ASSERT_TRUE(mc.check);
  std::vector<double> ok{1e9, 0.3, 2000, 1e5, 30, 30, 1e4};
  EXPECT_TRUE(mc.check(mc, ok).empty());
  std::vector<double> bad = ok;
  bad[m::dilation_angle] = 31;
  bad[m::tensile_strength] = 2e5;
  const auto problems = mc.check(mc, bad);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].param, "dilation_angle");
  EXPECT_EQ(problems[1].param, "tensile_strength");
  EXPECT_THROW(mc.value(ok, "friction"), std::logic_error);
}

// The envelope's apex and the angle conversions several declarations and kernels share.
TEST(LawRegistry, EnvelopeApexAndAngles) {
  EXPECT_DOUBLE_EQ(law::envelope_apex(1e5, law::radians(30)), 1e5 / std::tan(30.0 * 3.14159265358979323846 / 180.0));
  EXPECT_EQ(law::envelope_apex(1e5, 0.0), std::numeric_limits<double>::infinity());
  for (double deg : {0.0, 12.5, 30.0, 89.9}) EXPECT_NEAR(law::degrees(law::radians(deg)), deg, 1e-13);
}

// Every law with a strength reduces itself (strength reduction asks the declaration); a
// law without one has no reduction.
TEST(LawRegistry, LawsWithAStrengthReduceThemselves) {
  EXPECT_FALSE(law::material_laws().get("linear_elastic").reduce);
  EXPECT_TRUE(law::material_laws().get("mohr_coulomb").reduce);
  EXPECT_TRUE(law::material_laws().get("drucker_prager").reduce);
}
