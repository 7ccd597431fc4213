// The ensemble file (docs/theory.md §13): validated as a whole, errors with file, line and key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ensemble/ensemble_file.hpp"

using namespace dsdem;
using namespace dsdem::ensemble;

namespace {

const std::string kBase = std::string(DSDEM_TEST_DATA_DIR) + "/ensemble/incline.yaml";

std::string head(const std::string& extra = "", int members = 10) {
  return "base: " + kBase + "\nmembers: " + std::to_string(members) + "\n" + extra;
}

// All error lines of a file that must fail.
std::string errors_of(const std::string& text) {
  try {
    parse_ensemble(text, "ens.yaml");
  } catch (const io::ScenarioError& e) {
    std::string all;
    for (const auto& l : e.errors()) all += l + "\n";
    return all;
  }
  return "";
}

}  // namespace

TEST(EnsembleFile, ReadsEveryPartAndPlansReproducibly) {
  const auto spec = parse_ensemble(head(R"(sampling: {method: monte_carlo, seed: 9}
vary:
  - {key: contact.friction, name: mu, distribution: uniform, lower: 0.1, upper: 0.5}
  - {key: [contact.restitution], distribution: triangular, lower: 0.1, mode: 0.2, upper: 0.35}
  - {key: materials.rock.E, distribution: lognormal, mean: 1.0e8, sd: 2.0e7}
  - {key: materials.rock.rho, distribution: normal, mean: 2500, sd: 100, lower: 2300}
  - {key: output.history_interval, distribution: list, values: [0.01, 0.02], weights: [3, 1]}
  - {key: time.end, distribution: integer, lower: 1, upper: 3}
correlation:
  - {between: [mu, contact.restitution], rank: 0.5}
fixed:
  time.safety: 0.25
events:
  - gauges.block.max_displacement_m > 0.3
  - {name: slow, when: "gauges.block.peak_velocity_mps <= 1"}
member: {threads: 1, fields: false}
)"),
                                   "ens.yaml");
  EXPECT_EQ(spec.members, 10u);
  EXPECT_EQ(spec.method, SamplingMethod::MonteCarlo);
  EXPECT_EQ(spec.seed, 9u);
  ASSERT_EQ(spec.vary.size(), 6u);
  EXPECT_EQ(spec.vary[0].name, "mu");
  EXPECT_EQ(spec.vary[1].name, "contact.restitution");
  EXPECT_EQ(spec.correlation[0][1], 0.5);
  EXPECT_EQ(spec.fixed, (std::vector<std::string>{"time.safety=0.25"}));
  ASSERT_EQ(spec.events.size(), 2u);
  EXPECT_EQ(spec.events[1].name, "slow");
  EXPECT_TRUE(spec.events[1].holds(1.0));
  EXPECT_FALSE(spec.events[0].holds(0.3));
  const auto plans = plan_members(spec);
  EXPECT_EQ(plans.size(), 10u);
  EXPECT_EQ(plans[3].sets.front(), "time.safety=0.25");
  EXPECT_EQ(plans[3].sets.size(), 7u);
  for (const auto& p : plans) {
    EXPECT_TRUE(p.values[4] == "0.01" || p.values[4] == "0.02");
    EXPECT_TRUE(p.values[5] == "1" || p.values[5] == "2" || p.values[5] == "3");
    EXPECT_GE(p.numbers[3], 2300.0);
  }
  EXPECT_EQ(plan_members(spec)[7].sets, plans[7].sets);
  validate_members(spec, plans);
}

TEST(EnsembleFile, UnknownKeysAreNamedWithTheirLine) {
  const auto e = errors_of(head("smapling: {seed: 1}\nvary:\n  - {key: contact.friction, distribution: uniform, lower: 0, upper: 1, lowr: 2}\n"));
  EXPECT_NE(e.find("ens.yaml:3:1: smapling: unknown key; did you mean 'sampling'?"), std::string::npos) << e;
  EXPECT_NE(e.find("ens.yaml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("vary[0].lowr: unknown key; did you mean 'lower'?"), std::string::npos) << e;
}

TEST(EnsembleFile, AVariedKeyTheBaseScenarioLacksIsAnError) {
  const auto e = errors_of(head("vary:\n  - {key: contact.frictoin, distribution: uniform, lower: 0.1, upper: 0.5}\n"));
  EXPECT_NE(e.find("ens.yaml:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("vary[0].key: contact.frictoin=0.3"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'friction'"), std::string::npos) << e;
  // A value the base scenario refuses, in some members only: the member and the key are named.
  const auto spec = parse_ensemble(head("vary:\n  - {key: contact.friction, distribution: normal, mean: 0.1, sd: 0.2}\n", 40), "ens.yaml");
  try {
    validate_members(spec, plan_members(spec));
    FAIL() << "negative friction accepted";
  } catch (const io::ScenarioError& err) {
    EXPECT_NE(std::string(err.what()).find("member "), std::string::npos) << err.what();
    EXPECT_NE(std::string(err.what()).find("ens.yaml:4:"), std::string::npos) << err.what();
    EXPECT_NE(std::string(err.what()).find("contact.friction"), std::string::npos) << err.what();
  }
  // A fixed override the base lacks.
  const auto f = errors_of(head("fixed: {time.saftey: 0.2}\nvary:\n  - {key: contact.friction, distribution: uniform, lower: 0.1, upper: 0.5}\n"));
  EXPECT_NE(f.find("ens.yaml:3:9: fixed.time.saftey"), std::string::npos) << f;
}

TEST(EnsembleFile, ImpossibleDistributionsAndZeroMembersAreClearErrors) {
  auto one = [](const std::string& dist) { return errors_of(head("vary:\n  - {key: contact.friction, " + dist + "}\n")); };
  EXPECT_NE(one("distribution: normal, mean: 0.3, sd: 0").find("vary[0].sd: impossible normal distribution: sd must be > 0"),
            std::string::npos);
  EXPECT_NE(one("distribution: normal, mean: 0.3, sd: -1").find("sd must be > 0, got -1"), std::string::npos);
  EXPECT_NE(one("distribution: uniform, lower: 0.5, upper: 0.1").find("vary[0].lower: impossible uniform distribution: lower (0.5) must be below upper (0.1)"),
            std::string::npos);
  EXPECT_NE(one("distribution: triangular, lower: 0.1, mode: 0.9, upper: 0.5").find("vary[0].mode: impossible triangular distribution: mode (0.9) must lie in [lower, upper]"),
            std::string::npos);
  EXPECT_NE(one("distribution: lognormal, mean: 0.3").find("vary[0].sd: missing value (a lognormal distribution takes mean, sd)"),
            std::string::npos);
  EXPECT_NE(one("distribution: uniform, lower: 0.1, upper: 0.5, mode: 0.2").find("a uniform distribution takes lower, upper, not mode"),
            std::string::npos);
  EXPECT_NE(one("distribution: gaussian, mean: 0.3, sd: 0.1").find("'gaussian' is not one of"), std::string::npos);
  EXPECT_NE(one("distribution: list, values: [0.2, 0.3], weights: [1]").find("weights has 1 entries for 2 values"),
            std::string::npos);
  EXPECT_NE(one("distribution: integer, lower: 1.5, upper: 4").find("must be integers"), std::string::npos);
  const auto zero = errors_of(head("vary:\n  - {key: contact.friction, distribution: uniform, lower: 0.1, upper: 0.5}\n", 0));
  EXPECT_NE(zero.find("ens.yaml:2:10: members: 0 is out of range: must be >= 1"), std::string::npos) << zero;
  const auto none = errors_of(head("vary: []\n"));
  EXPECT_NE(none.find("vary: no varied value"), std::string::npos) << none;
  const auto corr = errors_of(head(R"(vary:
  - {key: contact.friction, name: a, distribution: uniform, lower: 0.1, upper: 0.5}
  - {key: contact.restitution, name: b, distribution: uniform, lower: 0.1, upper: 0.5}
correlation:
  - {between: [a, c], rank: 0.5}
  - {between: [a, b], rank: 1.5}
)"));
  EXPECT_NE(corr.find("'c' is not the name of a varied value"), std::string::npos) << corr;
  EXPECT_NE(corr.find("correlation[1].rank: 1.5 is out of range"), std::string::npos) << corr;
  const auto ev = errors_of(head("vary:\n  - {key: contact.friction, distribution: uniform, lower: 0.1, upper: 0.5}\nevents: [\"gauges.x.max_displacement_m >> 3\"]\n"));
  EXPECT_NE(ev.find("is not a condition"), std::string::npos) << ev;
  const auto base = errors_of("base: nowhere.yaml\nmembers: 3\nvary:\n  - {key: a, distribution: uniform, lower: 0, upper: 1}\n");
  EXPECT_NE(base.find("ens.yaml:1:7: base: the base scenario 'nowhere.yaml' does not exist"), std::string::npos) << base;
}

// docs/ensemble-reference.md ends with the generated key table (dsdem schema --ensemble).
TEST(EnsembleFile, ReferenceDocHasTheKeyTable) {
  std::ifstream in(std::string(DSDEM_SOURCE_DIR) + "/docs/ensemble-reference.md");
  ASSERT_TRUE(in.good());
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_NE(s.str().find(ensemble_schema_markdown()), std::string::npos)
      << "regenerate the table at the end of docs/ensemble-reference.md: ./build/dsdem schema --ensemble";
}
