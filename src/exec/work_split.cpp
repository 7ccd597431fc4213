#include "exec/work_split.hpp"

#include <cmath>

namespace dsdem::exec {

void balance_shares(std::span<double> share, std::span<const double> busy, double gain) {
  const std::size_t T = share.size();
  if (T < 2 || busy.size() != T) return;
  double rate_sum = 0.0;
  for (std::size_t t = 0; t < T; ++t) {
    if (!(busy[t] > 0.0) || !std::isfinite(busy[t]) || !(share[t] > 0.0)) return;
    rate_sum += share[t] / busy[t];
  }
  // The shares at the floor stay there; the others are scaled to make the sum 1.
  const double floor = 0.1 / static_cast<double>(T);
  double at_floor = 0.0, above = 0.0;
  for (std::size_t t = 0; t < T; ++t) {
    const double target = share[t] / busy[t] / rate_sum;
    share[t] += gain * (target - share[t]);
    if (share[t] <= floor) {
      share[t] = floor;
      at_floor += floor;
    } else {
      above += share[t];
    }
  }
  const double scale = (1.0 - at_floor) / above;
  for (double& s : share)
    if (s > floor) s *= scale;
}

void cumulative_shares(std::span<const double> share, std::vector<double>& cum) {
  const std::size_t T = share.size();
  cum.resize(T + 1);
  double sum = 0.0;
  for (std::size_t t = 0; t < T; ++t) {
    cum[t] = sum;
    sum += share[t];
  }
  for (std::size_t t = 0; t < T; ++t) cum[t] /= sum;
  cum[T] = 1.0;
}

}  // namespace dsdem::exec
