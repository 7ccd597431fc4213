// A scenario on a volume mesh (run/run3d): a column settling under its weight against the
// closed form, its outputs, and the keys of one dimension refused in the other.
#include "run/run3d.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "app/cli_util.hpp"
#include "io/json_file.hpp"
#include "mesh/model_builder3d.hpp"
#include "run/prepare.hpp"

namespace fs = std::filesystem;
using namespace dsdem;

namespace {

// A 4 x 4 x 20 m column meshed into tetrahedra, its faces named.
const char* kColumnGeo = R"(SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 4, 4, 20};
Physical Volume("soil") = {1};
e = 1e-3;
Physical Surface("base") = Surface In BoundingBox{-e, -e, -e, 4 + e, 4 + e, e};
Physical Surface("xsides") = Surface In BoundingBox{-e, -e, -e, e, 4 + e, 20 + e};
Physical Surface("xsides") += Surface In BoundingBox{4 - e, -e, -e, 4 + e, 4 + e, 20 + e};
Physical Surface("ysides") = Surface In BoundingBox{-e, -e, -e, 4 + e, e, 20 + e};
Physical Surface("ysides") += Surface In BoundingBox{-e, 4 - e, -e, 4 + e, 4 + e, 20 + e};
Physical Surface("top") = Surface In BoundingBox{-e, -e, 20 - e, 4 + e, 4 + e, 20 + e};
)";

const char* kColumnScenario = R"(title: column
mesh: {file: column.geo, element_size: 2.0}
materials:
  soil: {E: 1.0e8, nu: 0.25, rho: 2000}
regions:
  - {group: soil, material: soil}
gravity: [0, 0, -9.81]
time: {safety: 0.3}
stages:
  - name: gravity
    duration: 3.0
    damping: {alpha: 41.0}
    boundaries:
      - {group: base, type: roller, direction: z}
      - {group: xsides, type: roller, direction: x}
      - {group: ysides, type: roller, direction: y}
output: {field_interval: 1.0, history_interval: 0.1}
)";

fs::path write_case(const std::string& name, const std::string& scenario) {
  const fs::path dir = test::fresh_dir(name);
  fs::create_directories(dir);
  std::ofstream(dir / "column.geo") << kColumnGeo;
  std::ofstream(dir / "scenario.yaml") << scenario;
  return dir;
}

// The problems prepare finds for a scenario, joined; "" when it prepares.
std::string problems(const fs::path& dir, const std::vector<std::string>& sets = {}) {
  try {
    const io::Scenario sc = io::load_scenario((dir / "scenario.yaml").string(), sets);
    if (auto mesh = mesh::load_volume_mesh(sc, (dir / "work").string())) run::prepare_run_3d(sc, *mesh);
    else run::prepare_run(sc, (dir / "work").string());
  } catch (const io::ScenarioError& e) {
    std::string all;
    for (const auto& m : e.errors()) all += m + "\n";
    return all;
  }
  return "";
}

}  // namespace

// A column on rollers settles by rho g H^2 / (2 M) at its top (uniaxial strain, M the
// constrained modulus), within 2%; fields, history and summary are written.
TEST(Run3D, ColumnSettlesByTheClosedFormAndWritesItsOutputs) {
  const fs::path dir = write_case("run3d_column", kColumnScenario);
  const io::Scenario sc = io::load_scenario((dir / "scenario.yaml").string());
  auto mesh = mesh::load_volume_mesh(sc, (dir / "work").string());
  ASSERT_TRUE(mesh.has_value());
  run::PreparedRun3 prepared = run::prepare_run_3d(sc, *mesh);
  const std::string report = run::check_report_3d(prepared);
  EXPECT_NE(report.find("tetrahedra"), std::string::npos) << report;
  EXPECT_NE(report.find("ms per step"), std::string::npos) << report;  // the cost, timed
  EXPECT_NE(report.find("memory     about"), std::string::npos) << report;
  run::RunOptions options;
  options.output_dir = (dir / "out").string();
  options.quiet = true;
  const run::RunResult result = run::run_3d(prepared, options);
  EXPECT_GT(result.steps, 1000);
  const double E = 1e8, nu = 0.25, rho = 2000, g = 9.81, H = 20.0;
  const double M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  double top = 0.0;
  for (std::size_t i = 0; i < prepared.model.nodes.size(); ++i)
    if (prepared.model.nodes.X[i].z() > H - 1e-9) top += prepared.model.nodes.u[i].z();
  int n_top = 0;
  for (std::size_t i = 0; i < prepared.model.nodes.size(); ++i) n_top += prepared.model.nodes.X[i].z() > H - 1e-9;
  top /= n_top;
  const double expected = -rho * g * H * H / (2.0 * M);
  EXPECT_NEAR(top / expected, 1.0, 0.02) << "top settlement " << top << " m, closed form " << expected << " m";
  for (const char* f : {"fields.pvd", "history.csv", "summary.json", "dsdem.log"}) EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
  const auto summary = io::read_json_file(dir / "out" / "summary.json");
  EXPECT_EQ(summary["dimension"], 3);
  EXPECT_EQ(summary["elements"].get<std::size_t>(), prepared.model.tetrahedra.size());
  EXPECT_TRUE(summary["completed"].get<bool>());
  EXPECT_LT(summary["energy_balance_error"].get<double>(), 1e-3);
  EXPECT_NEAR(summary["max_displacement"]["value_m"].get<double>(), -expected, 0.05 * -expected);
}

// Gauges at [x, y, z] follow the material point in its tetrahedron: the one at the top of the
// settling column reads the top's settlement in history.csv and summary.json; one outside the
// mesh, or at [x, y], is refused with its key.
TEST(Run3D, AGaugeFollowsItsMaterialPointAndOneOutsideIsRefused) {
  std::string s = kColumnScenario;
  s.replace(s.find("output: {field_interval: 1.0, history_interval: 0.1}"), 52,
            "output:\n  field_interval: 1.0\n  history_interval: 0.1\n  gauges:\n    - {name: top, at: [2, 2, 20]}\n"
            "    - {name: mid, at: [1, 3, 10]}\n");
  const fs::path dir = write_case("run3d_gauges", s);
  const io::Scenario sc = io::load_scenario((dir / "scenario.yaml").string());
  auto mesh = mesh::load_volume_mesh(sc, (dir / "work").string());
  ASSERT_TRUE(mesh.has_value());
  run::PreparedRun3 prepared = run::prepare_run_3d(sc, *mesh);
  ASSERT_EQ(prepared.gauges.size(), 2u);
  EXPECT_NE(run::check_report_3d(prepared).find("gauge      top"), std::string::npos);
  run::RunOptions options;
  options.output_dir = (dir / "out").string();
  options.quiet = true;
  run::run_3d(prepared, options);
  const double E = 1e8, nu = 0.25, rho = 2000, g = 9.81, H = 20.0;
  const double M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  const auto summary = io::read_json_file(dir / "out" / "summary.json");
  ASSERT_EQ(summary["gauges"].size(), 2u);
  const auto& top = summary["gauges"][0];
  EXPECT_EQ(top["name"], "top");
  // Uniaxial strain: u_z(z) = -rho g (H z - z^2 / 2) / M; at the top rho g H^2 / (2 M), at mid-height 3/4 of it.
  const double top_closed = -rho * g * H * H / (2.0 * M), mid_closed = 0.75 * top_closed;
  EXPECT_NEAR(top["final_displacement_m"][2].get<double>() / top_closed, 1.0, 0.02);
  EXPECT_NEAR(summary["gauges"][1]["final_displacement_m"][2].get<double>() / mid_closed, 1.0, 0.02);
  EXPECT_NEAR(top["final_displacement_m"][0].get<double>(), 0.0, 1e-3 * -top_closed);  // rollers: no sideways motion
  EXPECT_GE(top["max_displacement_m"].get<double>(), -top["final_displacement_m"][2].get<double>() * 0.999);
  // The history has each gauge's columns.
  std::ifstream h(dir / "out" / "history.csv");
  std::string header;
  std::getline(h, header);
  if (!header.empty() && header[0] == '#') std::getline(h, header);
  EXPECT_NE(header.find("top_displacement_z"), std::string::npos) << header;
  EXPECT_NE(header.find("mid_acceleration_x"), std::string::npos) << header;
  // Outside the mesh, or at [x, y]: refused with the key.
  const std::string outside = problems(dir, {"output.gauges.1.at=[1, 3, 30]"});
  EXPECT_NE(outside.find("gauge 'mid' at (1, 3, 30) m lies outside the mesh"), std::string::npos) << outside;
  const std::string plane = problems(dir, {"output.gauges.1.at=[1, 3]"});
  EXPECT_NE(plane.find("gauge 'mid': a 3D model's gauge is at [x, y, z]"), std::string::npos) << plane;
}

// Keys of a plane model in a 3D scenario, and of a 3D model in a plane one, are refused
// with file, line and key before step 0.
TEST(Run3D, KeysOfTheOtherDimensionAreRefusedWithTheirKey) {
  const fs::path dir = write_case("run3d_keys", kColumnScenario);
  EXPECT_EQ(problems(dir), "");
  std::string plane_gravity = kColumnScenario;
  plane_gravity.replace(plane_gravity.find("[0, 0, -9.81]"), 13, "[0, -9.81]");
  const std::string gravity = problems(write_case("run3d_gravity", plane_gravity));
  EXPECT_NE(gravity.find("scenario.yaml:7:10: gravity:"), std::string::npos) << gravity;
  EXPECT_NE(gravity.find("[x, y, z]"), std::string::npos) << gravity;
  const std::string joints = problems(dir, {"joints.default.ft=1e5", "joints.default.c=1e5", "joints.default.phi=30",
                                            "joints.default.GI=10", "joints.default.GII=50"});
  EXPECT_NE(joints.find("no cohesive joints yet"), std::string::npos) << joints;
  const std::string zone = problems(dir, {"regions.0.zone=contact"});
  EXPECT_NE(zone.find("only continuous zones"), std::string::npos) << zone;
  const std::string region = problems(dir, {"regions.0.group=rock"});
  EXPECT_NE(region.find("no volume group 'rock'"), std::string::npos) << region;
  EXPECT_NE(region.find("its volumes are: soil"), std::string::npos) << region;
  const std::string safety = problems(dir, {"time.safety=0.8"});
  EXPECT_NE(safety.find("time.safety 0.8 is above 0.5"), std::string::npos) << safety;
  const std::string monitor = problems(dir, {"stability.monitor=[{name: crest, at: [0.5, 0.5]}]"});
  EXPECT_NE(monitor.find("stability.monitor: monitored points at [x, y] are plane"), std::string::npos) << monitor;
  // A plane scenario with a 3D gravity and a z history.
  const fs::path plane = fs::path(DSDEM_SOURCE_DIR) / "examples" / "elastic_slope" / "scenario.yaml";
  const fs::path pdir = test::fresh_dir("run3d_plane_keys");
  fs::copy(plane.parent_path(), pdir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  const std::string g3 = problems(pdir, {"gravity=[0, 0, -9.81]"});
  EXPECT_NE(g3.find("a plane model (the mesh has no volumes) takes gravity as [x, y]"), std::string::npos) << g3;
  const std::string gauge3 = problems(pdir, {"output.gauges=[{name: g, at: [10, 10, 0]}]"});
  EXPECT_NE(gauge3.find("gauge 'g': a plane model's gauge is at [x, y]"), std::string::npos) << gauge3;
}

// A horizontal record's direction: x, y or an azimuth in degrees; anything else refused.
TEST(Run3D, AHorizontalRecordNamesItsDirection) {
  std::string s = kColumnScenario;
  s += "earthquake:\n  horizontal:\n    direction: up\n    file: quake.csv\n";
  const fs::path dir = write_case("run3d_direction", s);
  {
    std::ofstream q(dir / "quake.csv");
    for (int i = 0; i <= 100; ++i) q << 0.01 * i << "," << 0.1 * std::sin(0.2 * i) << "\n";
  }
  const std::string up = problems(dir);
  EXPECT_NE(up.find("'up' is not a direction: x, y or an azimuth"), std::string::npos) << up;
  EXPECT_EQ(problems(dir, {"earthquake.horizontal.direction=30"}), "");
  EXPECT_EQ(problems(dir, {"earthquake.horizontal.direction=y"}), "");
}
