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
#include "run/run3d.hpp"
#include "run/stage.hpp"
#include "run/text.hpp"
#include "run/time_step.hpp"
#include "solver/gauges.hpp"

namespace dsdem::run {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const char* trial_result_name(TrialResult r) {
  switch (r) {
    case TrialResult::Equilibrium: return "equilibrium";
    case TrialResult::Failed: return "failed";
    case TrialResult::Undecided: return "undecided";
    case TrialResult::Survived: return "survived";
  }
  return "?";
}

template <int D>
double unbalanced_force_ratio(const NodeArrays<D>& n, std::type_identity_t<std::span<const VecD<D>>> damping_forces,
                              double gravity) {
  const bool damped = damping_forces.size() == n.size();
  double max_f2 = 0.0, sum_w = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n.size(); ++i) {
    if (!(n.m[i] > 0.0)) continue;
    const VecD<D> f = damped ? VecD<D>(n.m[i] * n.a[i] - damping_forces[i]) : VecD<D>(n.m[i] * n.a[i]);
    max_f2 = std::max(max_f2, f.squaredNorm());
    sum_w += n.m[i] * gravity;
    ++count;
  }
  if (count == 0 || !(sum_w > 0.0)) return 0.0;
  return std::sqrt(max_f2) / (sum_w / static_cast<double>(count));
}
template double unbalanced_force_ratio<2>(const NodeArrays<2>&, std::span<const Vec2>, double);
template double unbalanced_force_ratio<3>(const NodeArrays<3>&, std::span<const Vec3>, double);

double unbalanced_force_ratio(const Model& model, std::span<const Vec2> damping_forces, double gravity) {
  return unbalanced_force_ratio<2>(model.nodes, damping_forces, gravity);
}

namespace {

constexpr long kCheckEvery = 50;       // steps between equilibrium / failure checks
constexpr long kMinWindow = 250;        // least observation window, steps
constexpr long kFirstJudgement = 8;     // windows before the first judgement of motion
constexpr long kAutoBudgetWindows = 128; // the automatic budget, windows (five judgements)
constexpr double kMovingFloor = 1e-4;   // of failure_displacement: the least motion that counts
constexpr double kSlidAndStopped = 0.1; // of failure_displacement: a standing trial that moved this far is noted

// When a trial's motion is judged and how long it may run, steps.
struct Watch {
  long first_judgement = 0;  // then at every doubling
  long budget = 0;
};

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The model, prepared run and solver of each dimension: the procedure is the same.
template <int D>
struct Dimension;
template <>
struct Dimension<2> {
  using Prepared = PreparedRun;
  using ModelT = Model;
  using SolverT = solver::Solver;
};
template <>
struct Dimension<3> {
  using Prepared = PreparedRun3;
  using ModelT = Model3;
  using SolverT = solver::Solver3;
};

// One variant (static or pseudo-static): its gravity and settled state.
template <int D>
struct Variant {
  std::string name;         // "static", "pseudo_static"
  VecD<D> gravity;          // body force per unit mass, m/s^2
  fs::path settled;         // checkpoint of the settled state
  std::vector<VecD<D>> u_settled;
  long broken_settled = 0;
  double lowest_failed = 0.0;  // lowest F that failed so far (its mechanism is on disk)
};

// The trial stage's damping: the quasi-static solver (docs/theory.md §9).
io::DampingSpec quasi_static_damping(const io::StabilitySpec& spec) {
  io::DampingSpec d;
  d.alpha = spec.damping_alpha.value_or(0.0);
  d.beta = 0.0;
  d.local = spec.local_damping;
  return d;
}

template <int D>
class StabilityRunner {
 public:
  using Prepared = typename Dimension<D>::Prepared;
  using ModelT = typename Dimension<D>::ModelT;
  using SolverT = typename Dimension<D>::SolverT;
  using Vec = VecD<D>;
  using Variant = run::Variant<D>;
  StabilityRunner(Prepared& prepared, const StabilityOptions& options);
  ~StabilityRunner();
  StabilityResult run();

 private:
  void log(const std::string& line);
  void check_setup();
  void locate_monitors();
  io::StageSpec trial_stage() const;
  // The scenario's body force (m/s^2).
  Vec scenario_gravity() const;
  // The solver set up for a stage starting at start_time under `gravity` (run/stage.hpp,
  // run/run3d.hpp).
  void apply_stage_to(SolverT& s, const io::StageSpec& st, const Vec& gravity, double start_time);
  SolverT& new_solver();
  long broken_joints(const SolverT& s) const;
  // The mean element size (m) of the breakable zone, else of the whole mesh.
  double mean_element_size(bool breakable_zone_only) const;
  bool stopped() const { return options_.stop_signal && *options_.stop_signal; }
  // A check's unbalanced force ratio; then the adaptive mass damping for the next check
  // interval from the motion since the last check (docs/theory.md §9).
  double check_and_adapt(SolverT& s);
  void start_watching();  // the motion is measured from the current state
  // Runs to equilibrium with the current solver: true when reached within max_steps.
  bool run_to_equilibrium(long max_steps, long& steps, double& ratio);
  // The observation window from the settled static state (its period), and the watch.
  void choose_window(const std::vector<Vec>& u_before_settling);
  void settle_static(Variant& v);
  void settle_pseudo_static(const Variant& from, Variant& v);
  void keep_settled(Variant& v);
  SolverT& start_trial(const Variant& v, double F);
  StabilityTrial trial(Variant& v, double F, const Watch& watch, bool budget_check = false);
  // The dynamic variant's trial: the earthquake stages at strengths 1/F from the settled state.
  StabilityTrial dynamic_trial(Variant& v, double F);
  void record(Variant& v, StabilityTrial& t, std::chrono::steady_clock::time_point t0);
  double max_displacement(const Variant& v) const;
  void write_mechanism(const Variant& v, double F);
  double bisect(Variant& v);
  void check_budget(Variant& v, StabilityBracket& b);
  void write_summary(StabilityResult& r);
  void write_trial_histories() const;
  double settled_stage_end() const {  // s: the end of the static stages
    double t = 0.0;
    for (std::size_t si = 0; si <= last_static_; ++si) t += sc_.stages[si].duration;
    return t;
  }

  Prepared& prepared_;
  const StabilityOptions& options_;
  const io::Scenario& sc_;
  const io::StabilitySpec& spec_;
  ModelT& model_;
  const Clock::time_point wall_start_;
  fs::path out_, scratch_;
  std::ofstream log_file_;
  law::FullStrengths full_;
  std::optional<SolverT> solver_;
  std::vector<solver::Gauge> monitors_;
  std::size_t last_static_ = 0;  // index of the last static stage
  bool has_quake_ = false;       // the scenario has earthquake stages (after last_static_)
  long max_steps_ = 0;           // budget of the settling's equilibrium run and of each trial
  double period_ = 0.0;          // s: the slope's fundamental period (the window's)
  std::string period_source_;    // how it was estimated
  long window_ = 0;              // observation window, steps
  Watch watch_;                  // the trials'
  std::vector<StabilityBracket> brackets_;
  // The adaptive damping's last check: displacements and unbalanced forces; scratch.
  std::vector<Vec> u_last_, f_last_, f_now_, du_, df_;
  double failure_displacement_ = 0.0;
  double g_ = 9.81;
  double settled_time_ = 0.0;
  std::vector<StabilityTrial> trials_;
  int threads_ = 1;
};

template <int D>
StabilityRunner<D>::StabilityRunner(Prepared& prepared, const StabilityOptions& options)
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
  g_ = scenario_gravity().norm();
}

template <int D>
StabilityRunner<D>::~StabilityRunner() {
  std::error_code ec;
  if (!scratch_.empty()) fs::remove_all(scratch_, ec);
}

template <int D>
void StabilityRunner<D>::log(const std::string& line) {
  if (!options_.quiet) fmt::print(stderr, "{}\n", line);
  if (log_file_) log_file_ << line << '\n' << std::flush;
}

// A static stage to settle in and trials that can come to rest.
template <int D>
void StabilityRunner<D>::check_setup() {
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
  if (!(g_ > 0.0)) throw io::ScenarioError({fmt::format("{}: gravity: the factor of safety needs gravity", sc_.file)});
  // Default failure displacement: the mean element size of the breakable zone A (where
  // the slide is), of the whole mesh without one.
  failure_displacement_ = spec_.failure_displacement > 0.0 ? spec_.failure_displacement : mean_element_size(true);
  // The settling's equilibrium run: the trials' budget or, before the window is known, a
  // generous one (a settled slope is near equilibrium already).
  max_steps_ = spec_.max_steps > 0 ? spec_.max_steps : 1000000;
  if (spec_.kh || spec_.kv) {
    // kh along x, kv along the vertical (y in a plane model, z in 3D).
    const Vec g = scenario_gravity();
    if (g.head(D - 1) != VecD<D - 1>::Zero())
      throw io::ScenarioError({spec_.where.describe(D == 2 ? "kh and kv need gravity along -y (gravity: [0, -g])"
                                                           : "kh and kv need gravity along -z (gravity: [0, 0, -g])")});
  }
}

// Monitored points must lie in the mesh (within half an element, as gauges).
template <int D>
void StabilityRunner<D>::locate_monitors() {
  if constexpr (D == 3) {
    return;  // refused in 3D when the run is prepared (run3d.cpp): every node is watched
  } else {
  const double mean_size = mean_element_size(false);
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
}

template <int D>
io::StageSpec StabilityRunner<D>::trial_stage() const {
  io::StageSpec st = sc_.stages[last_static_];
  st.failure = true;
  st.earthquake = false;
  st.damping = quasi_static_damping(spec_);
  return st;
}

template <>
Vec2 StabilityRunner<2>::scenario_gravity() const { return sc_.gravity; }
template <>
Vec3 StabilityRunner<3>::scenario_gravity() const { return prepared_.gravity; }

template <>
void StabilityRunner<2>::apply_stage_to(solver::Solver& s, const io::StageSpec& st, const Vec2& gravity,
                                        double start_time) {
  io::Scenario sc = sc_;
  sc.gravity = gravity;
  apply_stage(s, st, sc, prepared_.dt, start_time, &prepared_);
}
template <>
void StabilityRunner<3>::apply_stage_to(solver::Solver3& s, const io::StageSpec& st, const Vec3& gravity,
                                        double start_time) {
  apply_stage_3d(s, st, prepared_, gravity, start_time);
}

template <>
solver::Solver& StabilityRunner<2>::new_solver() {
  solver_.reset();
  solver_.emplace(model_);
  install_time_step_rule(*solver_, prepared_);
  solver_->set_stress_on_demand(true);
  return *solver_;
}
template <>
solver::Solver3& StabilityRunner<3>::new_solver() {
  solver_.reset();
  solver_.emplace(model_);
  return *solver_;
}

template <>
long StabilityRunner<2>::broken_joints(const solver::Solver& s) const { return s.broken_joints(); }
template <>
long StabilityRunner<3>::broken_joints(const solver::Solver3&) const { return 0; }  // no joints in 3D yet

// Plane: the leg sqrt(2 A) of each triangle; 3D: the edge cbrt(6 V) of the cube each
// tetrahedron is a sixth of.
template <>
double StabilityRunner<2>::mean_element_size(bool breakable_zone_only) const {
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
  if (breakable_zone_only && n_a > 0) return size_a / static_cast<double>(n_a);
  return size_all / static_cast<double>(std::max<std::size_t>(1, tri.size()));
}
template <>
double StabilityRunner<3>::mean_element_size(bool) const {
  const auto& tet = model_.tetrahedra;
  double size = 0.0;
  for (double v : tet.volume0) size += std::cbrt(6.0 * v);
  return size / static_cast<double>(std::max<std::size_t>(1, tet.size()));
}

template <int D>
void StabilityRunner<D>::start_watching() {
  const auto& n = model_.nodes;
  const std::size_t nn = n.size();
  u_last_ = n.u;
  f_last_.assign(nn, Vec::Zero());
  const auto fd = solver_->damping_forces();
  for (std::size_t i = 0; i < nn; ++i)
    f_last_[i] = fd.size() == nn ? Vec(n.m[i] * n.a[i] - fd[i]) : Vec(n.m[i] * n.a[i]);
  f_now_.resize(nn);
  du_.resize(nn);
  df_.resize(nn);
  solver_->set_mass_damping(spec_.damping_alpha.value_or(0.0));
}

// Underwood's adaptive dynamic relaxation on top of the local damping: mass damping
// critical for the slowest mode the motion shows, 2 omega, from Rayleigh's quotient of the
// interval's displacement and force increments; none once the slope softens along its
// motion, so a failing mass is never held back.
template <int D>
double StabilityRunner<D>::check_and_adapt(SolverT& s) {
  const auto& n = model_.nodes;
  const std::size_t nn = n.size();
  const auto fd = s.damping_forces();
  for (std::size_t i = 0; i < nn; ++i) {
    f_now_[i] = fd.size() == nn ? Vec(n.m[i] * n.a[i] - fd[i]) : Vec(n.m[i] * n.a[i]);
    du_[i] = n.u[i] - u_last_[i];
    df_[i] = f_now_[i] - f_last_[i];
  }
  const double ratio = unbalanced_force_ratio<D>(n, fd, g_);
  if (!spec_.damping_alpha) {
    const double w2 = rayleigh_omega2<D>(n, du_, df_);
    s.set_mass_damping(w2 > 0.0 ? 2.0 * std::sqrt(w2) : 0.0);
  }
  std::copy(n.u.begin(), n.u.end(), u_last_.begin());
  std::copy(f_now_.begin(), f_now_.end(), f_last_.begin());
  return ratio;
}

template <int D>
bool StabilityRunner<D>::run_to_equilibrium(long max_steps, long& steps, double& ratio) {
  SolverT& s = *solver_;
  start_watching();
  for (steps = 0; steps < max_steps && !stopped();) {
    s.step();
    ++steps;
    if (steps % kCheckEvery == 0) {
      ratio = check_and_adapt(s);
      if (ratio < spec_.equilibrium_ratio) return true;
    }
  }
  ratio = unbalanced_force_ratio<D>(model_.nodes, s.damping_forces(), g_);
  return ratio < spec_.equilibrium_ratio;
}

// The window is about the slope's fundamental period: Rayleigh's quotient on the
// displacement of settling under gravity, or a shear column's 4 H / vs over the mesh's
// height with the slowest material when the settling moved nothing measurable.
template <int D>
void StabilityRunner<D>::choose_window(const std::vector<Vec>& u_before_settling) {
  std::vector<Vec> du(model_.nodes.size());
  for (std::size_t i = 0; i < du.size(); ++i) du[i] = model_.nodes.u[i] - u_before_settling[i];
  period_ = rayleigh_period<D>(model_.nodes, du, scenario_gravity());
  period_source_ = "Rayleigh's quotient on the settling displacement";
  if (!(period_ > 0.0)) {
    double y_min = 1e300, y_max = -1e300, vs = 1e300;
    for (std::size_t i = 0; i < model_.nodes.size(); ++i) {
      y_min = std::min(y_min, model_.nodes.X[i][D - 1]);  // the vertical: y, or z in 3D
      y_max = std::max(y_max, model_.nodes.X[i][D - 1]);
    }
    for (const auto& m : model_.materials)
      if (m.rho > 0.0 && m.E > 0.0) vs = std::min(vs, m.cs());
    period_ = shear_column_period(y_max - y_min, vs);
    period_source_ = "4 H / vs of the mesh's height and its slowest material";
  }
  const double dt = solver_->dt();
  window_ = std::max<long>(kMinWindow, static_cast<long>(std::ceil(period_ / dt)));
  // Judgements at 8, 16, 32, ... windows fall on check steps whose halves and quarters are too.
  const long unit = 4 * kCheckEvery;
  watch_.first_judgement = (kFirstJudgement * window_ + unit - 1) / unit * unit;
  // A fixed mass damping above critical for the fundamental mode (4 pi / T1) slows the
  // relaxation by alpha over critical: the automatic budget grows with it.
  const double overdamping = spec_.damping_alpha ? std::max(1.0, *spec_.damping_alpha * period_ / (4.0 * kPi)) : 1.0;
  watch_.budget = spec_.max_steps > 0
                      ? spec_.max_steps
                      : static_cast<long>(std::ceil(overdamping * static_cast<double>(watch_.first_judgement) *
                                                    (kAutoBudgetWindows / kFirstJudgement) / kCheckEvery)) *
                            kCheckEvery;
  max_steps_ = watch_.budget;
}

// The scenario's static stages at full strength, joints elastic, then equilibrium.
template <int D>
void StabilityRunner<D>::settle_static(Variant& v) {
  const auto t0 = Clock::now();
  law::apply_reduction(full_, 1.0, {}, model_);
  const std::vector<Vec> u_before = model_.nodes.u;
  SolverT& s = new_solver();
  double stage_end = 0.0;
  long steps = 0;
  for (std::size_t si = 0; si <= last_static_; ++si) {
    io::StageSpec st = sc_.stages[si];
    st.failure = false;
    apply_stage_to(s, st, v.gravity, s.time());
    if (si == 0) s.initialise();
    stage_end += st.duration;
    double peak = 0.0;
    const double stage_start = stage_end - st.duration;
    while (s.time() < stage_end - 0.5 * s.dt() && !stopped()) {
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
  st.damping = quasi_static_damping(spec_);
  apply_stage_to(s, st, v.gravity, s.time());
  long more = 0;
  double ratio = 0.0;
  const bool eq = run_to_equilibrium(max_steps_, more, ratio);
  log(fmt::format("settled ({}): the static stages to t = {:.4g} s and {} steps more{}: unbalanced force ratio {:.2e}, "
                  "{} steps, {}",
                  v.name, stage_end, more, eq ? "" : " (no equilibrium within the step budget)", ratio, steps + more,
                  human_time(seconds_since(t0))));
  keep_settled(v);
  choose_window(u_before);
}

// From the static settled state: the pseudo-static body force on, full strength, elastic joints.
template <int D>
void StabilityRunner<D>::settle_pseudo_static(const Variant& from, Variant& v) {
  const auto t0 = Clock::now();
  law::apply_reduction(full_, 1.0, {}, model_);
  SolverT& s = new_solver();
  io::StageSpec st = sc_.stages[last_static_];
  st.failure = false;
  st.damping = quasi_static_damping(spec_);
  apply_stage_to(s, st, v.gravity, settled_time_);
  s.initialise();
  s.restore(io::CheckpointReader(from.settled));
  long steps = 0;
  double ratio = 0.0;
  const bool eq = run_to_equilibrium(max_steps_, steps, ratio);
  std::string body_force;
  for (int d = 0; d < D; ++d) body_force += fmt::format("{}{:.4g}", d > 0 ? ", " : "", v.gravity[d]);
  log(fmt::format("settled ({}, body force ({}) m/s^2): {} steps{}, unbalanced force ratio {:.2e}, {}",
                  v.name, body_force, steps, eq ? "" : " (no equilibrium within the step budget)",
                  ratio, human_time(seconds_since(t0))));
  keep_settled(v);
}

template <int D>
void StabilityRunner<D>::keep_settled(Variant& v) {
  v.settled = scratch_ / fmt::format("settled_{}.h5", v.name);
  io::CheckpointWriter w(v.settled);
  solver_->save(w);
  w.commit();
  v.u_settled = model_.nodes.u;
  v.broken_settled = broken_joints(*solver_);
  settled_time_ = solver_->time();
}

template <int D>
double StabilityRunner<D>::max_displacement(const Variant& v) const {
  const auto& u = model_.nodes.u;
  double m2 = 0.0;
  if (monitors_.empty()) {
    for (std::size_t i = 0; i < u.size(); ++i) m2 = std::max(m2, (u[i] - v.u_settled[i]).squaredNorm());
    return std::sqrt(m2);
  }
  double m = 0.0;
  if constexpr (D == 2)
    for (const auto& g : monitors_)
      m = std::max(m, (solver::gauge_value(model_, g, u) - solver::gauge_value(model_, g, v.u_settled)).norm());
  return m;
}

// A trial's start: the strengths divided by F (checked), a new solver on the last static
// stage's supports with failure on, restored to the variant's settled state: every trial
// starts from it, so none inherits another's motion (a slope that slid and stopped again
// would stand at the next F on a shape no longer its own).
template <int D>
typename StabilityRunner<D>::SolverT& StabilityRunner<D>::start_trial(const Variant& v, double F) {
  law::ReductionOptions ro;
  ro.keep_tension = spec_.keep_tension;
  law::apply_reduction(full_, F, ro, model_);
  if constexpr (D == 2)
    for (const auto& p : model_.joint_properties)
      if (const std::string why = validate(p); !why.empty())
        throw io::ScenarioError({spec_.where_bounds.describe(fmt::format("at F = {}: {}", F, why))});
  SolverT& s = new_solver();
  apply_stage_to(s, trial_stage(), v.gravity, settled_time_);
  s.initialise();
  s.restore(io::CheckpointReader(v.settled));
  return s;
}

template <int D>
StabilityTrial StabilityRunner<D>::trial(Variant& v, double F, const Watch& watch, bool budget_check) {
  const auto t0 = Clock::now();
  StabilityTrial t;
  t.variant = v.name;
  t.F = F;
  t.budget_check = budget_check;
  t.history.reserve(static_cast<std::size_t>(watch.budget / kCheckEvery + 1));
  SolverT& s = start_trial(v, F);
  start_watching();
  const double floor = kMovingFloor * failure_displacement_;
  long next_judgement = watch.first_judgement;
  bool decided = false;
  try {
    while (t.steps < watch.budget && !stopped()) {
      s.step();
      ++t.steps;
      if (t.steps % kCheckEvery != 0) continue;
      t.max_displacement = max_displacement(v);
      t.unbalanced_ratio = check_and_adapt(s);
      t.history.push_back({t.steps, t.unbalanced_ratio, t.max_displacement});
      if (t.max_displacement > failure_displacement_) {
        t.result = TrialResult::Failed;
        t.reason = fmt::format("moved {:.3g} m (> {:.3g} m)", t.max_displacement, failure_displacement_);
        decided = true;
        break;
      }
      if (t.unbalanced_ratio < spec_.equilibrium_ratio) {
        t.result = TrialResult::Equilibrium;
        t.reason = "equilibrium";
        decided = true;
        break;
      }
      if (t.steps == next_judgement) {
        const MotionTrend m = motion_trend(t.history, kCheckEvery, floor);
        if (m.keeps_moving) {
          t.result = TrialResult::Failed;
          t.reason = fmt::format(
              "keeps moving: {:.3g} m in its last {} steps, velocity x{:.3g} and unbalanced force ratio x{:.3g} "
              "over the half before",
              m.moved_late, t.steps / 2, m.velocity_early > 0.0 ? m.velocity_late / m.velocity_early : 0.0,
              m.ratio_early > 0.0 ? m.ratio_late / m.ratio_early : 0.0);
          decided = true;
          break;
        }
        next_judgement *= 2;
      }
    }
    if (!decided) {
      t.result = TrialResult::Undecided;
      t.reason = fmt::format("neither equilibrium nor failure in {} steps (stability.max_steps)", t.steps);
    }
  } catch (const solver::InstabilityError& e) {
    t.max_displacement = max_displacement(v);
    t.result = TrialResult::Failed;
    t.reason = fmt::format("went unstable: {}", e.what());
  }
  t.broken_joints = broken_joints(s) - v.broken_settled;
  record(v, t, t0);
  return t;
}

// Books a finished trial: its mechanism when it is the lowest F that failed, the log line.
template <int D>
void StabilityRunner<D>::record(Variant& v, StabilityTrial& t, std::chrono::steady_clock::time_point t0) {
  const double F = t.F;
  t.wall_time_s = seconds_since(t0);
  // A jointed mass may slide, break joints and come to rest again on them: it stands by
  // equilibrium, but an engineer may call that movement failure.
  if (t.stands() && t.broken_joints > 0 && t.max_displacement > kSlidAndStopped * failure_displacement_)
    t.note = fmt::format("stood again after moving {:.3g} m and breaking {} joints: if that is failure, give "
                         "stability.failure_displacement below it",
                         t.max_displacement, t.broken_joints);
  if (t.result == TrialResult::Failed && !t.budget_check && (v.lowest_failed == 0.0 || F < v.lowest_failed)) {
    v.lowest_failed = F;
    write_mechanism(v, F);
  }
  const char* verdict = t.result == TrialResult::Failed ? "FAILS" : t.result == TrialResult::Undecided ? "UNDECIDED"
                                                                                                      : "stands";
  log(fmt::format("[{}] {} {}: F = {:.4f} {}  ({}; max displacement {:.3g} m, broken joints {}, {} steps, "
                  "unbalanced ratio {:.1e}, {})",
                  v.name, t.budget_check ? "budget check" : "trial", trials_.size() + 1, F, verdict, t.reason,
                  t.max_displacement,
                  t.broken_joints, t.steps, t.unbalanced_ratio, human_time(t.wall_time_s)));
  if (!t.note.empty()) log(fmt::format("[{}]   note: F = {:.4f} {}", v.name, F, t.note));
  trials_.push_back(t);
}

// From the static settled state (its supports and reactions), the scenario's earthquake
// stages as they are, failure on, at strengths 1/F: the slope survives the earthquake
// when no monitored point moves failure_displacement before they end.
template <int D>
StabilityTrial StabilityRunner<D>::dynamic_trial(Variant& v, double F) {
  const auto t0 = Clock::now();
  StabilityTrial t;
  t.variant = v.name;
  t.F = F;
  SolverT& s = start_trial(v, F);  // the settled supports: the earthquake stages start from them
  t.result = TrialResult::Survived;
  t.reason = "survived the earthquake stages";
  try {
    double stage_end = s.time();
    for (std::size_t si = last_static_ + 1; si < sc_.stages.size() && t.stands() && !stopped(); ++si) {
      apply_stage_to(s, sc_.stages[si], scenario_gravity(), s.time());
      stage_end += sc_.stages[si].duration;
      while (s.time() < stage_end - 0.5 * s.dt() && !stopped()) {
        s.step();
        ++t.steps;
        if (t.steps % kCheckEvery != 0) continue;
        t.max_displacement = std::max(t.max_displacement, max_displacement(v));
        if (t.max_displacement > failure_displacement_) {
          t.result = TrialResult::Failed;
          t.reason = fmt::format("moved {:.3g} m (> {:.3g} m) at t = {:.3g} s in stage '{}'", t.max_displacement,
                                 failure_displacement_, s.time(), sc_.stages[si].name);
          break;
        }
      }
    }
    t.max_displacement = std::max(t.max_displacement, max_displacement(v));
  } catch (const solver::InstabilityError& e) {
    t.result = TrialResult::Failed;
    t.max_displacement = max_displacement(v);
    t.reason = fmt::format("went unstable: {}", e.what());
  }
  t.unbalanced_ratio = unbalanced_force_ratio<D>(model_.nodes, s.damping_forces(), g_);
  t.broken_joints = broken_joints(s) - v.broken_settled;
  record(v, t, t0);
  return t;
}

// The state of a failed trial: displacement since the settled state and the broken joints.
template <int D>
void StabilityRunner<D>::write_mechanism(const Variant& v, double F) {
  const std::string suffix = v.name == "static" ? "" : "_" + v.name;
  std::vector<Vec> du(model_.nodes.size());
  for (std::size_t i = 0; i < du.size(); ++i) du[i] = model_.nodes.u[i] - v.u_settled[i];
  solver_->update_stress();
  io::VtuOptions vo;
  vo.time_s = F;  // the frame's "time" is the factor it failed at
  const fs::path path = out_ / fmt::format("mechanism{}.vtu", suffix);
  const io::FieldSet fields{io::vector_field("displacement_since_settled", "m", du)};
  if constexpr (D == 2) {
    io::write_triangles_vtu(path, model_.nodes, model_.triangles, model_.materials, fields, {}, vo);
    solver_->release_stress();
    if (model_.joints.size() > 0)
      io::write_cracks_vtu(out_ / fmt::format("mechanism_cracks{}.vtu", suffix), model_, F);
  } else {
    io::write_tetrahedra_vtu(path, model_.nodes, model_.tetrahedra, model_.materials, fields, {}, vo);
  }
}

template <int D>
double StabilityRunner<D>::bisect(Variant& v) {
  const bool dynamic = v.name == "dynamic";
  auto trial = [&](double F) { return dynamic ? dynamic_trial(v, F) : this->trial(v, F, watch_); };
  const std::string budget_hint =
      "raise stability.max_steps (the trial is still moving) or move the bounds away from the factor of safety";
  double lo = spec_.F_low, hi = spec_.F_high;
  const StabilityTrial at_lo = trial(lo);
  if (stopped()) return lo;
  if (at_lo.result == TrialResult::Failed)
    throw io::ScenarioError({spec_.where_bounds.describe(fmt::format(
        "the slope ({}) already fails at F_low = {} ({}): lower the bounds", v.name, lo, at_lo.reason))});
  if (at_lo.result == TrialResult::Undecided)
    throw io::ScenarioError({spec_.where_bounds.describe(
        fmt::format("the slope ({}) is undecided at F_low = {} ({}): {}", v.name, lo, at_lo.reason, budget_hint))});
  const StabilityTrial at_hi = trial(hi);
  if (stopped()) return lo;
  if (at_hi.stands())
    throw io::ScenarioError({spec_.where_bounds.describe(fmt::format(
        "the slope ({}) still stands at F_high = {}: raise the bounds", v.name, hi))});
  if (at_hi.result == TrialResult::Undecided)
    throw io::ScenarioError({spec_.where_bounds.describe(
        fmt::format("the slope ({}) is undecided at F_high = {} ({}): {}", v.name, hi, at_hi.reason, budget_hint))});
  StabilityBracket b;
  b.variant = v.name;
  b.failed = hi;
  while (hi - lo > spec_.tolerance * (1.0 + 1e-12) && !stopped()) {
    const double mid = 0.5 * (lo + hi);
    const StabilityTrial t = trial(mid);
    if (t.stands()) {
      lo = mid;
      continue;
    }
    hi = mid;  // an undecided trial bounds the bracket as a failed one would
    if (t.result == TrialResult::Failed) b.failed = mid;
  }
  b.stood = lo;
  for (const auto& t : trials_)
    if (t.variant == v.name && !t.budget_check && t.result == TrialResult::Undecided && t.F > lo &&
        (!b.failed || t.F < *b.failed))
      b.undecided.push_back(t.F);
  std::sort(b.undecided.begin(), b.undecided.end());
  log(fmt::format("[{}] factor of safety {:.4f} (stands at {:.4f}, fails at {}{})", v.name, lo, lo,
                  b.failed ? fmt::format("{:.4f}", *b.failed) : std::string("-"),
                  b.undecided.empty() ? std::string()
                                      : fmt::format("; undecided at {} between them: the factor of safety may be up to "
                                                    "the lowest F that failed",
                                                    b.undecided.size())));
  if (spec_.check_budget && !dynamic && !stopped()) check_budget(v, b);
  brackets_.push_back(b);
  return lo;
}

// The two trials that bracket the factor of safety again, watched twice as long before
// their motion is judged and with twice the budget: a verdict the longer watch does not
// keep says the window decided it, not the slope.
template <int D>
void StabilityRunner<D>::check_budget(Variant& v, StabilityBracket& b) {
  const Watch twice{2 * watch_.first_judgement, 2 * watch_.budget};
  const StabilityTrial a = trial(v, b.stood, twice, true);
  b.stood_held = a.stands();
  if (b.failed && !stopped()) {
    const StabilityTrial f = trial(v, *b.failed, twice, true);
    b.failed_held = f.result == TrialResult::Failed;
  }
  log(fmt::format("[{}] budget check (watched twice as long): F = {:.4f} {}{}", v.name, b.stood,
                  *b.stood_held ? "still stands" : "NO LONGER STANDS",
                  b.failed_held ? fmt::format(", F = {:.4f} {}", *b.failed, *b.failed_held ? "still fails" : "NO LONGER FAILS")
                                : std::string()));
}

template <int D>
void StabilityRunner<D>::write_summary(StabilityResult& r) {
  nlohmann::ordered_json s;
  s["dsdem_version"] = std::string(DSDEM_VERSION) + " (" + DSDEM_GIT_COMMIT + ")";
  s["scenario"] = sc_.file;
  s["title"] = sc_.title;
  if constexpr (D == 3) s["dimension"] = 3;
  s["factor_of_safety"] = r.factor_of_safety;
  if (r.factor_of_safety_pseudo_static) s["factor_of_safety_pseudo_static"] = *r.factor_of_safety_pseudo_static;
  if (r.factor_of_safety_dynamic) s["factor_of_safety_dynamic"] = *r.factor_of_safety_dynamic;
  nlohmann::ordered_json m;
  m["method"] = "strength reduction (docs/theory.md §9): c/F, tan(phi)/F" +
                std::string(spec_.keep_tension ? "" : ", ft/F") + " for joints, Mohr-Coulomb materials and contact "
                "friction; bisection on F";
  m["bounds"] = {spec_.F_low, spec_.F_high};
  m["tolerance"] = spec_.tolerance;
  m["equilibrium_ratio"] = spec_.equilibrium_ratio;
  m["failure_displacement_m"] = failure_displacement_;
  m["solver"] = "dynamic relaxation with local non-viscous damping (docs/theory.md §9)";
  m["local_damping"] = spec_.local_damping;
  if (spec_.damping_alpha)
    m["damping_alpha_per_s"] = *spec_.damping_alpha;
  else
    m["damping_alpha_per_s"] = "adaptive";
  m["period_s"] = period_;
  m["period_from"] = period_source_;
  m["window_steps"] = window_;
  m["first_judgement_steps"] = watch_.first_judgement;
  m["max_steps"] = watch_.budget;
  m["check_budget"] = spec_.check_budget;
  m["keep_tension"] = spec_.keep_tension;
  m["dynamic"] = spec_.dynamic;
  if (spec_.kh) m["kh"] = *spec_.kh;
  if (spec_.kv) m["kv"] = *spec_.kv;
  nlohmann::ordered_json mon = nlohmann::ordered_json::array();
  for (const auto& g : spec_.monitor) mon.push_back({{"name", g.name}, {"at_m", {g.at.x(), g.at.y()}}});
  m["monitor"] = mon;
  s["settings"] = m;
  nlohmann::ordered_json br = nlohmann::ordered_json::object();
  for (const auto& b : r.brackets) {
    nlohmann::ordered_json j;
    j["stood"] = b.stood;
    j["failed"] = b.failed ? nlohmann::ordered_json(*b.failed) : nlohmann::ordered_json(nullptr);
    j["undecided"] = b.undecided;
    j["decided"] = b.undecided.empty();
    if (b.stood_held) {
      nlohmann::ordered_json c;
      c["stood_held"] = *b.stood_held;
      if (b.failed_held) c["failed_held"] = *b.failed_held;
      j["budget_check"] = c;
    }
    br[b.variant] = j;
  }
  s["brackets"] = br;
  nlohmann::ordered_json tr = nlohmann::ordered_json::array();
  for (const auto& t : r.trials)
    tr.push_back({{"variant", t.variant},
                  {"F", t.F},
                  {"result", trial_result_name(t.result)},
                  {"budget_check", t.budget_check},
                  {"reason", t.reason},
                  {"note", t.note},
                  {"max_displacement_m", t.max_displacement},
                  {"broken_joints", t.broken_joints},
                  {"steps", t.steps},
                  {"unbalanced_ratio", t.unbalanced_ratio},
                  {"wall_time_s", t.wall_time_s}});
  s["trials"] = tr;
  s["trial_histories"] = "trials.csv";
  s["threads"] = threads_;
  s["wall_time_s"] = r.wall_time_s;
  r.summary_path = (out_ / "summary.json").string();
  io::write_json_file(out_ / "summary.json", s);
}

// trials.csv: each static and pseudo-static trial's checks, for the convergence plot.
template <int D>
void StabilityRunner<D>::write_trial_histories() const {
  std::string text = "trial,variant,F,result,budget_check,step,unbalanced_ratio,displacement_m\n";
  for (std::size_t k = 0; k < trials_.size(); ++k) {
    const auto& t = trials_[k];
    for (const auto& h : t.history)
      text += fmt::format("{},{},{:.6g},{},{},{},{:.6e},{:.6e}\n", k + 1, t.variant, t.F, trial_result_name(t.result),
                          t.budget_check ? 1 : 0, h.step, h.ratio, h.displacement);
  }
  io::write_file_atomically(out_ / "trials.csv", text);
}

template <int D>
StabilityResult StabilityRunner<D>::run() {
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
  if constexpr (D == 2)
    log(fmt::format("dsdem {} ({}), {} threads: factor of safety of {} ({} nodes, {} triangles, {} joints)",
                    DSDEM_VERSION, DSDEM_GIT_COMMIT, threads_, sc_.file, model_.nodes.size(), model_.triangles.size(),
                    model_.joints.size()));
  else
    log(fmt::format("dsdem {} ({}), {} threads: factor of safety of {} (3D: {} nodes, {} tetrahedra)", DSDEM_VERSION,
                    DSDEM_GIT_COMMIT, threads_, sc_.file, model_.nodes.size(), model_.tetrahedra.size()));
  StabilityResult r;
  Variant stat{"static", scenario_gravity(), {}, {}, 0, 0.0};
  settle_static(stat);
  log(fmt::format("trials: local damping {}{}; equilibrium at unbalanced force ratio < {:.1e}; failure past {:.3g} m "
                  "of displacement{} or motion that keeps on over a doubling of the trial, judged from {} steps "
                  "(8 windows of {} steps: the period {:.3g} s from {}, dt {:.3g} s) on; at most {} steps",
                  spec_.local_damping,
                  spec_.damping_alpha ? fmt::format(" and mass damping {} 1/s", *spec_.damping_alpha)
                                      : std::string(" and adaptive mass damping"),
                  spec_.equilibrium_ratio, failure_displacement_,
                  monitors_.empty() ? " (any node)" : " (monitored points)", watch_.first_judgement, window_, period_,
                  period_source_, solver_->dt(), watch_.budget));
  if (!stopped()) r.factor_of_safety = bisect(stat);
  if ((spec_.kh || spec_.kv) && !stopped()) {
    Vec k = Vec::Zero();  // kh along x, kv up
    k.x() = spec_.kh.value_or(0.0);
    k[D - 1] = spec_.kv.value_or(0.0);
    const Vec g = scenario_gravity() + g_ * k;
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
  r.brackets = brackets_;
  r.wall_time_s = seconds_since(wall_start_);
  if (stopped()) {
    r.stopped_by_signal = static_cast<int>(*options_.stop_signal);
    log(fmt::format("stopped by {}: no factor of safety", signal_name(r.stopped_by_signal)));
    return r;
  }
  write_summary(r);
  write_trial_histories();
  log(fmt::format("done in {}: factor of safety {:.4f}{}", human_time(r.wall_time_s), r.factor_of_safety,
                  r.factor_of_safety_pseudo_static
                      ? fmt::format(", pseudo-static {:.4f}", *r.factor_of_safety_pseudo_static)
                      : std::string()) +
      (r.factor_of_safety_dynamic ? fmt::format(", dynamic {:.4f}", *r.factor_of_safety_dynamic) : std::string()));
  return r;
}

}  // namespace

StabilityResult find_factor_of_safety(PreparedRun& prepared, const StabilityOptions& options) {
  return StabilityRunner<2>(prepared, options).run();
}

StabilityResult find_factor_of_safety(PreparedRun3& prepared, const StabilityOptions& options) {
  return StabilityRunner<3>(prepared, options).run();
}

}  // namespace dsdem::run
