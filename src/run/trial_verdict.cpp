#include "run/trial_verdict.hpp"

#include <cmath>
#include <numbers>

namespace dsdem::run {

namespace {
constexpr double kAccelerating = 1.25;  // velocity ratio over the doubling
constexpr double kSteady = 0.9;         // velocity and force ratios of a steady creep
}  // namespace

MotionTrend motion_trend(std::span<const TrialSample> samples, long every, double floor) {
  MotionTrend t;
  const std::size_t n_idx = samples.size();  // samples[k] is step (k + 1) every
  if (n_idx < 4 || n_idx % 4 != 0 || every <= 0) return t;
  const std::size_t half = n_idx / 2, quarter = n_idx / 4;
  const double n = static_cast<double>(n_idx) * static_cast<double>(every);
  const double d_n = samples[n_idx - 1].displacement;
  const double d_half = samples[half - 1].displacement;
  const double d_quarter = samples[quarter - 1].displacement;
  t.moved_late = d_n - d_half;
  t.velocity_late = t.moved_late / (0.5 * n);
  t.velocity_early = (d_half - d_quarter) / (0.25 * n);
  double early = 0.0, late = 0.0;
  for (std::size_t k = quarter; k < half; ++k) early += samples[k].ratio;
  for (std::size_t k = half; k < n_idx; ++k) late += samples[k].ratio;
  t.ratio_early = early / static_cast<double>(half - quarter);
  t.ratio_late = late / static_cast<double>(n_idx - half);
  // Accelerating whatever its unbalanced force does, or creeping steadily with the force
  // that drives it undiminished (a terminal velocity under heavy mass damping).
  const bool accelerating = t.velocity_late >= kAccelerating * t.velocity_early;
  const bool creeping = t.velocity_late >= kSteady * t.velocity_early && t.ratio_late >= kSteady * t.ratio_early;
  // A mass that came back over (n/4, n/2] (its displacement fell) is swinging, not failing.
  t.keeps_moving = t.moved_late > floor && t.velocity_early > 0.0 && (accelerating || creeping);
  return t;
}

template <int D>
double rayleigh_omega2(const NodeArrays<D>& nodes, std::type_identity_t<std::span<const VecD<D>>> du,
                       std::type_identity_t<std::span<const VecD<D>>> df) {
  double work = 0.0, inertia = 0.0;
  for (std::size_t i = 0; i < du.size() && i < df.size() && i < nodes.size(); ++i) {
    if (!(nodes.m[i] > 0.0)) continue;
    work -= du[i].dot(df[i]);
    inertia += nodes.m[i] * du[i].squaredNorm();
  }
  return inertia > 0.0 ? work / inertia : 0.0;
}

template <int D>
double rayleigh_period(const NodeArrays<D>& nodes, std::type_identity_t<std::span<const VecD<D>>> displacement,
                       const std::type_identity_t<VecD<D>>& gravity) {
  double work = 0.0, inertia = 0.0;
  for (std::size_t i = 0; i < displacement.size() && i < nodes.size(); ++i) {
    if (!(nodes.m[i] > 0.0)) continue;
    work += nodes.m[i] * gravity.dot(displacement[i]);
    inertia += nodes.m[i] * displacement[i].squaredNorm();
  }
  if (!(work > 0.0) || !(inertia > 0.0)) return 0.0;
  return 2.0 * std::numbers::pi * std::sqrt(inertia / work);
}

template double rayleigh_omega2<2>(const NodeArrays<2>&, std::span<const Vec2>, std::span<const Vec2>);
template double rayleigh_omega2<3>(const NodeArrays<3>&, std::span<const Vec3>, std::span<const Vec3>);
template double rayleigh_period<2>(const NodeArrays<2>&, std::span<const Vec2>, const Vec2&);
template double rayleigh_period<3>(const NodeArrays<3>&, std::span<const Vec3>, const Vec3&);

}  // namespace dsdem::run
