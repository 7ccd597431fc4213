#pragma once
// Factor of safety by strength reduction (DESIGN.md §12; Dawson, Roth & Drescher 1999):
// `dsdem stability`.
//
// 1. Settle: the scenario's static stages (those before its first earthquake stage), at
//    full strength with joints that may not fail, then the last of them run on until
//    equilibrium. Reducing before the slope has settled would let the dynamic overshoot of
//    switching gravity on break what statics would not. The settled state is kept (a
//    checkpoint in a scratch folder) and every trial starts from it.
// 2. Trial at F: the settled state, strengths reduced by F (law/strength_reduction.hpp),
//    the last static stage's supports with failure allowed and mass damping, run until
//      equilibrium: largest |m a + alpha m v| over the nodes (the unbalanced force, the
//        damping force left out) / mean |m g| < stability.equilibrium_ratio (1e-5); or
//      failure: a monitored point (every node without stability.monitor) has moved
//        stability.failure_displacement (default: the mean element size of zone A) from the settled
//        state, or no equilibrium within the step budget, or the run went unstable.
//    Checked every 50 steps.
// 3. Bisection on F between stability.bounds (the slope must stand at F_low and fail at
//    F_high) until F_high - F_low <= stability.tolerance; the factor of safety is F_low.
// With kh or kv the same again with the pseudo-static body force |g| (kh, kv) m per node
// (kh > 0 toward +x, kv > 0 upward), settled from the static state at full strength.
//
// Output in OUT: summary.json (factor_of_safety, factor_of_safety_pseudo_static, the
// trials), mechanism[_pseudo_static].vtu and mechanism_cracks[...].vtu (the state at the
// lowest F that failed: displacement since the settled state, broken joints), stability.log.
#include <csignal>
#include <optional>
#include <string>
#include <vector>

#include "run/prepare.hpp"

namespace dsdem::run {

struct StabilityOptions {
  std::string output_dir = "out";
  int threads = 0;     // 0 = all cores
  bool quiet = false;  // no progress lines on the terminal (stability.log still gets them)
  const volatile std::sig_atomic_t* stop_signal = nullptr;  // stop between steps (no result then)
};

struct StabilityTrial {
  std::string variant;  // "static" or "pseudo_static"
  double F = 0.0;
  bool stands = false;
  std::string reason;              // how the trial ended
  double max_displacement = 0.0;   // largest displacement since the settled state, m (monitored points or all nodes)
  long broken_joints = 0;          // joints broken in the trial
  long steps = 0;
  double unbalanced_ratio = 0.0;   // at the end of the trial
  double wall_time_s = 0.0;
};

struct StabilityResult {
  double factor_of_safety = 0.0;
  std::optional<double> factor_of_safety_pseudo_static;
  std::optional<double> factor_of_safety_dynamic;  // stability.dynamic: the earthquake at strengths 1/F
  std::vector<StabilityTrial> trials;
  double wall_time_s = 0.0;
  std::string summary_path;
  int stopped_by_signal = 0;
};

// Runs the procedure above on a prepared scenario (its `stability` section; a default one
// when absent). Throws io::ScenarioError (file, line, key) for bounds that bracket nothing,
// a monitored point outside the mesh, a static stage missing or undamped trials.
StabilityResult find_factor_of_safety(PreparedRun& prepared, const StabilityOptions& options);

// The unbalanced-force ratio of the equilibrium test above at the model's current state:
// max_i |m_i (a_i + alpha v_i)| / mean_i (m_i |g|) over the nodes with mass.
double unbalanced_force_ratio(const Model& model, double alpha, double gravity);

}  // namespace dsdem::run
