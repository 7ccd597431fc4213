#include "run/stability.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "dsdem_version.hpp"
#include "io/atomic_file.hpp"
#include "io/checkpoint.hpp"
#include "io/crack_output.hpp"
#include "io/json_file.hpp"
#include "io/vtu_writer.hpp"
#include "law/strength_reduction.hpp"
#include "run/stage.hpp"
#include "run/text.hpp"
#include "run/time_step.hpp"
#include "solver/gauges.hpp"

namespace dsdem::run {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double unbalanced_force_ratio(const Model& model, double alpha, double gravity) {
  const Nodes& n = model.nodes;
  double max_f2 = 0.0, sum_w = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n.size(); ++i) {
    if (!(n.m[i] > 0.0)) continue;
    const Vec2 f = n.m[i] * (n.a[i] + alpha * n.v[i]);
    max_f2 = std::max(max_f2, f.squaredNorm());
    sum_w += n.m[i] * gravity;
    ++count;
  }
  if (count == 0 || !(sum_w > 0.0)) return 0.0;
  return std::sqrt(max_f2) / (sum_w / static_cast<double>(count));
}

namespace {

constexpr long kCheckEvery = 50;      // steps between equilibrium / failure checks
constexpr long kMinAutoSteps = 10000;  // floor of the automatic step budget

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// One variant (static or pseudo-static): its gravity and settled state.
struct Variant {
  std::string name;         // "static", "pseudo_static"
  Vec2 gravity;             // body force per unit mass, m/s^2
  fs::path settled;         // checkpoint of the settled state
  std::vector<Vec2> u_settled;
  long broken_settled = 0;
  double lowest_failed = 0.0;  // lowest F that failed so far (its mechanism is on disk)
};

class StabilityRunner {
 public:
  StabilityRunner(PreparedRun& prepared, const StabilityOptions& options);
  ~StabilityRunner();
  StabilityResult run();

 private:
  void log(const std::string& line);
  void check_setup();
  void locate_monitors();
  io::StageSpec trial_stage() const;
  io::Scenario scenario_with(const Vec2& gravity) const;
  solver::Solver& new_solver();
  bool stopped() const { return options_.stop_signal && *options_.stop_signal; }
  // Runs to equilibrium with the current solver: true when reached within max_steps.
  bool run_to_equilibrium(double alpha, long max_steps, long& steps, double& ratio);
  void settle_static(Variant& v);
  void settle_pseudo_static(const Variant& from, Variant& v);
  void keep_settled(Variant& v);
  solver::Solver& start_trial(const Variant& v, double F);
  StabilityTrial trial(Variant& v, double F);
  // The dynamic variant's trial: the earthquake stages at strengths 1/F from the settled state.
  StabilityTrial dynamic_trial(Variant& v, double F);
  void record(Variant& v, StabilityTrial& t, std::chrono::steady_clock::time_point t0);
  double max_displacement(const Variant& v) const;
  void write_mechanism(const Variant& v, double F);
  double bisect(Variant& v);
  void write_summary(StabilityResult& r);
  double settled_stage_end() const {  // s: the end of the static stages
    double t = 0.0;
    for (std::size_t si = 0; si <= last_static_; ++si) t += sc_.stages[si].duration;
    return t;
  }

  PreparedRun& prepared_;
  const StabilityOptions& options_;
  const io::Scenario& sc_;
  const io::StabilitySpec& spec_;
  Model& model_;
  const Clock::time_point wall_start_;
  fs::path out_, scratch_;
  std::ofstream log_file_;
  law::FullStrengths full_;
  std::optional<solver::Solver> solver_;
  std::vector<solver::Gauge> monitors_;
  std::size_t last_static_ = 0;  // index of the last static stage
  bool has_quake_ = false;       // the scenario has earthquake stages (after last_static_)
  double alpha_ = 0.0;           // trial damping, 1/s
  long max_steps_ = 0;
  double failure_displacement_ = 0.0;
  double g_ = 9.81;
  double settled_time_ = 0.0;
  std::vector<StabilityTrial> trials_;
  int threads_ = 1;
};

StabilityRunner::StabilityRunner(PreparedRun& prepared, const StabilityOptions& options)
    : prepared_(prepared),
      options_(options),
      sc_(prepared.scenario),
      spec_(prepared.scenario.stability),
      model_(prepared.model),
      wall_start_(Clock::now()),
      out_(options.output_dir) {
  if (options.threads > 0) omp_set_num_threads(options.threads);
  threads_ = omp_get_max_threads();
  full_ = law::full_strengths(model_);
  g_ = sc_.gravity.norm();
}

StabilityRunner::~StabilityRunner() {
  std::error_code ec;
  if (!scratch_.empty()) fs::remove_all(scratch_, ec);
}

void StabilityRunner::log(const std::string& line) {
  if (!options_.quiet) fmt::print(stderr, "{}\n", line);
  if (log_file_) log_file_ << line << '\n' << std::flush;
}

// A static stage to settle in and trials that can come to rest.
void StabilityRunner::check_setup() {
  std::size_t first_quake = sc_.stages.size();
  for (std::size_t si = 0; si < sc_.stages.size(); ++si)
    if (sc_.stages[si].earthquake) {
      first_quake = si;
      break;
    }
  if (first_quake == 0)
    throw io::ScenarioError({fmt::format("{}: stages: the first stage '{}' has the earthquake on: the factor of safety "
                                         "needs a static stage (gravity) before it to settle in",
                                         sc_.file, sc_.stages[0].name)});
  last_static_ = first_quake - 1;
  has_quake_ = first_quake < sc_.stages.size();
  if (spec_.dynamic && !has_quake_)
    throw io::ScenarioError({spec_.where.describe(
        "stability.dynamic needs an earthquake stage (stages[].earthquake: true) after the static ones")});
  const io::StageSpec& st = sc_.stages[last_static_];
  alpha_ = spec_.damping_alpha.value_or(st.damping.alpha);
  if (!(alpha_ > 0.0))
    throw io::ScenarioError({spec_.where.describe(fmt::format(
        "stage '{}' has no mass damping (alpha = 0), so a trial would never come to rest: give stability.damping "
        "(1/s, about critical for the slope's first mode: 4 pi / T1)",
        st.name))});
  if (!(g_ > 0.0)) throw io::ScenarioError({fmt::format("{}: gravity: the factor of safety needs gravity", sc_.file)});
  // Default failure displacement: the mean element size of the breakable zone A (where
  // the slide is), of the whole mesh without one.
  const auto& tri = model_.triangles;
  double size_a = 0.0, size_all = 0.0;
  std::size_t n_a = 0;
  for (std::size_t t = 0; t < tri.size(); ++t) {
    const double h = std::sqrt(2.0 * tri.area0[t]);
    size_all += h;
    if (tri.zone[t] == Zone::Discrete) {
      size_a += h;
      ++n_a;
    }
  }
  const double mean_size = n_a > 0 ? size_a / static_cast<double>(n_a)
                                   : size_all / static_cast<double>(std::max<std::size_t>(1, tri.size()));
  failure_displacement_ = spec_.failure_displacement > 0.0 ? spec_.failure_displacement : mean_size;
  // Automatic budget: 40/alpha of simulated time takes an underdamped mode's amplitude
  // down by e^-20 (mass damping: exp(-alpha t / 2)).
  max_steps_ = spec_.max_steps > 0 ? spec_.max_steps
                                   : std::max<long>(kMinAutoSteps, static_cast<long>(std::ceil(40.0 / (alpha_ * prepared_.dt))));
  if (spec_.kh || spec_.kv) {
    if (sc_.gravity.x() != 0.0)
      throw io::ScenarioError({spec_.where.describe("kh and kv need gravity along -y (gravity: [0, -g])")});
  }
}

// Monitored points must lie in the mesh (within half an element, as gauges).
void StabilityRunner::locate_monitors() {
  double mean_size = 0.0;
  for (double a : model_.triangles.area0) mean_size += std::sqrt(2.0 * a);
  mean_size /= static_cast<double>(std::max<std::size_t>(1, model_.triangles.size()));
  std::vector<std::string> errors;
  for (const auto& m : spec_.monitor) {
    auto g = solver::locate_gauge(model_, m.name, m.at, 0.5 * mean_size);
    if (!g)
      errors.push_back(m.where.describe(
          fmt::format("monitored point '{}' at ({}, {}) m lies outside the mesh", m.name, m.at.x(), m.at.y())));
    else
      monitors_.push_back(*g);
  }
  if (!errors.empty()) throw io::ScenarioError(errors);
}

io::StageSpec StabilityRunner::trial_stage() const {
  io::StageSpec st = sc_.stages[last_static_];
  st.failure = true;
  st.earthquake = false;
  st.damping.alpha = alpha_;
  return st;
}

io::Scenario StabilityRunner::scenario_with(const Vec2& gravity) const {
  io::Scenario s = sc_;
  s.gravity = gravity;
  return s;
}

solver::Solver& StabilityRunner::new_solver() {
  solver_.reset();
  solver_.emplace(model_);
  install_time_step_rule(*solver_, prepared_);
  solver_->set_stress_on_demand(true);
  return *solver_;
}

bool StabilityRunner::run_to_equilibrium(double alpha, long max_steps, long& steps, double& ratio) {
  solver::Solver& s = *solver_;
  for (steps = 0; steps < max_steps && !stopped();) {
    s.step();
    ++steps;
    if (steps % kCheckEvery == 0) {
      ratio = unbalanced_force_ratio(model_, alpha, g_);
      if (ratio < spec_.equilibrium_ratio) return true;
    }
  }
  ratio = unbalanced_force_ratio(model_, alpha, g_);
  return ratio < spec_.equilibrium_ratio;
}

// The scenario's static stages at full strength, joints elastic, then equilibrium.
void StabilityRunner::settle_static(Variant& v) {
  const auto t0 = Clock::now();
  law::apply_reduction(full_, 1.0, {}, model_);
  solver::Solver& s = new_solver();
  const io::Scenario sc = scenario_with(v.gravity);
  double stage_end = 0.0;
  long steps = 0;
  for (std::size_t si = 0; si <= last_static_; ++si) {
    io::StageSpec st = sc_.stages[si];
    st.failure = false;
    apply_stage(s, st, sc, prepared_.dt, s.time(), &prepared_);
    if (si == 0) s.initialise();
    stage_end += st.duration;
    double peak = 0.0;
    const double stage_start = stage_end - st.duration;
    while (s.time() < stage_end - 0.5 * s.settings().dt && !stopped()) {
      s.step();
      ++steps;
      peak = std::max(peak, s.kinetic_energy());
      if (st.stop_kinetic_ratio > 0 && s.kinetic_energy() < st.stop_kinetic_ratio * peak &&
          s.time() > stage_start + 0.05 * st.duration)
        break;
    }
  }
  io::StageSpec st = sc_.stages[last_static_];
  st.failure = false;
  st.damping.alpha = alpha_;
  apply_stage(s, st, sc, prepared_.dt, s.time(), &prepared_);
  long more = 0;
  double ratio = 0.0;
  const bool eq = run_to_equilibrium(alpha_, max_steps_, more, ratio);
  log(fmt::format("settled ({}): the static stages to t = {:.4g} s and {} steps more{}: unbalanced force ratio {:.2e}, "
                  "{} steps, {}",
                  v.name, stage_end, more, eq ? "" : " (no equilibrium within the step budget)", ratio, steps + more,
                  human_time(seconds_since(t0))));
  keep_settled(v);
}

// From the static settled state: the pseudo-static body force on, full strength, elastic joints.
void StabilityRunner::settle_pseudo_static(const Variant& from, Variant& v) {
  const auto t0 = Clock::now();
  law::apply_reduction(full_, 1.0, {}, model_);
  solver::Solver& s = new_solver();
  io::StageSpec st = sc_.stages[last_static_];
  st.failure = false;
  st.damping.alpha = alpha_;
  apply_stage(s, st, scenario_with(v.gravity), prepared_.dt, settled_time_, &prepared_);
  s.initialise();
  s.restore(io::CheckpointReader(from.settled));
  long steps = 0;
  double ratio = 0.0;
  const bool eq = run_to_equilibrium(alpha_, max_steps_, steps, ratio);
  log(fmt::format("settled ({}, body force ({:.4g}, {:.4g}) m/s^2): {} steps{}, unbalanced force ratio {:.2e}, {}",
                  v.name, v.gravity.x(), v.gravity.y(), steps, eq ? "" : " (no equilibrium within the step budget)",
                  ratio, human_time(seconds_since(t0))));
  keep_settled(v);
}

void StabilityRunner::keep_settled(Variant& v) {
  v.settled = scratch_ / fmt::format("settled_{}.h5", v.name);
  io::CheckpointWriter w(v.settled);
  solver_->save(w);
  w.commit();
  v.u_settled = model_.nodes.u;
  v.broken_settled = solver_->broken_joints();
  settled_time_ = solver_->time();
}

double StabilityRunner::max_displacement(const Variant& v) const {
  const auto& u = model_.nodes.u;
  double m2 = 0.0;
  if (monitors_.empty()) {
    for (std::size_t i = 0; i < u.size(); ++i) m2 = std::max(m2, (u[i] - v.u_settled[i]).squaredNorm());
    return std::sqrt(m2);
  }
  double m = 0.0;
  for (const auto& g : monitors_)
    m = std::max(m, (solver::gauge_value(model_, g, u) - solver::gauge_value(model_, g, v.u_settled)).norm());
  return m;
}

// A trial's start: the strengths divided by F (checked), a new solver on the last static
// stage's supports with failure on, restored to the variant's settled state.
solver::Solver& StabilityRunner::start_trial(const Variant& v, double F) {
  law::ReductionOptions ro;
  ro.keep_tension = spec_.keep_tension;
  law::apply_reduction(full_, F, ro, model_);
  for (const auto& p : model_.joint_properties)
    if (const std::string why = validate(p); !why.empty())
      throw io::ScenarioError({spec_.where_bounds.describe(fmt::format("at F = {}: {}", F, why))});
  solver::Solver& s = new_solver();
  apply_stage(s, trial_stage(), scenario_with(v.gravity), prepared_.dt, settled_time_, &prepared_);
  s.initialise();
  s.restore(io::CheckpointReader(v.settled));
  return s;
}

StabilityTrial StabilityRunner::trial(Variant& v, double F) {
  const auto t0 = Clock::now();
  StabilityTrial t;
  t.variant = v.name;
  t.F = F;
  solver::Solver& s = start_trial(v, F);
  bool decided = false;
  try {
    while (t.steps < max_steps_ && !stopped()) {
      s.step();
      ++t.steps;
      if (t.steps % kCheckEvery != 0) continue;
      t.max_displacement = max_displacement(v);
      if (t.max_displacement > failure_displacement_) {
        t.reason = fmt::format("moved {:.3g} m (> {:.3g} m)", t.max_displacement, failure_displacement_);
        decided = true;
        break;
      }
      t.unbalanced_ratio = unbalanced_force_ratio(model_, alpha_, g_);
      if (t.unbalanced_ratio < spec_.equilibrium_ratio) {
        t.stands = true;
        t.reason = "equilibrium";
        decided = true;
        break;
      }
    }
    if (!decided) {
      t.max_displacement = max_displacement(v);
      t.unbalanced_ratio = unbalanced_force_ratio(model_, alpha_, g_);
      t.reason = fmt::format("no equilibrium in {} steps", t.steps);
    }
  } catch (const solver::InstabilityError& e) {
    t.max_displacement = max_displacement(v);
    t.reason = fmt::format("went unstable: {}", e.what());
  }
  t.broken_joints = s.broken_joints() - v.broken_settled;
  record(v, t, t0);
  return t;
}

// Books a finished trial: its mechanism when it is the lowest F that failed, the log line.
void StabilityRunner::record(Variant& v, StabilityTrial& t, std::chrono::steady_clock::time_point t0) {
  const double F = t.F;
  t.wall_time_s = seconds_since(t0);
  if (!t.stands && (v.lowest_failed == 0.0 || F < v.lowest_failed)) {
    v.lowest_failed = F;
    write_mechanism(v, F);
  }
  log(fmt::format("[{}] trial {}: F = {:.4f} {}  ({}; max displacement {:.3g} m, broken joints {}, {} steps, "
                  "unbalanced ratio {:.1e}, {})",
                  v.name, trials_.size() + 1, F, t.stands ? "stands" : "FAILS", t.reason, t.max_displacement,
                  t.broken_joints, t.steps, t.unbalanced_ratio, human_time(t.wall_time_s)));
  trials_.push_back(t);
}

// From the static settled state (its supports and reactions), the scenario's earthquake
// stages as they are, failure on, at strengths 1/F: the slope survives the earthquake
// when no monitored point moves failure_displacement before they end.
StabilityTrial StabilityRunner::dynamic_trial(Variant& v, double F) {
  const auto t0 = Clock::now();
  StabilityTrial t;
  t.variant = v.name;
  t.F = F;
  solver::Solver& s = start_trial(v, F);  // the settled supports: the earthquake stages start from them
  t.stands = true;
  t.reason = "survived the earthquake stages";
  try {
    double stage_end = s.time();
    for (std::size_t si = last_static_ + 1; si < sc_.stages.size() && t.stands && !stopped(); ++si) {
      apply_stage(s, sc_.stages[si], sc_, prepared_.dt, s.time(), &prepared_);
      stage_end += sc_.stages[si].duration;
      while (s.time() < stage_end - 0.5 * s.settings().dt && !stopped()) {
        s.step();
        ++t.steps;
        if (t.steps % kCheckEvery != 0) continue;
        t.max_displacement = std::max(t.max_displacement, max_displacement(v));
        if (t.max_displacement > failure_displacement_) {
          t.stands = false;
          t.reason = fmt::format("moved {:.3g} m (> {:.3g} m) at t = {:.3g} s in stage '{}'", t.max_displacement,
                                 failure_displacement_, s.time(), sc_.stages[si].name);
          break;
        }
      }
    }
    t.max_displacement = std::max(t.max_displacement, max_displacement(v));
  } catch (const solver::InstabilityError& e) {
    t.stands = false;
    t.max_displacement = max_displacement(v);
    t.reason = fmt::format("went unstable: {}", e.what());
  }
  t.unbalanced_ratio = unbalanced_force_ratio(model_, 0.0, g_);
  t.broken_joints = s.broken_joints() - v.broken_settled;
  record(v, t, t0);
  return t;
}

// The state of a failed trial: displacement since the settled state and the broken joints.
void StabilityRunner::write_mechanism(const Variant& v, double F) {
  const std::string suffix = v.name == "static" ? "" : "_" + v.name;
  std::vector<Vec2> du(model_.nodes.size());
  for (std::size_t i = 0; i < du.size(); ++i) du[i] = model_.nodes.u[i] - v.u_settled[i];
  solver_->update_stress();
  io::VtuOptions vo;
  vo.time_s = F;  // the frame's "time" is the factor it failed at
  io::write_triangles_vtu(out_ / fmt::format("mechanism{}.vtu", suffix), model_.nodes, model_.triangles,
                          model_.materials, {io::vector_field("displacement_since_settled", "m", du)}, {}, vo);
  solver_->release_stress();
  if (model_.joints.size() > 0)
    io::write_cracks_vtu(out_ / fmt::format("mechanism_cracks{}.vtu", suffix), model_, F);
}

double StabilityRunner::bisect(Variant& v) {
  auto trial = [&](Variant& var, double F) { return var.name == "dynamic" ? dynamic_trial(var, F) : this->trial(var, F); };
  double lo = spec_.F_low, hi = spec_.F_high;
  const StabilityTrial at_lo = trial(v, lo);
  if (stopped()) return lo;
  if (!at_lo.stands)
    throw io::ScenarioError({spec_.where_bounds.describe(fmt::format(
        "the slope ({}) already fails at F_low = {} ({}): lower the bounds", v.name, lo, at_lo.reason))});
  const StabilityTrial at_hi = trial(v, hi);
  if (stopped()) return lo;
  if (at_hi.stands)
    throw io::ScenarioError({spec_.where_bounds.describe(fmt::format(
        "the slope ({}) still stands at F_high = {}: raise the bounds", v.name, hi))});
  while (hi - lo > spec_.tolerance * (1.0 + 1e-12) && !stopped()) {
    const double mid = 0.5 * (lo + hi);
    if (trial(v, mid).stands)
      lo = mid;
    else
      hi = mid;
  }
  log(fmt::format("[{}] factor of safety {:.4f} (stands at {:.4f}, fails at {:.4f})", v.name, lo, lo, hi));
  return lo;
}

void StabilityRunner::write_summary(StabilityResult& r) {
  nlohmann::ordered_json s;
  s["dsdem_version"] = std::string(DSDEM_VERSION) + " (" + DSDEM_GIT_COMMIT + ")";
  s["scenario"] = sc_.file;
  s["title"] = sc_.title;
  s["factor_of_safety"] = r.factor_of_safety;
  if (r.factor_of_safety_pseudo_static) s["factor_of_safety_pseudo_static"] = *r.factor_of_safety_pseudo_static;
  if (r.factor_of_safety_dynamic) s["factor_of_safety_dynamic"] = *r.factor_of_safety_dynamic;
  nlohmann::ordered_json m;
  m["method"] = "strength reduction (DESIGN.md §12): c/F, tan(phi)/F" +
                std::string(spec_.keep_tension ? "" : ", ft/F") + " for joints, Mohr-Coulomb materials and contact "
                "friction; bisection on F";
  m["bounds"] = {spec_.F_low, spec_.F_high};
  m["tolerance"] = spec_.tolerance;
  m["equilibrium_ratio"] = spec_.equilibrium_ratio;
  m["failure_displacement_m"] = failure_displacement_;
  m["max_steps"] = max_steps_;
  m["damping_alpha_per_s"] = alpha_;
  m["keep_tension"] = spec_.keep_tension;
  m["dynamic"] = spec_.dynamic;
  if (spec_.kh) m["kh"] = *spec_.kh;
  if (spec_.kv) m["kv"] = *spec_.kv;
  nlohmann::ordered_json mon = nlohmann::ordered_json::array();
  for (const auto& g : spec_.monitor) mon.push_back({{"name", g.name}, {"at_m", {g.at.x(), g.at.y()}}});
  m["monitor"] = mon;
  s["settings"] = m;
  nlohmann::ordered_json tr = nlohmann::ordered_json::array();
  for (const auto& t : r.trials)
    tr.push_back({{"variant", t.variant},
                  {"F", t.F},
                  {"result", !t.stands ? "failed" : t.variant == "dynamic" ? "survived" : "equilibrium"},
                  {"reason", t.reason},
                  {"max_displacement_m", t.max_displacement},
                  {"broken_joints", t.broken_joints},
                  {"steps", t.steps},
                  {"unbalanced_ratio", t.unbalanced_ratio},
                  {"wall_time_s", t.wall_time_s}});
  s["trials"] = tr;
  s["threads"] = threads_;
  s["wall_time_s"] = r.wall_time_s;
  r.summary_path = (out_ / "summary.json").string();
  io::write_json_file(out_ / "summary.json", s);
}

StabilityResult StabilityRunner::run() {
  check_setup();
  locate_monitors();
  try {
    io::ensure_writable_directory(out_);
  } catch (const std::exception& e) {
    throw io::ScenarioError({fmt::format("--output {}: {}", out_.string(), e.what())});
  }
  log_file_.open(out_ / "stability.log");
  scratch_ = fs::temp_directory_path() / fmt::format("dsdem-stability-{}", ::getpid());
  fs::create_directories(scratch_);
  log(fmt::format("dsdem {} ({}), {} threads: factor of safety of {} ({} nodes, {} triangles, {} joints)",
                  DSDEM_VERSION, DSDEM_GIT_COMMIT, threads_, sc_.file, model_.nodes.size(), model_.triangles.size(),
                  model_.joints.size()));
  log(fmt::format("trials: damping alpha {} 1/s, at most {} steps (dt {:.3g} s), equilibrium at unbalanced force "
                  "ratio < {:.1e}, failure past {:.3g} m of displacement{}",
                  alpha_, max_steps_, prepared_.dt, spec_.equilibrium_ratio, failure_displacement_,
                  monitors_.empty() ? " (any node)" : " (monitored points)"));
  StabilityResult r;
  Variant stat{"static", sc_.gravity, {}, {}, 0, 0.0};
  settle_static(stat);
  if (!stopped()) r.factor_of_safety = bisect(stat);
  if ((spec_.kh || spec_.kv) && !stopped()) {
    const Vec2 g = sc_.gravity + g_ * Vec2(spec_.kh.value_or(0.0), spec_.kv.value_or(0.0));
    Variant ps{"pseudo_static", g, {}, {}, 0, 0.0};
    settle_pseudo_static(stat, ps);
    if (!stopped()) r.factor_of_safety_pseudo_static = bisect(ps);
  }
  if (spec_.dynamic && !stopped()) {
    Variant dyn = stat;
    dyn.name = "dynamic";
    dyn.lowest_failed = 0.0;
    log(fmt::format("[dynamic] each trial runs the earthquake stages ({} s) from the static settled state",
                    sc_.end_time() - settled_stage_end()));
    r.factor_of_safety_dynamic = bisect(dyn);
  }
  law::apply_reduction(full_, 1.0, {}, model_);
  r.trials = trials_;
  r.wall_time_s = seconds_since(wall_start_);
  if (stopped()) {
    r.stopped_by_signal = static_cast<int>(*options_.stop_signal);
    log(fmt::format("stopped by {}: no factor of safety", signal_name(r.stopped_by_signal)));
    return r;
  }
  write_summary(r);
  log(fmt::format("done in {}: factor of safety {:.4f}{}", human_time(r.wall_time_s), r.factor_of_safety,
                  r.factor_of_safety_pseudo_static
                      ? fmt::format(", pseudo-static {:.4f}", *r.factor_of_safety_pseudo_static)
                      : std::string()) +
      (r.factor_of_safety_dynamic ? fmt::format(", dynamic {:.4f}", *r.factor_of_safety_dynamic) : std::string()));
  return r;
}

}  // namespace

StabilityResult find_factor_of_safety(PreparedRun& prepared, const StabilityOptions& options) {
  return StabilityRunner(prepared, options).run();
}

}  // namespace dsdem::run
