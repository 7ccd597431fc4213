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

FreeFieldState3 free_field_column_3d(IncidentWave wave, int direction, const IncidentMotion& motion,
                                     const ElasticMedium& medium, double z, double H, double t) {
  if (wave == IncidentWave::SV && direction != 0 && direction != 1)
    throw std::invalid_argument(fmt::format("free field: an SV wave moves along x (0) or y (1), not {}", direction));
  // The column's 1D field with the height along the 2D column's y.
  const FreeFieldState f = free_field_column(wave, motion, medium, z, H, t);
  FreeFieldState3 ff;
  if (wave == IncidentWave::SV) {
    ff.u[direction] = f.u.x();
    ff.v[direction] = f.v.x();
    ff.stress[direction == 0 ? 4 : 3] = f.stress[2];  // sigma_xz or sigma_yz
  } else {
    ff.u.z() = f.u.y();
    ff.v.z() = f.v.y();
    ff.stress[0] = f.stress[0];
    ff.stress[1] = f.stress[0];
    ff.stress[2] = f.stress[1];
  }
  return ff;
}

}  // namespace dsdem::boundary
