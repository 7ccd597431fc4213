#pragma once
// Factor of safety by strength reduction (docs/theory.md §9; Dawson, Roth & Drescher 1999):
// `dsdem stability`.
//
// 1. Settle: the scenario's static stages (those before its first earthquake stage), at
//    full strength with joints that may not fail, then the last of them run on until
//    equilibrium with the trials' quasi-static solver. Reducing before the slope has
//    settled would let the dynamic overshoot of switching gravity on break what statics
//    would not. The settled state is kept (a checkpoint in a scratch folder) and every
//    trial starts from it.
// 2. Trial at F: the settled state, strengths reduced by F (law/strength_reduction.hpp),
//    the last static stage's supports with failure allowed, solved by dynamic relaxation
//    with local non-viscous damping (stability.local_damping, 0.8) and adaptive mass
//    damping (stability.damping: a fixed alpha instead), not the scenario's Rayleigh
//    damping: docs/theory.md §9. Judged from its own
//    history (run/trial_verdict.hpp): stands at equilibrium (unbalanced force ratio <
//    stability.equilibrium_ratio), fails when a monitored point moves
//    stability.failure_displacement or the monitored mass keeps moving over a doubling of
//    the trial's history, undecided when the budget ends first. Checked every 50 steps.
// 3. Bisection on F between stability.bounds (the slope must stand at F_low and fail at
//    F_high) until F_high - F_low <= stability.tolerance; an undecided trial bounds the
//    bracket from above as a failed one would, and is reported as undecided. The factor of
//    safety is the largest F that stood; the bracket gives the lowest that failed.
//    stability.check_budget reruns the two bracketing trials watched twice as long.
// With kh or kv the same again with the pseudo-static body force |g| (kh, kv) m per node
// (kh > 0 toward +x, kv > 0 upward), settled from the static state at full strength.
//
// Output in OUT: summary.json (factor_of_safety, factor_of_safety_pseudo_static, the
// brackets, the trials), trials.csv (every trial's unbalanced force ratio and monitored
// displacement every 50 steps), mechanism[_pseudo_static].vtu and
// mechanism_cracks[...].vtu (the state at the lowest F that failed: displacement since
// the settled state, broken joints), stability.log.
#include <csignal>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "run/prepare.hpp"
#include "run/run3d.hpp"
#include "run/trial_verdict.hpp"

namespace dsdem::run {

struct StabilityOptions {
  std::string output_dir = "out";
  int threads = 0;     // 0 = all cores
  bool quiet = false;  // no progress lines on the terminal (stability.log still gets them)
  const volatile std::sig_atomic_t* stop_signal = nullptr;  // stop between steps (no result then)
};

enum class TrialResult { Equilibrium, Failed, Undecided, Survived };
const char* trial_result_name(TrialResult r);  // "equilibrium", "failed", "undecided", "survived"

struct StabilityTrial {
  std::string variant;  // "static", "pseudo_static" or "dynamic"
  double F = 0.0;
  TrialResult result = TrialResult::Undecided;
  bool stands() const { return result == TrialResult::Equilibrium || result == TrialResult::Survived; }
  bool budget_check = false;       // a rerun of stability.check_budget, watched twice as long
  std::string reason;              // how the trial ended
  std::string note;                // a standing trial that slid and stopped again, said so
  double max_displacement = 0.0;   // largest displacement since the settled state, m (monitored points or all nodes)
  long broken_joints = 0;          // joints broken in the trial
  long steps = 0;
  double unbalanced_ratio = 0.0;   // at the end of the trial
  double wall_time_s = 0.0;
  std::vector<TrialSample> history;  // every 50 steps (static and pseudo-static trials)
};

// What bisection left between the largest F that stood and the lowest that failed.
struct StabilityBracket {
  std::string variant;
  double stood = 0.0;                  // the factor of safety
  std::optional<double> failed;        // the lowest F that failed
  std::vector<double> undecided;       // F of undecided trials above `stood`, below `failed`
  // stability.check_budget: the bracketing trials' verdicts watched twice as long.
  std::optional<bool> stood_held, failed_held;
};

struct StabilityResult {
  double factor_of_safety = 0.0;
  std::optional<double> factor_of_safety_pseudo_static;
  std::optional<double> factor_of_safety_dynamic;  // stability.dynamic: the earthquake at strengths 1/F
  std::vector<StabilityTrial> trials;
  std::vector<StabilityBracket> brackets;  // one per variant bisected
  double wall_time_s = 0.0;
  std::string summary_path;
  int stopped_by_signal = 0;
};

// Runs the procedure above on a prepared scenario (its `stability` section; a default one
// when absent). Throws io::ScenarioError (file, line, key) for bounds that bracket nothing,
// a monitored point outside the mesh, a static stage missing or undamped trials.
StabilityResult find_factor_of_safety(PreparedRun& prepared, const StabilityOptions& options);
// The same on a 3D continuum (docs/theory.md §9, §14): every node watched (no monitored
// points yet), the mechanism as tetrahedra.
StabilityResult find_factor_of_safety(PreparedRun3& prepared, const StabilityOptions& options);

// The unbalanced-force ratio of the equilibrium test above at the model's current state:
// max_i |m_i a_i - f_damping,i| / mean_i (m_i |g|) over the nodes with mass, with the
// damping force each node took in the step (Solver::damping_forces(); empty: none).
double unbalanced_force_ratio(const Model& model, std::span<const Vec2> damping_forces, double gravity);
// The same over the nodes of either dimension.
template <int D>
double unbalanced_force_ratio(const NodeArrays<D>& nodes, std::type_identity_t<std::span<const VecD<D>>> damping_forces,
                              double gravity);

}  // namespace dsdem::run
