#pragma once
// The scenario (YAML) in memory, validated as a whole before step 0 (docs/developer-guide.md §5).
#include <array>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "model/model.hpp"

namespace dsdem::io {

// All input errors at once: every line is "file:line:col: key: message".
class ScenarioError : public std::runtime_error {
 public:
  explicit ScenarioError(const std::vector<std::string>& errors);
  const std::vector<std::string>& errors() const { return errors_; }

 private:
  std::vector<std::string> errors_;
};

// Where a value came from, for errors found after parsing (e.g. a group the mesh lacks).
struct SourceLocation {
  std::string file;
  int line = -1;    // 0-based as yaml-cpp gives them
  int column = -1;
  std::string key;  // actual key path
  std::string describe(const std::string& message) const;
};

// Piecewise-linear function of time, held constant after its last point and before its first.
struct TimeHistory {
  std::vector<double> t, value;
  double at(double time) const;
  double rate_at(double time) const;  // derivative (piecewise constant)
  bool empty() const { return t.empty(); }
};

enum class BoundaryType { Fixed, Roller, Velocity, Displacement, Free, ViscousSpring };

struct BoundarySpec {
  std::string group;
  BoundaryType type = BoundaryType::Fixed;
  int direction = 0;  // roller: 0 = x held, 1 = y held, 2 = z held (3D)
  std::optional<TimeHistory> x, y;
  // viscous_spring (docs/theory.md §5)
  std::optional<double> R;
  std::optional<Vec2> scattering_centre;  // as given, its x and y
  bool free_field = true;
  SourceLocation where;
  // 3D models: the z history, the scattering centre given as [x, y, z].
  std::optional<TimeHistory> z;
  std::optional<Vec3> scattering_centre_3d;
};

// One component of the earthquake: a record file or a generated artificial wave.
struct MotionSpec {
  bool present = false;
  std::string file;  // resolved path; empty when generated
  std::string units = "g";
  double scale = 1.0;
  bool generate = false;
  std::string spectrum = "hydraulic";
  double pga_g = 0.05, Tg = 0.35, beta_max = 2.25, damping = 0.05, duration = 10.0, dt = 0.02;
  double t1 = 1.5, t2 = 6.5, c = 1.0;
  std::uint64_t seed = 1;
  // The horizontal record's direction in a 3D model: degrees from x toward y (x: 0, y: 90).
  double azimuth_deg = 0.0;
  bool direction_given = false;
  SourceLocation where;
};

struct EarthquakeSpec {
  bool present = false;
  double incident_factor = 0.5;
  MotionSpec horizontal, vertical;
};

struct RegionSpec {
  std::string group;
  std::string material;
  Zone zone = Zone::Bedrock;
  SourceLocation where_group, where_material;
};

struct DampingSpec {
  double alpha = 0.0;  // 1/s
  double beta = 0.0;   // s
  // Local non-viscous damping (docs/theory.md §9): the quasi-static trials of `dsdem
  // stability` set it; no scenario key does, since it has no place in a dynamic stage.
  double local = 0.0;
};

// A law's parameters as the scenario gives them, by their declared names (law::ParamDecl),
// in the units the declaration states; absent ones are not in the map.
struct GivenParams {
  std::map<std::string, double, std::less<>> values;
  std::optional<double> get(std::string_view name) const {
    const auto it = values.find(name);
    return it == values.end() ? std::nullopt : std::optional<double>(it->second);
  }
  // These, with the values of `over` where it gives them.
  GivenParams merged(const GivenParams& over) const {
    GivenParams g = *this;
    for (const auto& [k, v] : over.values) g.values[k] = v;
    return g;
  }
};

// Joint properties as given; absent values fall back to joints.default (docs/theory.md §3).
struct JointSpec {
  std::optional<std::string> law;  // joint law by name (law/registry); joints.default's when absent
  GivenParams params;              // the joint law's parameters (law::joint_laws())
  std::optional<bool> broken;
  SourceLocation where;
  // Values of `over` where given, else these.
  JointSpec merged(const JointSpec& over) const;
};

struct JointsSection {
  bool present = false;
  JointSpec defaults;
  std::map<std::string, JointSpec> groups;  // by surface group name
  std::optional<JointSpec> interface;
  std::map<std::string, JointSpec> curves;  // by curve group name
  SourceLocation where;
};

struct ContactPairSpec {
  std::string group_a, group_b;
  GivenParams params;  // the contact law's parameters declared per pair (law::ParamDecl::per_pair)
  SourceLocation where;
};

struct ContactSpec {
  bool present = false;  // the scenario has a contact section
  std::string law = "spring_dashpot_coulomb";  // contact law by name (law/registry)
  double penalty = 1.0;
  std::optional<double> kn;
  double ks_ratio = 1.0;
  double friction = 0.5;
  double restitution = 1.0;
  double rounding = 0.05;
  std::optional<double> skin;
  bool output = false;
  std::vector<ContactPairSpec> pairs;
};

// Water in a named crack up to a level (docs/theory.md §8).
struct CrackWaterSpec {
  std::string curve;  // a curve group whose joints form the crack
  double level = 0.0;  // m
  SourceLocation where;
};

// Water at rest during a stage (docs/theory.md §8).
struct WaterSpec {
  bool present = false;
  std::vector<Vec2> line;   // piezometric line (x, z), m, x increasing; one point: a level
  double density = 1000.0;  // kg/m^3
  // saturated: pore pressure in the whole solid; discontinuities: only in named-curve
  // joints, broken joints and on exposed edges.
  bool pore_pressure_in_matrix = true;
  double ru = 0.0;          // > 0: pore-pressure ratio below the ground surface instead of a line
  std::vector<CrackWaterSpec> cracks;
  SourceLocation where;  // of the line (or the level)
};

struct StageSpec {
  std::string name;
  double duration = 0.0;
  DampingSpec damping;
  std::vector<BoundarySpec> boundaries;
  double stop_kinetic_ratio = 0.0;  // 0 = run the full duration
  bool failure = true;              // joints may damage and break
  bool earthquake = false;          // the earthquake acts (time zero = stage start)
  WaterSpec water;                  // the top-level water unless the stage sets its own
};

struct GaugeSpec {
  std::string name;
  Vec2 at = Vec2::Zero();
  Vec3 at_3d = Vec3::Zero();  // output.gauges[].at given as [x, y, z] (a 3D model's)
  int components = 2;         // of `at` as written
  SourceLocation where;
};

struct OutputSpec {
  double field_interval = 0.0;     // s (0 = end/50)
  double history_interval = 0.0;   // s (0 = end/1000)
  double progress_interval = 2.0;  // s wall clock
  long checkpoint_steps = 0;          // 0 = only by wall clock, at the end and on a signal
  double checkpoint_interval = 600.0;  // s wall clock (0 = none by wall clock)
  std::vector<GaugeSpec> gauges;
};

// The reservoir at its still level, where a slide may enter it (docs/theory.md §12): the run
// measures the slide where it meets the water and gives the Heller & Hager estimate of the
// impulse wave it raises.
// A named place on the water where the run measures it (docs/theory.md §12).
struct WaterGaugeSpec {
  std::string name;
  double x = 0.0;  // m: the free-surface gauge's abscissa
  SourceLocation where;
};
struct WaterCurveSpec {
  std::string name;
  std::vector<Vec2> polyline;  // m, at least two points
  SourceLocation where;
};
struct CrestSpec {
  std::string name;
  Vec2 at = Vec2::Zero();  // m: the crest point; water beyond x on the far side, above y
  int direction = 1;       // +1: the far side is x > at.x
  SourceLocation where;
};
// A body of water the region fills: a rectangle, or a polygon below a level.
struct WaterFillSpec {
  std::vector<Vec2> polygon;  // m, counter-clockwise or not; a rectangle becomes four corners
  double level = std::numeric_limits<double>::infinity();  // m, no water above it; unset: reservoir.level
  SourceLocation where;
};

// The reservoir as moving water: weakly compressible SPH coupled both ways with the solid
// (docs/theory.md §11).
struct SphSpec {
  bool present = false;
  double spacing = 0.0;              // m, dp
  double smoothing = 1.5;            // h / dp
  double sound_speed = 0.0;          // m/s; 0: 10 max(sqrt(g H), expected_speed)
  double expected_speed = 0.0;       // m/s, the fastest flow expected (a slide's entry speed)
  double viscosity = 0.02;           // the artificial viscosity alpha
  bool wall_free_slip = false;       // wall_viscosity: free_slip (sph::WallViscosity)
  double excluded_limit = 0.01;      // fraction of the particles that may be taken out of the water
  double density_diffusion = 0.1;    // delta
  double settle = 0.0;               // s of damped settling with the solid held, before step 0
  double freeboard = -1.0;           // m above the level where solid faces are coupled; < 0: the depth
  std::vector<WaterFillSpec> fill;   // empty: below the level over the reservoir's x range
  std::vector<WaterGaugeSpec> gauges;
  std::vector<WaterCurveSpec> runup, pressure;
  std::vector<CrestSpec> crests;
  SourceLocation where;
};

struct ReservoirSpec {
  bool present = false;
  double level = 0.0;            // m, the still water level
  double x_min = 0.0, x_max = 0.0;  // m, the reservoir's extent along the section
  double density = 1000.0;       // kg/m^3
  SphSpec sph;
  SourceLocation where;
};

// Factor of safety by strength reduction (`dsdem stability`, docs/theory.md §9).
struct StabilitySpec {
  bool present = false;
  // Pseudo-static coefficients: a body force |g| (kh, kv) m per node on top of gravity,
  // kh > 0 toward +x, kv > 0 upward. Absent: static only.
  std::optional<double> kh, kv;
  double F_low = 0.5, F_high = 4.0;  // bisection bounds on F
  double tolerance = 0.005;          // bisection stops when F_high - F_low <= this
  double equilibrium_ratio = 1e-5;   // largest unbalanced nodal force / mean gravity force
  long max_steps = 0;                // per trial; 0: automatic (see run/stability.hpp)
  double failure_displacement = 0.0; // m; 0: the mean element size
  double local_damping = 0.8;        // the trials' local non-viscous damping coefficient
  // 1/s: the trials' mass damping, fixed; absent: adaptive (docs/theory.md §9)
  std::optional<double> damping_alpha;
  bool check_budget = false;         // rerun the bracketing trials watched twice as long
  bool keep_tension = false;         // ft is not divided by F
  bool dynamic = false;              // also the dynamic FS: the earthquake stages at strengths 1/F
  std::vector<GaugeSpec> monitor;    // monitored points; none: every node
  SourceLocation where, where_bounds;
};

struct Scenario {
  std::string file;       // path of the scenario file
  std::vector<std::string> overrides;  // the --set key=value overrides applied to it, in order
  std::string directory;  // its folder: relative paths are resolved from here
  std::string title;
  std::string mesh_file;  // absolute or relative to directory
  std::optional<double> element_size;
  bool crossed_mesh = false;  // mesh.crossed: quadrilaterals split in four at their diagonals' crossing
  bool spatial_triangle_order = true;  // mesh.triangle_order: spatial (Hilbert) or file
  static const char* triangle_order_name(bool spatial) { return spatial ? "spatial" : "file"; }
  bool plane_stress = false;
  double thickness = 1.0;
  std::map<std::string, Material> materials;
  std::vector<RegionSpec> regions;
  Vec2 gravity = Vec2(0.0, -9.81);
  // gravity as given: 0 components (absent: the default of the mesh's dimension), 2 (a plane
  // model: gravity) or 3 (a 3D model: gravity_3d).
  int gravity_components = 0;
  Vec3 gravity_3d = Vec3(0.0, 0.0, -9.81);
  SourceLocation where_gravity;
  std::optional<double> dt;
  double safety = 0.3;
  // Take the step again as joints break (safety x the stable step of the model as it is,
  // docs/theory.md §6); false keeps the first step for the whole run. Not with a fixed dt.
  bool adaptive_dt = true;
  std::vector<StageSpec> stages;  // at least one after parsing
  OutputSpec output;
  JointsSection joints;
  ContactSpec contact;
  EarthquakeSpec earthquake;
  StabilitySpec stability;
  ReservoirSpec reservoir;
  SourceLocation where_mesh;

  double end_time() const;
  std::string resolve(const std::string& path) const;
};

// Applies `key.path=value` overrides (list entries by index: stages.0.duration=2).
void apply_override(YAML::Node& root, const std::string& assignment);

// Loads, applies overrides and validates the scenario; throws ScenarioError listing
// every problem with file, line, column and key.
Scenario load_scenario(const std::string& path, const std::vector<std::string>& overrides = {});
Scenario parse_scenario(const std::string& yaml_text, const std::string& file_name,
                        const std::vector<std::string>& overrides = {});

}  // namespace dsdem::io
