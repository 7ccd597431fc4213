#pragma once
// How a strength-reduction trial is judged from its own history (docs/theory.md §9): pure
// functions of the samples a trial records, so that the budget only bounds the cost.
//
//   stands     the unbalanced force ratio falls below the equilibrium ratio (FLAC's 1e-5);
//   fails      a monitored point moves failure_displacement, or the monitored mass keeps
//              moving: at a judgement step n it moved more than 1e-4 failure_displacement
//              over (n/2, n], and its velocity over (n/2, n] is 1.25 times that over
//              (n/4, n/2] or more (accelerating), or at least 0.9 times it with its mean
//              unbalanced force ratio at least 0.9 times too (creeping steadily);
//   undecided  neither within the budget.
// Judgement steps are 8 W, 16 W, 32 W, ... for the observation window W (about the slope's
// fundamental period in steps): a standing slope's motion decays over a doubling of its
// history, a failing one's does not, whatever the damping that slows it.
#include <cstddef>
#include <span>
#include <type_traits>
#include <vector>

#include "model/model.hpp"

namespace dsdem::run {

// One check of a trial: its step, unbalanced force ratio and monitored displacement (m).
struct TrialSample {
  long step = 0;
  double ratio = 0.0;
  double displacement = 0.0;
};

// The motion of the monitored mass over the two last quarters of a trial's history.
struct MotionTrend {
  double velocity_early = 0.0;  // m per step over (n/4, n/2]
  double velocity_late = 0.0;   // m per step over (n/2, n]
  double ratio_early = 0.0;     // mean unbalanced force ratio over (n/4, n/2]
  double ratio_late = 0.0;      // the same over (n/2, n]
  double moved_late = 0.0;      // m over (n/2, n]
  bool keeps_moving = false;
};

// The trend at the last sample's step n, from samples taken every `every` steps from step
// `every` on (samples[k].step == (k + 1) every); n must be a multiple of 4 every.
// `floor` (m): the least motion over (n/2, n] that counts as moving.
MotionTrend motion_trend(std::span<const TrialSample> samples, long every, double floor);

// Rayleigh's quotient of a displacement increment du whose forces changed by df (N):
// omega^2 = -du.df / du.M du, 1/s^2 (Underwood 1983: the frequency of the mode the motion
// shows). Negative where the forces grow along the motion (a softening slope); zero for no
// motion.
// Any dimension (plane and 3D nodes).
template <int D>
double rayleigh_omega2(const NodeArrays<D>& nodes, std::type_identity_t<std::span<const VecD<D>>> du,
                       std::type_identity_t<std::span<const VecD<D>>> df);

// The slope's fundamental period (s) by Rayleigh's quotient on its settled displacement
// under gravity (the static deflection shape): omega^2 = sum m g.u / sum m |u|^2. Zero when
// the displacement holds no such shape (no gravity work, e.g. a model that starts from
// its initial stresses).
template <int D>
double rayleigh_period(const NodeArrays<D>& nodes, std::type_identity_t<std::span<const VecD<D>>> displacement,
                       const std::type_identity_t<VecD<D>>& gravity);

// The fundamental period of a soil column of height H and shear-wave speed vs: 4 H / vs.
inline double shear_column_period(double height, double vs) { return vs > 0.0 ? 4.0 * height / vs : 0.0; }

}  // namespace dsdem::run
