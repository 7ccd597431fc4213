// Scenario validation: every error names file, line, column and key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "io/scenario.hpp"
#include "io/schema.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"

using namespace dsdem;

namespace {

const std::string kGood = R"(title: test
mesh:
  file: DATA/mesh/square.geo
  element_size: 0.25
materials:
  rock:
    E: 10.0e9
    nu: 0.25
    rho: 2500
regions:
  - group: block
    material: rock
boundaries:
  - group: bottom
    type: fixed
time:
  end: 0.01
output:
  gauges:
    - name: top
      at: [0.5, 1.0]
)";

std::string good() {
  std::string s = kGood;
  s.replace(s.find("DATA"), 4, DSDEM_TEST_DATA_DIR);
  return s;
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) s.replace(pos, from.size(), to);
  return s;
}

std::vector<std::string> errors_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    io::parse_scenario(text, "case.yaml", sets);
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

TEST(Scenario, GoodScenarioParses) {
  const io::Scenario sc = io::parse_scenario(good(), "case.yaml");
  EXPECT_EQ(sc.materials.at("rock").E, 10e9);
  ASSERT_EQ(sc.stages.size(), 1u);
  EXPECT_DOUBLE_EQ(sc.end_time(), 0.01);
  EXPECT_DOUBLE_EQ(sc.safety, 0.3);
  EXPECT_DOUBLE_EQ(sc.output.field_interval, 0.01 / 50);
  EXPECT_EQ(sc.gravity, Vec2(0, -9.81));
  ASSERT_EQ(sc.output.gauges.size(), 1u);
}

TEST(Scenario, YamlSyntaxErrorGivesLineAndColumn) {
  const auto e = errors_of("mesh:\n  file: [a, b\nmaterials: {}\n");
  ASSERT_EQ(e.size(), 1u);
  EXPECT_TRUE(has_error(e, "case.yaml:")) << e[0];
  EXPECT_TRUE(has_error(e, "YAML syntax error"));
}

TEST(Scenario, UnknownKeyGetsNearestValidOneWithLineAndColumn) {
  const auto e = errors_of(replace(good(), "    nu: 0.25", "    nu: 0.25\n    densty: 3"));
  EXPECT_TRUE(has_error(e, "case.yaml:9:5: materials.rock.densty: unknown key; valid keys here: model, E, nu, rho"));
  const auto e2 = errors_of(replace(good(), "materials:", "matrials:"));
  EXPECT_TRUE(has_error(e2, "matrials: unknown key; did you mean 'materials'?"));
  EXPECT_TRUE(has_error(e2, "materials: missing section"));
}

TEST(Scenario, WrongTypeIsReported) {
  const auto e = errors_of(replace(good(), "E: 10.0e9", "E: ten"));
  EXPECT_TRUE(has_error(e, "case.yaml:7:8: materials.rock.E: expected a number in Pa, got 'ten'"));
  const auto e2 = errors_of(replace(good(), "at: [0.5, 1.0]", "at: 3"));
  EXPECT_TRUE(has_error(e2, "output.gauges[0].at: expected [x, y] (a plane model) or [x, y, z] (a 3D model) in m"));
}

TEST(Scenario, MissingValuesAreReported) {
  const auto e = errors_of(replace(good(), "    nu: 0.25\n", ""));
  EXPECT_TRUE(has_error(e, "case.yaml:7:5: materials.rock.nu: missing value (Poisson's ratio)"));
  const auto e2 = errors_of(replace(good(), "  end: 0.01", "  safety: 0.5"));
  EXPECT_TRUE(has_error(e2, "time.end: missing value"));
}

TEST(Scenario, OutOfRangeValuesAreReported) {
  EXPECT_TRUE(has_error(errors_of(replace(good(), "E: 10.0e9", "E: 0")), "materials.rock.E: 0 is out of range: must be > 0 Pa"));
  EXPECT_TRUE(has_error(errors_of(replace(good(), "E: 10.0e9", "E: -5e9")), "materials.rock.E: -5000000000 is out of range"));
  EXPECT_TRUE(has_error(errors_of(replace(good(), "nu: 0.25", "nu: 0.5")), "materials.rock.nu: 0.5 is out of range: must be > -1 and < 0.5"));
  EXPECT_TRUE(has_error(errors_of(replace(good(), "rho: 2500", "rho: 0")), "materials.rock.rho: 0 is out of range"));
  EXPECT_TRUE(has_error(errors_of(replace(good(), "end: 0.01", "end: -1")), "time.end: -1 is out of range"));
  EXPECT_TRUE(has_error(errors_of(replace(good(), "end: 0.01", "end: 0.01\n  safety: 1.5")), "time.safety: 1.5 is out of range"));
  EXPECT_TRUE(has_error(errors_of(replace(good(), "end: 0.01", "end: .nan")), "time.end: nan is not a finite number"));
}

TEST(Scenario, AllErrorsAreReportedAtOnce) {
  std::string s = replace(good(), "E: 10.0e9", "E: -1");
  s = replace(s, "rho: 2500", "rho: -1");
  s = replace(s, "type: fixed", "type: glued");
  const auto e = errors_of(s);
  EXPECT_EQ(e.size(), 3u);
  EXPECT_TRUE(has_error(e, "boundaries[0].type: 'glued' is not one of: fixed, roller, velocity, displacement, free"));
}

TEST(Scenario, UnknownMaterialAndMissingMeshFile) {
  EXPECT_TRUE(has_error(errors_of(replace(good(), "material: rock", "material: rok")),
                        "regions[0].material: no material 'rok' under materials; did you mean 'rock'?"));
  EXPECT_TRUE(has_error(errors_of(replace(good(), "square.geo", "nothere.geo")), "mesh.file: file not found"));
  EXPECT_TRUE(has_error(errors_of(replace(good(), "  element_size: 0.25\n", "")), "mesh.element_size: a .geo geometry needs an element size"));
}

// A file name the OS refuses (here longer than NAME_MAX) used to escape as a
// std::filesystem::filesystem_error from exists() and abort the process (fuzz_scenario,
// CI of session 5). It is an input error naming the key, like a missing file.
TEST(Scenario, FileNamesTheSystemRefusesAreInputErrorsNotCrashes) {
  const std::string long_name(5000, 'x');
  const auto mesh_errors = errors_of(replace(good(), "square.geo", long_name + ".geo"));
  EXPECT_TRUE(has_error(mesh_errors, "mesh.file: cannot access"));
  EXPECT_TRUE(has_error(mesh_errors, "File name too long"));
  const std::string quake = "earthquake:\n  horizontal:\n    file: " + long_name + ".csv\n";
  EXPECT_TRUE(has_error(errors_of(good() + quake), "earthquake.horizontal.file: cannot access"));
  // A device would be read forever: only regular files (the mesh reader's rule, now for every input file).
  EXPECT_TRUE(has_error(errors_of(good() + "earthquake:\n  horizontal:\n    file: /dev/zero\n"),
                        "earthquake.horizontal.file: /dev/zero: not a regular file"));
  // A folder is not a mesh file either.
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("dsdem-test-mesh-folder-" + std::to_string(::getpid()) + ".msh");
  std::filesystem::create_directories(folder);
  EXPECT_TRUE(has_error(errors_of(replace(good(), std::string(DSDEM_TEST_DATA_DIR) + "/mesh/square.geo", folder.string())),
                        "is a directory, not a file"));
  std::filesystem::remove(folder);
}

TEST(Scenario, RollerNeedsDirectionAndVelocityNeedsValues) {
  EXPECT_TRUE(has_error(errors_of(replace(good(), "type: fixed", "type: roller")), "a roller needs the direction"));
  EXPECT_TRUE(has_error(errors_of(replace(good(), "type: fixed", "type: velocity")), "needs x, y and/or z"));
  EXPECT_TRUE(has_error(errors_of(replace(good(), "type: fixed", "type: velocity\n    y: [[0, 0], [0, 1]]")),
                        "times must increase"));
}

TEST(Scenario, SetOverridesValuesAndIsValidatedToo) {
  const io::Scenario sc = io::parse_scenario(good(), "case.yaml", {"materials.rock.E=2e9", "time.end=0.5", "boundaries.0.type=free"});
  EXPECT_EQ(sc.materials.at("rock").E, 2e9);
  EXPECT_DOUBLE_EQ(sc.end_time(), 0.5);
  EXPECT_EQ(sc.stages[0].boundaries[0].type, io::BoundaryType::Free);
  EXPECT_TRUE(has_error(errors_of(good(), {"materials.rock.nu=0.7"}), "materials.rock.nu: 0.7 is out of range"));
  EXPECT_TRUE(has_error(errors_of(good(), {"materials.rock.Ee=1"}), "did you mean 'E'?"));
  EXPECT_TRUE(has_error(errors_of(good(), {"novalue"}), "expected key.path=value"));
}

// A bad --set value has no line in the file: the error used to say "case.yaml:1:1"
// (the line yaml-cpp gives a value parsed on its own); it names the assignment now.
TEST(Scenario, SetOverrideErrorsNameTheAssignmentNotALine) {
  const auto e = errors_of(good(), {"materials.rock.nu=0.7"});
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].rfind("--set materials.rock.nu=0.7: materials.rock.nu: 0.7 is out of range", 0), 0u) << e[0];
  // A section replaced as a whole, and list entries (stages[0] in the path, stages.0 in the key).
  EXPECT_TRUE(has_error(errors_of(good(), {"materials.rock={E: -1, nu: 0.2, rho: 2000}"}),
                        "--set materials.rock={E: -1, nu: 0.2, rho: 2000}: materials.rock.E: -1 is out of range"));
  EXPECT_TRUE(has_error(errors_of(good(), {"boundaries.0.type=fixd"}), "--set boundaries.0.type=fixd: boundaries[0].type"));
  // Errors on keys the assignment did not touch keep their file line.
  const auto f = errors_of(replace(good(), "    nu: 0.25", "    nu: 0.6"), {"time.end=0.5"});
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].rfind("case.yaml:", 0), 0u) << f[0];
}

TEST(Scenario, StagesOverrideDampingAndBoundaries) {
  std::string s = replace(good(), "time:\n  end: 0.01", R"(time:
  safety: 0.5
stages:
  - name: gravity
    duration: 1.0
    damping: {alpha: 20}
  - name: dynamic
    duration: 2.0
    boundaries:
      - group: bottom
        type: roller
        direction: y)");
  const io::Scenario sc = io::parse_scenario(s, "case.yaml");
  ASSERT_EQ(sc.stages.size(), 2u);
  EXPECT_DOUBLE_EQ(sc.stages[0].damping.alpha, 20);
  EXPECT_EQ(sc.stages[0].boundaries.size(), 1u);
  EXPECT_EQ(sc.stages[1].boundaries[0].type, io::BoundaryType::Roller);
  EXPECT_DOUBLE_EQ(sc.end_time(), 3.0);
}

TEST(Scenario, GroupsTheMeshLacksAreReportedAgainstTheScenarioLine) {
  const io::Scenario sc = io::parse_scenario(replace(replace(good(), "group: block", "group: blok"), "group: bottom", "group: base"),
                                             "case.yaml");
  const RawMesh raw = [] {
    RawMesh m = mesh::rectangle_mesh(2, 2, 1, 1, mesh::Diagonal::Right, 0, 0, "block");
    return m;
  }();
  try {
    mesh::build_model(sc, raw);
    FAIL() << "expected an error";
  } catch (const io::ScenarioError& e) {
    EXPECT_TRUE(has_error(e.errors(), "case.yaml:11:12: regions[0].group: the mesh rectangle_mesh has no surface group 'blok' (did you mean 'block'?)"));
    EXPECT_TRUE(has_error(e.errors(), "case.yaml:14:12: boundaries[0].group: the mesh rectangle_mesh has no curve or point group 'base'"));
  }
}

TEST(Schema, EveryKeyIsDocumentedAndMarkdownListsIt) {
  const std::string md = io::schema_markdown();
  for (const auto& s : io::scenario_schema()) {
    EXPECT_FALSE(s.doc.empty()) << s.pattern;
    EXPECT_NE(md.find("`" + s.pattern + "`"), std::string::npos) << s.pattern;
  }
}

// docs/scenario-reference.md is generated from the schema (dsdem schema): it must not drift.
TEST(Schema, CommittedReferenceMatchesTheCode) {
  std::ifstream in(std::string(DSDEM_SOURCE_DIR) + "/docs/scenario-reference.md");
  ASSERT_TRUE(in.good()) << "docs/scenario-reference.md is missing";
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), io::schema_markdown())
      << "regenerate it: ./build/dsdem schema > docs/scenario-reference.md";
}

// The step follows the joints as they break unless asked not to, and never with a fixed
// dt: asking for both is an error at the key, not a silent choice.
TEST(Scenario, AdaptiveTimeStepIsTheDefaultAndExcludesAFixedStep) {
  EXPECT_TRUE(io::parse_scenario(good(), "case.yaml").adaptive_dt);
  EXPECT_FALSE(io::parse_scenario(replace(good(), "end: 0.01", "end: 0.01\n  adaptive: false"), "case.yaml").adaptive_dt);
  // A fixed dt alone: no rule.
  EXPECT_FALSE(io::parse_scenario(replace(good(), "end: 0.01", "end: 0.01\n  dt: 1.0e-6"), "case.yaml").adaptive_dt);
  EXPECT_FALSE(io::parse_scenario(replace(good(), "end: 0.01", "end: 0.01\n  dt: 1.0e-6\n  adaptive: false"), "case.yaml")
                   .adaptive_dt);
  EXPECT_TRUE(has_error(errors_of(replace(good(), "end: 0.01", "end: 0.01\n  dt: 1.0e-6\n  adaptive: true")),
                        "case.yaml:19:13: time.adaptive: adaptive: true takes the step from the stable step"));
  EXPECT_TRUE(has_error(errors_of(replace(good(), "end: 0.01", "end: 0.01\n  adaptive: maybe")), "time.adaptive:"));
}
