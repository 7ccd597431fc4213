#include "boundary/free_field.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace dsdem::boundary {

FreeFieldState free_field_column(IncidentWave wave, const IncidentMotion& motion, const ElasticMedium& medium,
                                 double y, double H, double t) {
  if (motion.record == nullptr) throw std::runtime_error("free field: no incident motion record");
  if (!(H > 0.0) || !std::isfinite(H))
    throw std::runtime_error(fmt::format("free field: column height H must be positive, got {}", H));
  const double tol = 1e-9 * H;
  if (!(y >= -tol && y <= H + tol))
    throw std::runtime_error(fmt::format("free field: height y = {} is outside the column [0, {}]", y, H));
  const double c = wave == IncidentWave::SV ? medium.cs() : medium.cp();
  // Upgoing incident wave and its reflection from the free surface (docs/theory.md §5).
  const seismic::MotionSample up = motion.at(t - y / c);
  const seismic::MotionSample down = motion.at(t - (2.0 * H - y) / c);
  const double u = up.d + down.d;
  const double v = up.v + down.v;
  // du/dy = (-v_up + v_down)/c; the surface (y = H) is traction-free.
  const double dudy = (down.v - up.v) / c;
  FreeFieldState ff;
  if (wave == IncidentWave::SV) {
    ff.u.x() = u;
    ff.v.x() = v;
    ff.stress[2] = medium.G * dudy;
  } else {
    ff.u.y() = u;
    ff.v.y() = v;
    ff.stress[0] = medium.lambda * dudy;
    ff.stress[1] = (medium.lambda + 2.0 * medium.G) * dudy;
  }
  return ff;
}

}  // namespace dsdem::boundary
