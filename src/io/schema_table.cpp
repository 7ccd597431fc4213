// The scenario's keys (the table behind io/schema.hpp), from the law registries'
// declarations for the law parameters.
#include "io/schema_table.hpp"

#include <fmt/format.h>

#include "law/registry.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace dsdem::io::detail {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

KeySpec num(std::string pattern, std::string unit, std::string def, double min, double max, std::string doc,
            bool min_excl = false, bool max_excl = false) {
  KeySpec s;
  s.pattern = std::move(pattern);
  s.type = KeyType::Number;
  s.unit = std::move(unit);
  s.default_text = std::move(def);
  s.min = min;
  s.max = max;
  s.min_exclusive = min_excl;
  s.max_exclusive = max_excl;
  s.doc = std::move(doc);
  return s;
}
KeySpec of(std::string pattern, KeyType type, std::string def, std::string doc, std::string unit = "") {
  KeySpec s;
  s.pattern = std::move(pattern);
  s.type = type;
  s.default_text = std::move(def);
  s.doc = std::move(doc);
  s.unit = std::move(unit);
  return s;
}
KeySpec choice(std::string pattern, std::vector<std::string> choices, std::string def, std::string doc) {
  KeySpec s = of(std::move(pattern), KeyType::Choice, std::move(def), std::move(doc));
  s.choices = std::move(choices);
  return s;
}

// One key per parameter of the laws of a registry, under `prefix`, in registration and
// declaration order; a parameter several laws declare is one key (declared alike). Its
// doc names the laws that use it unless all do. Without `keep_required` a required
// parameter has no default here (a set of overrides).
void add_law_params(std::vector<KeySpec>& s, const law::Registry& reg, const std::string& prefix, bool keep_required) {
  std::vector<const law::ParamDecl*> params;
  for (const auto& l : reg.laws())
    for (const auto& p : l.params) {
      const auto same = std::find_if(params.begin(), params.end(), [&](const law::ParamDecl* q) { return q->name == p.name; });
      if (same == params.end()) {
        params.push_back(&p);
        continue;
      }
      const law::ParamDecl& q = **same;
      if (q.unit != p.unit || q.default_text != p.default_text || q.min != p.min || q.max != p.max ||
          q.min_exclusive != p.min_exclusive || q.max_exclusive != p.max_exclusive || q.doc != p.doc)
        throw std::logic_error(fmt::format("{} law '{}' declares parameter '{}' unlike an earlier law",
                                           law::category_name(reg.category()), l.name, p.name));
    }
  for (const law::ParamDecl* p : params) {
    std::string users;
    std::size_t n_users = 0;
    for (const auto& l : reg.laws())
      if (l.has_param(p->name)) {
        users += (users.empty() ? "" : ", ") + l.name;
        ++n_users;
      }
    std::string doc = n_users == reg.size() ? p->doc : users + ": " + p->doc;
    const std::string def = p->required() && !keep_required ? "" : p->default_text;
    s.push_back(num(prefix + "." + p->name, p->unit, def, p->min, p->max, std::move(doc), p->min_exclusive,
                    p->max_exclusive));
  }
}

// The mesh, the materials and the regions that join them.
void add_mesh_and_materials(std::vector<KeySpec>& s) {
  s.push_back(of("title", KeyType::String, "", "Free text shown in the log, summary and report."));
  s.push_back(of("mesh", KeyType::Map, "required", "The Gmsh mesh or geometry."));
  s.push_back(of("mesh.file", KeyType::String, "required",
                 "Gmsh ASCII .msh (format 4.1 or 2.2) or .geo file, relative to the scenario file."));
  s.push_back(num("mesh.element_size", "m", "", 0, kInf,
                  "Maximum element size used to mesh a .geo (required for .geo, ignored for .msh).", true));
  s.push_back(of("mesh.crossed", KeyType::Boolean, "false",
                 "Crossed triangles: every quadrilateral split in four around the crossing of its diagonals "
                 "(docs/theory.md §2), which lock far less than unstructured triangles under plastic flow: for "
                 "Mohr-Coulomb zones in strength reduction. A .geo is meshed by Gmsh into quadrilaterals (triangles "
                 "of twice every size, each split in three) whose edges along the curves are about element_size: "
                 "about 3 times the triangles of the unstructured mesh and a 3 times shorter stable time step. A .msh "
                 "may hold 4-node quadrilaterals, refused without it (the .msh a run keeps in its output is Gmsh's "
                 "quadrilateral mesh); its triangles are kept as they are."));
  s.push_back(choice("mesh.triangle_order", {"spatial", "file"}, "spatial",
                     "Numbering of the triangles: spatial (along a Hilbert curve through their centroids, "
                     "for memory locality and thread balance) or file (the mesh file's order). The two runs "
                     "differ by rounding only; ParaView's cell ids are the solver's numbers."));
  s.push_back(choice("mesh.plane", {"strain", "stress"}, "strain",
                     "2D idealisation: plane strain (per unit thickness) or plane stress."));
  s.push_back(num("mesh.thickness", "m", "1", 0, kInf, "Out-of-plane thickness (plane stress).", true));

  s.push_back(of("materials", KeyType::Map, "required", "Materials by name."));
  s.push_back(of("materials.*", KeyType::Map, "", "One material."));
  s.push_back(choice("materials.*.model", law::material_laws().names(), std::string(law::kDefaultMaterialLaw),
                     "Constitutive model of the bulk."));
  add_law_params(s, law::material_laws(), "materials.*", true);

  s.push_back(of("regions", KeyType::List, "required", "Assigns a material and a zone to each physical surface group."));
  s.push_back(of("regions[]", KeyType::Map, "", "One region."));
  s.push_back(of("regions[].group", KeyType::String, "required", "Name of a physical surface group of the mesh."));
  s.push_back(of("regions[].material", KeyType::String, "required", "Name of a material under `materials`."));
  s.push_back(choice("regions[].zone", {"continuous", "contact", "discrete"}, "continuous",
                     "continuous: plain FEM (zone B); contact: FEM whose surface takes part in contact (zone C); "
                     "discrete: breakable spheropolygon elements glued by joints (zone A)."));
}

// Boundary conditions, gravity, damping, time and stages.
void add_boundaries_time_stages(std::vector<KeySpec>& s) {
  s.push_back(of("boundaries", KeyType::List, "", "Boundary conditions on curve or point groups."));
  s.push_back(of("boundaries[]", KeyType::Map, "", "One boundary condition."));
  s.push_back(of("boundaries[].group", KeyType::String, "required",
                 "Name of a physical curve or point group, or a surface group (a driven body: all its nodes)."));
  s.push_back(choice("boundaries[].type", {"fixed", "roller", "velocity", "displacement", "free", "viscous_spring"}, "required",
                     "fixed: both directions held; roller: `direction` held; velocity / displacement: the given "
                     "components prescribed (constant or history); free: nothing (overrides an earlier stage); "
                     "viscous_spring: absorbing boundary with the free-field earthquake input (docs/theory.md §5)."));
  s.push_back(num("boundaries[].R", "m", "", 0, kInf, "viscous_spring: distance from the scattering source to the boundary.", true));
  s.push_back(of("boundaries[].scattering_centre", KeyType::Vector, "",
                 "viscous_spring: point of the scattering source; R is then each node's distance to it.", "m"));
  s.push_back(of("boundaries[].free_field", KeyType::Boolean, "true",
                 "viscous_spring: apply the free-field seismic input forces on this boundary."));
  s.push_back(choice("boundaries[].direction", {"x", "y", "z"}, "",
                     "For a roller: the direction that is held (a plane model: x for a vertical side, y for a base; a "
                     "3D model: z for a base)."));
  s.push_back(of("boundaries[].x", KeyType::NumberOrTable, "",
                 "Prescribed x component: a number, or a history [[t, value], ...] (linear in between, held after).",
                 "m/s or m"));
  s.push_back(of("boundaries[].y", KeyType::NumberOrTable, "", "Prescribed y component, as for x.", "m/s or m"));
  s.push_back(of("boundaries[].z", KeyType::NumberOrTable, "", "Prescribed z component, as for x (3D models).", "m/s or m"));

  s.push_back(of("gravity", KeyType::Vector, "[0, -9.81] or [0, 0, -9.81]",
                 "Gravitational acceleration: [x, y] for a plane model, [x, y, z] for a 3D one (the mesh decides).",
                 "m/s^2"));
  s.push_back(of("damping", KeyType::Map, "", "Rayleigh damping C = alpha M + beta K (docs/theory.md §6)."));
  s.push_back(num("damping.alpha", "1/s", "0", 0, kInf, "Mass-proportional coefficient."));
  s.push_back(num("damping.beta", "s", "0", 0, kInf, "Stiffness-proportional coefficient."));

  s.push_back(of("time", KeyType::Map, "required", "Time integration."));
  s.push_back(num("time.end", "s", "", 0, kInf,
                  "End time (required without stages; with stages the sum of their durations).", true));
  s.push_back(num("time.dt", "s", "", 0, kInf, "Fixed time step; when absent, safety x the stable step.", true));
  s.push_back(num("time.safety", "", "0.3", 0, 1, "Fraction of the stable time step used.", true));
  s.push_back(of("time.adaptive", KeyType::Boolean, "true without time.dt",
                 "Take the step again as joints break: safety x the stable step of the intact joints, triangles and "
                 "contacts (docs/theory.md §6), so it grows as the stiffest joints go; false keeps the first step. Not "
                 "with time.dt."));

  s.push_back(of("stages", KeyType::List, "", "Stages run one after another; each may override damping and boundaries."));
  s.push_back(of("stages[]", KeyType::Map, "", "One stage."));
  s.push_back(of("stages[].name", KeyType::String, "required", "Stage name (log, histories)."));
  s.push_back(num("stages[].duration", "s", "required", 0, kInf, "Simulated time of the stage.", true));
  s.push_back(of("stages[].damping", KeyType::Map, "", "Rayleigh damping during this stage (else the top-level one)."));
  s.push_back(num("stages[].damping.alpha", "1/s", "0", 0, kInf, "Mass-proportional coefficient."));
  s.push_back(num("stages[].damping.beta", "s", "0", 0, kInf, "Stiffness-proportional coefficient."));
  s.push_back(of("stages[].boundaries", KeyType::List, "",
                 "Boundary conditions during this stage (else the top-level ones)."));
  s.push_back(of("stages[].boundaries[]", KeyType::Map, "", "One boundary condition."));
  for (const char* k : {"group", "type", "direction", "x", "y", "z", "R", "scattering_centre", "free_field"}) {
    KeySpec copy = *std::find_if(s.begin(), s.end(), [&](const KeySpec& q) { return q.pattern == std::string("boundaries[].") + k; });
    copy.pattern = std::string("stages[].boundaries[].") + k;
    s.push_back(copy);
  }
  s.push_back(num("stages[].stop_kinetic_ratio", "", "", 0, 1,
                  "End the stage early once kinetic energy falls below this fraction of its peak in the stage.", true));
}

// Cohesive joints (docs/theory.md §3; paper eqs. 6-9).
void add_joints(std::vector<KeySpec>& s) {
  s.push_back(of("joints", KeyType::Map, "", "Cohesive joint properties for discrete (breakable) zones."));
  const std::vector<std::pair<std::string, std::string>> joint_sets{
      {"joints.default", "Properties of every joint unless a group, interface or curve entry overrides them."},
      {"joints.groups.*", "Overrides for joints inside one discrete surface group."},
      {"joints.interface", "Overrides for joints between a discrete group and a continuous one (the bond to bedrock)."},
      {"joints.curves.*", "Overrides for joints on a named mesh curve (pre-existing crack, weak interlayer)."}};
  s.push_back(of("joints.groups", KeyType::Map, "", "Per discrete group overrides, by group name."));
  s.push_back(of("joints.curves", KeyType::Map, "", "Per curve overrides, by curve group name."));
  for (const auto& [prefix, doc] : joint_sets) {
    const bool base = prefix == "joints.default";
    s.push_back(of(prefix, KeyType::Map, "", doc));
    s.push_back(choice(prefix + ".law", law::joint_laws().names(), base ? std::string(law::kDefaultJointLaw) : "",
                       base ? "Joint law (its parameters follow)."
                            : "Joint law of these joints (default: the one of joints.default)."));
    // Required values are required once, in joints.default; the other sets override.
    add_law_params(s, law::joint_laws(), prefix, base);
    s.push_back(of(prefix + ".broken", KeyType::Boolean, "false", "Start broken (a pre-existing crack: contact only)."));
  }
}

// Spheropolygon contact (docs/theory.md §4; paper eqs. 1-5).
void add_contact(std::vector<KeySpec>& s) {
  s.push_back(of("contact", KeyType::Map, "", "Contact between spheropolygons of the discrete and contact zones."));
  s.push_back(choice("contact.law", law::contact_laws().names(), std::string(law::kDefaultContactLaw),
                     "Contact law (its parameters follow)."));
  add_law_params(s, law::contact_laws(), "contact", true);
  s.push_back(num("contact.rounding", "", "0.05", 0, 0.5, "Rounding radius as a fraction of each triangle's inscribed radius.", true, true));
  s.push_back(num("contact.skin", "m", "auto", 0, kInf, "Broad-phase skin (default: half the mean inscribed radius).", true));
  s.push_back(of("contact.output", KeyType::Boolean, "false", "Write contact points and forces as a VTU series (contacts.pvd)."));
  s.push_back(of("contact.pairs", KeyType::List, "", "Friction / restitution / stiffness for particular pairs of surface groups."));
  s.push_back(of("contact.pairs[]", KeyType::Map, "", "One pair of groups."));
  s.push_back(of("contact.pairs[].groups", KeyType::List, "required", "Two surface group names (the same name twice: within one group)."));
  // A law's parameters declared per pair, defaulting to the contact section's value.
  std::vector<std::string> per_pair;
  for (const auto& l : law::contact_laws().laws())
    for (const auto& p : l.params) {
      if (!p.per_pair || std::find(per_pair.begin(), per_pair.end(), p.name) != per_pair.end()) continue;
      per_pair.push_back(p.name);
      s.push_back(num("contact.pairs[]." + p.name, p.unit, "contact." + p.name, p.min, p.max,
                      "contact." + p.name + " for this pair of groups.", p.min_exclusive, p.max_exclusive));
    }
}

// Earthquake input (docs/theory.md §5; paper §2.2) and the stage switches after it.
void add_earthquake(std::vector<KeySpec>& s) {
  s.push_back(of("earthquake", KeyType::Map, "", "Design ground motion fed through viscous-spring boundaries."));
  s.push_back(num("earthquake.incident_factor", "", "0.5", 0, kInf,
                  "Incident wave = this factor x the design (outcrop) motion (0.5 for a uniform half-space).", true));
  for (const std::string comp : {"horizontal", "vertical"}) {
    const std::string base = "earthquake." + comp;
    s.push_back(of(base, KeyType::Map, "", comp == "horizontal" ? "Horizontal component: vertically incident SV wave."
                                                                  : "Vertical component: vertically incident P wave."));
    s.push_back(of(base + ".file", KeyType::String, "", "Accelerogram: CSV (t, a) or PEER .AT2, relative to the scenario."));
    s.push_back(choice(base + ".units", {"g", "m/s2"}, "g", "Units of a CSV accelerogram (AT2 is always g)."));
    s.push_back(num(base + ".scale", "", "1", -kInf, kInf, "Factor applied to the record (e.g. to scale it to a PGA)."));
    if (comp == "horizontal")
      s.push_back(of(base + ".direction", KeyType::String, "x",
                     "A 3D model's horizontal direction of motion: x, y or an azimuth in degrees from x toward y (a "
                     "plane model moves along x)."));
    s.push_back(of(base + ".generate", KeyType::Map, "", "Generate an artificial accelerogram (GB 17741 method) instead of a file."));
    s.push_back(choice(base + ".generate.spectrum", {"hydraulic", "gb50011"}, "hydraulic", "Target spectrum."));
    s.push_back(num(base + ".generate.pga", "g", "0.05", 0, kInf, "Peak ground acceleration.", true));
    s.push_back(num(base + ".generate.Tg", "s", "0.35", 0.1, 10, "Characteristic period.", true));
    s.push_back(num(base + ".generate.beta_max", "", "2.25", 1, kInf, "Peak of the hydraulic beta spectrum."));
    s.push_back(num(base + ".generate.damping", "", "0.05", 0, 1, "Damping ratio of the target spectrum.", true, true));
    s.push_back(num(base + ".generate.duration", "s", "10", 0, kInf, "Duration.", true));
    s.push_back(num(base + ".generate.dt", "s", "0.02", 0, kInf, "Sampling step.", true));
    s.push_back(num(base + ".generate.seed", "", "1", 0, kInf, "Random seed (same seed, same wave)."));
    s.push_back(num(base + ".generate.t1", "s", "1.5", 0, kInf, "End of the rising part of the intensity envelope."));
    s.push_back(num(base + ".generate.t2", "s", "6.5", 0, kInf, "Start of the decay of the intensity envelope."));
    s.push_back(num(base + ".generate.c", "1/s", "1", 0, kInf, "Decay rate of the envelope."));
  }
  s.push_back(of("stages[].earthquake", KeyType::Boolean, "false",
                 "The earthquake acts during this stage (its time zero is the stage start)."));

  s.push_back(of("stages[].failure", KeyType::Boolean, "true",
                 "Joints may damage and break in this stage (false for a gravity stage: elastic joints)."));
}

// Water at rest (docs/theory.md §8), for every stage and per stage.
void add_water(std::vector<KeySpec>& s) {
  s.push_back(of("water", KeyType::Map, "",
                 "Water at rest in every stage unless a stage sets its own (docs/theory.md §8): hydrostatic pressure "
                 "rho_w g (z_w(x) - z) below the piezometric line z_w(x), acting on elements (total stress), joint "
                 "faces and exposed edges."));
  for (const std::string base : {"water", "stages[].water"}) {
    if (base != "water")
      s.push_back(of(base, KeyType::Map, "", "Water during this stage (else the top-level water)."));
    s.push_back(num(base + ".level", "m", "", -kInf, kInf,
                    "Horizontal piezometric line at this elevation (a pool level); or give line."));
    s.push_back(of(base + ".line", KeyType::Polyline, "",
                   "Piezometric line [[x, z], ...], x increasing, spanning the model: the pool level over open "
                   "water, the water table in the slope.",
                   "m"));
    s.push_back(num(base + ".ru", "", "", 0, 1,
                    "Pore-pressure ratio (Bishop & Morgenstern): p = ru gamma h at depth h below the ground surface, "
                    "gamma the unit weight of the material there; instead of level or line.",
                    true, true));
    s.push_back(num(base + ".density", "kg/m^3", "1000", 0, kInf, "Water density rho_w.", true));
    s.push_back(choice(base + ".pore_pressure", {"saturated", "discontinuities"}, "saturated",
                       "saturated: pore pressure in the whole solid below the line (elements, every joint face, "
                       "exposed edges); discontinuities: only in joints on named curves, broken joints and on "
                       "exposed edges (an impervious intact rock mass)."));
    s.push_back(of(base + ".cracks", KeyType::List, "", "Water standing in named cracks at their own level."));
    s.push_back(of(base + ".cracks[]", KeyType::Map, "", "One crack."));
    s.push_back(of(base + ".cracks[].curve", KeyType::String, "required",
                   "A named mesh curve with joints (e.g. a back crack); its faces take rho_w g (level - z) while "
                   "they are within the joint's length of each other (opened farther, the crack has drained)."));
    s.push_back(num(base + ".cracks[].level", "m", "required", -kInf, kInf, "Water level in the crack."));
    s.push_back(of(base + ".dry", KeyType::Boolean, "false",
                   base == "water" ? "No water: the section's values are kept and checked but do not act (one switch "
                                     "to fill or empty a documented pool)."
                                   : "No water in this stage (its values are kept but do not act)."));
  }
}

// The reservoir as moving water (docs/theory.md §11).
void add_reservoir_sph(std::vector<KeySpec>& s) {
  const std::string b = "reservoir.sph";
  s.push_back(of(b, KeyType::Map, "",
                 "The reservoir as moving water: weakly compressible SPH, coupled both ways with the solid (the "
                 "bedrock's surface near the water and every face of the discrete zone), replacing the static "
                 "water's pressure on faces over the reservoir's x range. Absent: the Heller & Hager estimate only "
                 "(required without a discrete zone)."));
  s.push_back(num(b + ".spacing", "m", "required", 0, kInf, "Particle spacing dp.", true));
  s.push_back(num(b + ".smoothing", "", "1.5", 1.3, 2.0, "Smoothing length h / dp."));
  s.push_back(num(b + ".sound_speed", "m/s", "0", 0, kInf,
                  "Numerical speed of sound c0; 0: 10 max(sqrt(g H), expected_speed), H the deepest water."));
  s.push_back(num(b + ".expected_speed", "m/s", "0", 0, kInf,
                  "The fastest flow expected (a slide's entry speed), for the sound speed; the run warns when the "
                  "water goes faster than c0 / 10."));
  s.push_back(num(b + ".viscosity", "", "0.02", 0, 1, "Artificial viscosity alpha (docs/theory.md §11: 0.01-0.1)."));
  s.push_back(choice(b + ".wall_viscosity", {"no_slip", "free_slip"}, "no_slip",
                     "The artificial viscosity between the water and its walls: no_slip, as between two water "
                     "particles (the wall holds the water still at its face, a viscous layer about a particle thick); "
                     "free_slip, along the wall's normal only (it resists the approach, not the sliding: water whose "
                     "motion along a wall is not to be damped, as a sloshing tank's; docs/theory.md §11)."));
  s.push_back(num(b + ".excluded_limit", "", "0.01", 0, 0.5,
                  "Water particles that leave the weakly compressible range (faster than the sound speed, or "
                  "density off by half: one flung out of a squeeze) are taken out of the water, up to this fraction "
                  "of them; one more stops the run (water_unsound). The log names them (the first twenty one by one); "
                  "summary.json moving_water.excluded. 0: the first stops the run."));
  s.push_back(num(b + ".density_diffusion", "", "0.1", 0, 1, "Density diffusion delta (delta-SPH)."));
  s.push_back(num(b + ".settle", "s", "0", 0, kInf,
                  "Settling of the freshly laid water before step 0, the solid held still and the water's velocity "
                  "damped: over its first half the particles are also packed into the gaps the lattice leaves against "
                  "slanted banks (particle shifting), the second half damps alone."));
  s.push_back(num(b + ".freeboard", "m", "depth", 0, kInf,
                  "Height above the level up to which the bedrock's surface faces are coupled, over the filled x range "
                  "widened by its width on each side (the discrete zone's faces always are). Water that runs up higher "
                  "passes through the rock: the run warns (summary.json moving_water.above_freeboard_particles)."));
  s.push_back(of(b + ".fill", KeyType::List, "below the level over x",
                 "Regions filled with water, outside the solid: rectangles, or polygons below a level."));
  s.push_back(of(b + ".fill[]", KeyType::Map, "", "One region: `rectangle` or `polygon`."));
  s.push_back(of(b + ".fill[].rectangle", KeyType::Points, "", "Corners [[x0, y0], [x1, y1]].", "m"));
  s.push_back(of(b + ".fill[].polygon", KeyType::Points, "", "Polygon corners, at least three.", "m"));
  s.push_back(num(b + ".fill[].level", "m", "reservoir.level", -kInf, kInf, "No water above this level."));
  s.push_back(of(b + ".gauges", KeyType::List, "",
                 "Free-surface gauges: the surface elevation at x in history.csv (<name>_eta_m, above the level). "
                 "The wave's amplitude (history wave_amplitude_m, summary max_wave_amplitude_m) is sought over water at "
                 "least a quarter of the deepest beyond the slide's front, above the still level measured just before "
                 "the slide enters (water alone: over all of it, above the level at step 0)."));
  s.push_back(of(b + ".gauges[]", KeyType::Map, "", "One gauge."));
  s.push_back(of(b + ".gauges[].name", KeyType::String, "required", "Gauge name (history column prefix)."));
  s.push_back(num(b + ".gauges[].x", "m", "required", -kInf, kInf, "Where along the section."));
  s.push_back(of(b + ".runup", KeyType::List, "",
                 "Banks on which the run-up is measured: the highest water on each joined to the pool along "
                 "the bank (a gap of about a spacing bridged; spray landing higher up is left out): its "
                 "elevation in history.csv (<name>_runup_m), its highest above reservoir.level in summary.json "
                 "max_runup_m, and in moving_water.runup the highest elevation, the reading at rest and the "
                 "rise above it."));
  s.push_back(of(b + ".runup[]", KeyType::Map, "", "One bank."));
  s.push_back(of(b + ".runup[].name", KeyType::String, "required", "Its name."));
  s.push_back(of(b + ".runup[].polyline", KeyType::Points, "required", "The bank's surface, at least two points.", "m"));
  s.push_back(of(b + ".pressure", KeyType::List, "",
                 "Curves on which the water's force and peak pressure are measured (an intake, a dam face)."));
  s.push_back(of(b + ".pressure[]", KeyType::Map, "", "One curve."));
  s.push_back(of(b + ".pressure[].name", KeyType::String, "required", "Its name."));
  s.push_back(of(b + ".pressure[].polyline", KeyType::Points, "required", "The curve, at least two points.", "m"));
  s.push_back(of(b + ".crests", KeyType::List, "",
                 "Crests the water may overtop: the volume past each, in history.csv and summary.json."));
  s.push_back(of(b + ".crests[]", KeyType::Map, "", "One crest."));
  s.push_back(of(b + ".crests[].name", KeyType::String, "required", "Its name."));
  s.push_back(of(b + ".crests[].at", KeyType::Vector2, "required", "The crest point; water beyond x above y is past it.",
                 "m"));
  s.push_back(choice(b + ".crests[].side", {"right", "left"}, "right", "The far side: x greater (right) or smaller."));
}

// The reservoir a slide may enter (docs/theory.md §12).
void add_reservoir(std::vector<KeySpec>& s) {
  s.push_back(of("reservoir", KeyType::Map, "",
                 "The reservoir at its still level: the run measures the slide where it enters the water (speed, "
                 "thickness, mass, slope) and gives the Heller & Hager (2010) estimate of the impulse wave. Without a "
                 "discrete zone it is water alone (a tank, a pool shaken by its walls): it then needs `sph`, the water "
                 "moves against the faces of the continuous and contact zones (fixed, or driven by `boundaries`), and "
                 "summary.json heller_hager says `applicable: false`."));
  s.push_back(num("reservoir.level", "m", "required", -kInf, kInf, "Still water level."));
  s.push_back(of("reservoir.x", KeyType::Range, "required",
                 "The reservoir's extent [x_min, x_max] along the section; the bank the slide enters is where the "
                 "ground surface crosses the level at one end (water alone: the span the default fill covers).",
                 "m"));
  s.push_back(num("reservoir.density", "kg/m^3", "1000", 0, kInf, "Water density.", true));
  add_reservoir_sph(s);
}

// Output intervals, checkpoints and gauges.
void add_output(std::vector<KeySpec>& s) {
  s.push_back(of("output", KeyType::Map, "", "What is written and how often."));
  s.push_back(num("output.field_interval", "s", "end/50", 0, kInf, "Interval between VTU frames.", true));
  s.push_back(num("output.history_interval", "s", "end/1000", 0, kInf, "Interval between history rows.", true));
  s.push_back(num("output.progress_interval", "s", "2", 0, kInf, "Wall-clock interval between progress lines.", true));
  s.push_back(num("output.checkpoint_steps", "", "0", 0, kInf,
                  "Write OUT/checkpoint.h5 every this many steps (0: only by wall clock, at the end and on SIGINT/SIGTERM)."));
  s.push_back(num("output.checkpoint_interval", "s", "600", 0, kInf,
                  "Wall-clock interval between checkpoints (0: none by wall clock). A checkpoint is always written at "
                  "the end and on SIGINT/SIGTERM; continue with `dsdem run SCENARIO --restart OUT/checkpoint.h5`."));
  s.push_back(of("output.gauges", KeyType::List, "", "Gauges: material points followed through the run."));
  s.push_back(of("output.gauges[]", KeyType::Map, "", "One gauge."));
  s.push_back(of("output.gauges[].name", KeyType::String, "required", "Gauge name (history column prefix)."));
  s.push_back(of("output.gauges[].at", KeyType::Vector, "required",
                 "Reference position, [x, y] in a plane model, [x, y, z] in a 3D one; the gauge follows the material "
                 "point there.",
                 "m"));
}

// Factor of safety by strength reduction: `dsdem stability` (docs/theory.md §9).
void add_stability(std::vector<KeySpec>& s) {
  s.push_back(of("stability", KeyType::Map, "",
                 "Factor of safety by strength reduction (`dsdem stability`, docs/theory.md §9): c/F, tan(phi)/F and "
                 "ft/F for every joint, Mohr-Coulomb material and contact friction, bisection on F. Ignored by "
                 "`dsdem run`."));
  s.push_back(num("stability.kh", "", "", -kInf, kInf,
                  "Pseudo-static horizontal coefficient: a body force kh g m at every node (g = |gravity|), toward +x for kh > 0 "
                  "(give the sign that pushes toward the free face). With kh or kv the pseudo-static factor is "
                  "found too."));
  s.push_back(num("stability.kv", "", "", -kInf, kInf,
                  "Pseudo-static vertical coefficient: a body force kv g m, upward for kv > 0."));
  s.push_back(of("stability.bounds", KeyType::Range, "[0.5, 4]",
                 "[F_low, F_high]: the bisection's bounds. The slope must stand at F_low and fail at F_high, else "
                 "the command stops with an error that says which."));
  s.push_back(num("stability.tolerance", "", "0.005", 0, kInf,
                  "Bisection stops when F_high - F_low is at most this; the factor of safety is F_low, the largest "
                  "F at which the slope stood.", true));
  s.push_back(num("stability.equilibrium_ratio", "", "1e-5", 0, 1,
                  "Equilibrium: the largest unbalanced nodal force (without the damping force) over the mean "
                  "gravity force of the nodes is below this (FLAC's default).", true, true));
  s.push_back(num("stability.max_steps", "", "auto", 0, kInf,
                  "Step budget of one trial: it bounds the cost only. A trial that neither comes to equilibrium "
                  "nor fails within it is reported undecided (auto: 128 observation windows, more with a fixed "
                  "damping above critical, see "
                  "docs/user-guide.md \"Factor of safety\")."));
  s.push_back(num("stability.failure_displacement", "m", "mean element size", 0, kInf,
                  "A trial failed once a monitored point (or any node without monitor) has moved this far from "
                  "the settled state: the strength-reduced slope slides instead of settling (default: the mean "
                  "element size of the discrete zone, of the whole mesh without one).", true));
  s.push_back(num("stability.local_damping", "", "0.8", 0, 1,
                  "Coefficient of the trials' local non-viscous damping (Cundall; FLAC's and UDEC's 0.8): each "
                  "velocity component is opposed by this fraction of the node's unbalanced force. It brings a "
                  "slope that can stand to rest without holding back one that cannot.", true, true));
  s.push_back(num("stability.damping", "1/s", "adaptive", 0, kInf,
                  "Mass-proportional damping alpha of the trials and the settling, fixed, with the local damping. "
                  "Default: adaptive (Underwood's dynamic relaxation): critical for the slowest mode the motion "
                  "shows, none once the slope softens along its motion; it brings a standing slope to rest "
                  "several times faster than the local damping alone. The factor of safety does not depend on "
                  "it; a large fixed alpha makes the trials near it creep, cost more and end undecided sooner."));
  s.push_back(of("stability.check_budget", KeyType::Boolean, "false",
                 "After the bisection, run the two trials that bracket the factor of safety again, each watched "
                 "twice as long before it is judged and with twice the budget, and say whether their verdicts "
                 "held (summary.json budget_check)."));
  s.push_back(of("stability.keep_tension", KeyType::Boolean, "false", "Do not divide the tensile strengths by F."));
  s.push_back(of("stability.dynamic", KeyType::Boolean, "false",
                 "Also the dynamic factor of safety: from the static settled state, the scenario's earthquake stages "
                 "run at strengths 1/F; a trial fails when a monitored point moves failure_displacement during them."));
  s.push_back(of("stability.monitor", KeyType::List, "",
                 "Monitored points (their displacement decides failure and is plotted against F); default: every "
                 "node."));
  s.push_back(of("stability.monitor[]", KeyType::Map, "", "One monitored point."));
  s.push_back(of("stability.monitor[].name", KeyType::String, "required", "Name of the point."));
  s.push_back(of("stability.monitor[].at", KeyType::Vector2, "required",
                 "Reference position; it must lie in the mesh.", "m"));
}

}  // namespace

// Keys in the order of docs/scenario-reference.md.
std::vector<KeySpec> build_schema() {
  std::vector<KeySpec> s;
  add_mesh_and_materials(s);
  add_boundaries_time_stages(s);
  add_joints(s);
  add_contact(s);
  add_earthquake(s);
  add_water(s);
  add_reservoir(s);
  add_output(s);
  add_stability(s);
  return s;
}

}  // namespace dsdem::io::detail
