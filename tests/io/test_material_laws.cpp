// Laws chosen by name in the scenario (law/registry.hpp): the parameters each declares,
// its cross-checks, and keys of another law, each error with file, line and key.
#include <gtest/gtest.h>

#include <cmath>

#include "io/scenario.hpp"
#include "io/schema.hpp"
#include "law/laws.hpp"

using namespace dsdem;

namespace {

const std::string kScenario = R"(mesh:
  file: DATA/mesh/square.geo
  element_size: 0.25
materials:
  soil:
    model: mohr_coulomb
    E: 50.0e6
    nu: 0.3
    rho: 1800
    cohesion: 20.0e3
    friction_angle: 30
    dilation_angle: 5
regions:
  - group: block
    material: soil
time:
  end: 0.01
)";

std::string scenario(const std::string& from = "", const std::string& to = "") {
  std::string s = kScenario;
  s.replace(s.find("DATA"), 4, DSDEM_TEST_DATA_DIR);
  if (!from.empty()) {
    const auto pos = s.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    if (pos != std::string::npos) s.replace(pos, from.size(), to);
  }
  return s;
}

std::vector<std::string> errors_of(const std::string& text) {
  try {
    io::parse_scenario(text, "case.yaml");
  } catch (const io::ScenarioError& e) {
    return e.errors();
  }
  return {};
}

::testing::AssertionResult has_error(const std::vector<std::string>& errors, const std::string& expected) {
  for (const auto& e : errors)
    if (e.find(expected) != std::string::npos) return ::testing::AssertionSuccess();
  std::string all;
  for (const auto& e : errors) all += "\n  " + e;
  return ::testing::AssertionFailure() << "no error containing '" << expected << "' in:" << all;
}

}  // namespace

TEST(MaterialLaws, MohrCoulombParses) {
  const io::Scenario sc = io::parse_scenario(scenario(), "case.yaml");
  const Material& m = sc.materials.at("soil");
  namespace mc = law::mohr_coulomb;
  EXPECT_EQ(m.model, "mohr_coulomb");
  EXPECT_EQ(m.law, law::material_laws().index("mohr_coulomb"));
  ASSERT_EQ(m.params.size(), std::size_t(mc::kParams));
  EXPECT_EQ(m.E, 50e6);
  EXPECT_EQ(m.nu, 0.3);
  EXPECT_EQ(m.rho, 1800);
  EXPECT_EQ(m.params[mc::E], 50e6);
  EXPECT_EQ(m.params[mc::cohesion], 20e3);
  EXPECT_EQ(m.params[mc::friction_angle], 30);
  EXPECT_EQ(m.params[mc::dilation_angle], 5);
  // Default cut-off: the apex c / tan(phi).
  EXPECT_DOUBLE_EQ(m.params[mc::tensile_strength], 20e3 / std::tan(30.0 * 3.14159265358979323846 / 180.0));
}

TEST(MaterialLaws, DefaultsAndGivenCutOff) {
  std::string s = scenario("    dilation_angle: 5\n", "    tensile_strength: 1000\n");
  const io::Scenario sc = io::parse_scenario(s, "case.yaml");
  const Material& m = sc.materials.at("soil");
  EXPECT_EQ(m.params[law::mohr_coulomb::dilation_angle], 0.0);
  EXPECT_EQ(m.params[law::mohr_coulomb::tensile_strength], 1000.0);
  // phi = 0 (Tresca): no apex, no cut-off by default.
  const io::Scenario t = io::parse_scenario(scenario("friction_angle: 30\n    dilation_angle: 5", "friction_angle: 0"), "case.yaml");
  EXPECT_EQ(t.materials.at("soil").params[law::mohr_coulomb::tensile_strength], std::numeric_limits<double>::infinity());
}

TEST(MaterialLaws, LinearElasticKeepsItsValues) {
  std::string s = scenario("    model: mohr_coulomb\n", "");
  s = s.substr(0, s.find("    cohesion")) + s.substr(s.find("regions:"));
  const io::Scenario sc = io::parse_scenario(s, "case.yaml");
  const Material& m = sc.materials.at("soil");
  EXPECT_EQ(m.model, "linear_elastic");
  EXPECT_EQ(m.law, 0);
  EXPECT_EQ(m.params, (std::vector<double>{50e6, 0.3, 1800}));
  EXPECT_EQ(m.E, 50e6);
  EXPECT_EQ(m.nu, 0.3);
  EXPECT_EQ(m.rho, 1800);
}

TEST(MaterialLaws, MissingCohesionNamesFileLineAndKey) {
  const auto errors = errors_of(scenario("    cohesion: 20.0e3\n", ""));
  EXPECT_TRUE(has_error(errors, "case.yaml:6:5: materials.soil.cohesion: missing value (mohr_coulomb, drucker_prager: Cohesion c of the Mohr-Coulomb envelope, in Pa)"));
  EXPECT_EQ(errors.size(), 1u);
}

TEST(MaterialLaws, DilationAboveFrictionIsAnError) {
  const auto errors = errors_of(scenario("dilation_angle: 5", "dilation_angle: 35"));
  EXPECT_TRUE(has_error(errors, "case.yaml:12:21: materials.soil.dilation_angle: 35 deg exceeds friction_angle 30 deg"));
  EXPECT_EQ(errors.size(), 1u);
}

TEST(MaterialLaws, CutOffAboveTheApexIsAnError) {
  const auto errors = errors_of(scenario("    dilation_angle: 5\n", "    tensile_strength: 1.0e5\n"));
  EXPECT_TRUE(has_error(errors, "materials.soil.tensile_strength: 100000 Pa is above the apex"));
}

TEST(MaterialLaws, OutOfRangeFrictionAngle) {
  const auto errors = errors_of(scenario("friction_angle: 30", "friction_angle: 90"));
  EXPECT_TRUE(has_error(errors, "materials.soil.friction_angle: 90 is out of range: must be >= 0 and < 90 deg"));
}

TEST(MaterialLaws, KeyOfAnotherModelIsAnError) {
  // A Mohr-Coulomb parameter on a linear elastic material.
  const auto errors = errors_of(scenario("model: mohr_coulomb", "model: linear_elastic"));
  EXPECT_TRUE(has_error(errors, "case.yaml:10:5: materials.soil.cohesion: 'cohesion' belongs to model mohr_coulomb or drucker_prager, "
                                "not to model linear_elastic chosen here (set model: mohr_coulomb or remove the key)"));
  EXPECT_TRUE(has_error(errors, "materials.soil.friction_angle: 'friction_angle' belongs to model mohr_coulomb"));
  EXPECT_TRUE(has_error(errors, "materials.soil.dilation_angle: 'dilation_angle' belongs to model mohr_coulomb"));
  EXPECT_EQ(errors.size(), 3u);
  // The same without model: linear_elastic is the default.
  EXPECT_EQ(errors_of(scenario("    model: mohr_coulomb\n", "")).size(), 3u);
}

TEST(MaterialLaws, UnknownModelNamesTheValidOnes) {
  const auto errors = errors_of(scenario("model: mohr_coulomb", "model: mohr_colomb"));
  EXPECT_TRUE(has_error(errors, "materials.soil.model: 'mohr_colomb' is not one of: linear_elastic, mohr_coulomb, drucker_prager; "
                                "did you mean 'mohr_coulomb'?"));
}

TEST(MaterialLaws, SchemaKeysComeFromTheDeclarations) {
  const io::KeySpec* model = io::find_spec("materials.*.model");
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->choices, law::material_laws().names());
  for (const auto& l : law::material_laws().laws())
    for (const auto& p : l.params) {
      const io::KeySpec* k = io::find_spec("materials.*." + p.name);
      ASSERT_NE(k, nullptr) << p.name;
      EXPECT_EQ(k->unit, p.unit);
      EXPECT_EQ(k->default_text, p.default_text);
      EXPECT_EQ(k->min, p.min);
      EXPECT_EQ(k->max, p.max);
    }
  // Used by one model only: the doc says which.
  EXPECT_EQ(io::find_spec("materials.*.cohesion")->doc, "mohr_coulomb, drucker_prager: Cohesion c of the Mohr-Coulomb envelope.");
  EXPECT_EQ(io::find_spec("materials.*.E")->doc, "Young's modulus.");
  // Joint and contact laws: the law keys and their parameters.
  EXPECT_EQ(io::find_spec("joints.default.law")->default_text, "cohesive");
  EXPECT_EQ(io::find_spec("joints.groups.*.law")->choices, law::joint_laws().names());
  EXPECT_EQ(io::find_spec("joints.default.ft")->default_text, "required");
  EXPECT_EQ(io::find_spec("joints.curves.*.ft")->default_text, "");
  EXPECT_EQ(io::find_spec("contact.law")->default_text, "spring_dashpot_coulomb");
  for (const auto& p : law::contact_laws().get("spring_dashpot_coulomb").params)
    EXPECT_NE(io::find_spec("contact." + p.name), nullptr) << p.name;
}

TEST(MaterialLaws, JointAndContactLawKeys) {
  const std::string joints = "joints:\n  default:\n    law: cohesive\n    ft: 1.0e6\n    c: 2.0e6\n    phi: 30\n"
                             "    GI: 10\n    GII: 50\n  curves:\n    crack:\n      ft: 1.0e5\n";
  const std::string contact = "contact:\n  law: spring_dashpot_coulomb\n  friction: 0.3\n";
  const io::Scenario sc = io::parse_scenario(scenario() + joints + contact, "case.yaml");
  EXPECT_EQ(sc.joints.defaults.law.value_or(""), "cohesive");
  EXPECT_EQ(sc.joints.defaults.merged(sc.joints.curves.at("crack")).law.value_or(""), "cohesive");
  EXPECT_EQ(sc.contact.law, "spring_dashpot_coulomb");
  // Absent: the default laws.
  const io::Scenario d = io::parse_scenario(scenario() + "joints:\n  default:\n    ft: 1.0e6\n    c: 2.0e6\n"
                                                         "    phi: 30\n    GI: 10\n    GII: 50\n", "case.yaml");
  EXPECT_EQ(d.joints.defaults.law.value_or(""), "cohesive");
  EXPECT_EQ(d.contact.law, "spring_dashpot_coulomb");
  auto errors = errors_of(scenario() + "contact:\n  law: hertz\n");
  EXPECT_TRUE(has_error(errors, "case.yaml:19:8: contact.law: 'hertz' is not one of: spring_dashpot_coulomb"));
  errors = errors_of(scenario() + "joints:\n  default:\n    law: czm\n    ft: 1.0e6\n    c: 2.0e6\n    phi: 30\n"
                                  "    GI: 10\n    GII: 50\n");
  EXPECT_TRUE(has_error(errors, "joints.default.law: 'czm' is not one of: cohesive"));
}

// Joint and pair parameters are kept by their declared names: a set of overrides gives only
// what it names, merged over joints.default; a pair takes the contact law's per-pair
// parameters, and a parameter the law does not declare per pair is an unknown key there.
TEST(MaterialLaws, GivenParametersGoByTheirDeclaredNames) {
  const std::string joints = "joints:\n  default:\n    ft: 1.0e6\n    c: 2.0e6\n    phi: 30\n    GI: 10\n    GII: 50\n"
                             "    penalty: 20\n  curves:\n    crack:\n      ft: 1.0e5\n      kn: 3.0e12\n";
  const std::string contact = "contact:\n  friction: 0.3\n  pairs:\n    - groups: [a, b]\n      friction: 0.6\n"
                              "      restitution: 0.2\n";
  const io::Scenario sc = io::parse_scenario(scenario() + joints + contact, "case.yaml");
  const io::JointSpec& d = sc.joints.defaults;
  for (const auto& p : law::joint_laws().get("cohesive").params)
    EXPECT_EQ(d.params.get(p.name).has_value(), p.name != "kn" && p.name != "ks") << p.name;
  EXPECT_EQ(d.params.get("penalty"), 20.0);
  const io::JointSpec crack = d.merged(sc.joints.curves.at("crack"));
  EXPECT_EQ(sc.joints.curves.at("crack").params.values.size(), 2u);
  EXPECT_EQ(crack.params.get("ft"), 1.0e5);
  EXPECT_EQ(crack.params.get("kn"), 3.0e12);
  EXPECT_EQ(crack.params.get("c"), 2.0e6);
  EXPECT_EQ(crack.params.get("penalty"), 20.0);
  ASSERT_EQ(sc.contact.pairs.size(), 1u);
  const io::GivenParams& pair = sc.contact.pairs[0].params;
  EXPECT_EQ(pair.get("friction"), 0.6);
  EXPECT_EQ(pair.get("restitution"), 0.2);
  EXPECT_FALSE(pair.get("kn").has_value());
  // The pair keys are the law's per-pair parameters, and only those.
  for (const auto& p : law::contact_laws().get("spring_dashpot_coulomb").params)
    EXPECT_EQ(io::find_spec("contact.pairs[]." + p.name) != nullptr, p.per_pair) << p.name;
  const auto errors = errors_of(scenario() + "contact:\n  pairs:\n    - groups: [a, b]\n      ks_ratio: 0.5\n");
  EXPECT_TRUE(has_error(errors, "contact.pairs[0].ks_ratio: unknown key"));
}

TEST(MaterialLaws, MohrCoulombIsPlaneStrainOnly) {
  const auto errors = errors_of(scenario("  element_size: 0.25\n", "  element_size: 0.25\n  plane: stress\n"));
  EXPECT_TRUE(has_error(errors, "case.yaml:7:12: materials.soil.model: mohr_coulomb is plane strain only"));
  EXPECT_EQ(errors.size(), 1u);
}
