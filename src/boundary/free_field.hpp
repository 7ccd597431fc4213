#pragma once
// Free field of a 1D column for vertically incident SV and P waves and the equivalent
// nodal forces that feed it through a viscous-spring boundary (docs/theory.md §5):
//   u_ff(y,t) = u0(t - y/c) + u0(t - (2H - y)/c),   F = K u_ff + C v_ff + A sigma_ff.n
// y is the height of the node above the column base, H the height of the column (base
// to the free surface above that boundary point). Pure per-node kernels, no allocation.
#include "boundary/viscous_spring.hpp"
#include "model/types.hpp"
#include "seismic/accelerogram.hpp"

namespace dsdem::boundary {

// SV: horizontal motion (x), travels at cs. P: vertical motion (y), travels at cp.
enum class IncidentWave { SV, P };

// The incident wave u0 is half the design (outcrop) motion for a uniform half-space.
constexpr double kIncidentFraction = 0.5;

// The incident motion: u0(t) = scale * record(t), with record(t) interpolated linearly
// and zero before t = 0 (seismic::Accelerogram::at). Holds a pointer: the record must
// outlive it.
struct IncidentMotion {
  const seismic::Accelerogram* record = nullptr;
  double scale = kIncidentFraction;
  seismic::MotionSample at(double t) const {
    seismic::MotionSample s = record->at(t);
    return {scale * s.a, scale * s.v, scale * s.d};
  }
};

// Displacement, velocity (m, m/s) and stress (xx, yy, xy; Pa, tension positive) of the
// free field at one point. Free fields of an SV and a P wave add (linear elasticity).
struct FreeFieldState {
  Vec2 u = Vec2::Zero();
  Vec2 v = Vec2::Zero();
  Vec3 stress = Vec3::Zero();
  FreeFieldState& operator+=(const FreeFieldState& o) {
    u += o.u;
    v += o.v;
    stress += o.stress;
    return *this;
  }
};

// Free field at height y in [0, H] at time t. SV: u_x as above, sigma_xy =
// rho cs (v0(t - (2H - y)/cs) - v0(t - y/cs)). P: u_y likewise with cp, sigma_yy =
// rho cp (...), sigma_xx = lambda/cp (...). Throws std::runtime_error on H <= 0 or y
// outside [0, H] (beyond a 1e-9 H rounding allowance).
FreeFieldState free_field_column(IncidentWave wave, const IncidentMotion& motion, const ElasticMedium& medium,
                                 double y, double H, double t);

// Equivalent nodal input force F = K u_ff + C v_ff + A sigma_ff.n for a boundary node
// with coefficients c (viscous_spring_coefficients with the same A), unit outward
// normal n and tributary area A. The node's total boundary force is then
// F + viscous_spring_force(c, n, u, v).
inline Vec2 free_field_input_force(const ViscousSpringCoefficients& c, double A, const Vec2& n,
                                   const FreeFieldState& ff) {
  const Vec2 t(-n.y(), n.x());
  const double fn = c.kn * ff.u.dot(n) + c.cn * ff.v.dot(n);
  const double ft = c.kt * ff.u.dot(t) + c.ct * ff.v.dot(t);
  const Vec3& s = ff.stress;
  const Vec2 traction(s[0] * n.x() + s[2] * n.y(), s[2] * n.x() + s[1] * n.y());
  return fn * n + ft * t + A * traction;
}

// The free field of a 3D model: a vertical column along z, SV waves moving in x or y, P
// waves in z (docs/theory.md §5, §14). Stress Voigt (xx, yy, zz, yz, xz, xy).
struct FreeFieldState3 {
  Vec3 u = Vec3::Zero();
  Vec3 v = Vec3::Zero();
  Vec6 stress = Vec6::Zero();
  FreeFieldState3& operator+=(const FreeFieldState3& o) {
    u += o.u;
    v += o.v;
    stress += o.stress;
    return *this;
  }
};

// The column's field at height z in [0, H] at time t: free_field_column's, its motion along
// x (direction 0) or y (1) for SV and along z for P, with sigma_xz or sigma_yz for SV and
// sigma_zz, sigma_xx = sigma_yy for P. Throws as free_field_column, and
// std::invalid_argument for an SV direction other than 0 or 1.
FreeFieldState3 free_field_column_3d(IncidentWave wave, int direction, const IncidentMotion& motion,
                                     const ElasticMedium& medium, double z, double H, double t);

// F = K u_ff + C v_ff + A sigma_ff.n in 3D, split as viscous_spring_force (3D) splits.
inline Vec3 free_field_input_force(const ViscousSpringCoefficients& c, double A, const Vec3& n,
                                   const FreeFieldState3& ff) {
  const double un = ff.u.dot(n), vn = ff.v.dot(n);
  const Vec6& s = ff.stress;
  const Vec3 traction(s[0] * n.x() + s[5] * n.y() + s[4] * n.z(), s[5] * n.x() + s[1] * n.y() + s[3] * n.z(),
                      s[4] * n.x() + s[3] * n.y() + s[2] * n.z());
  return (c.kn * un + c.cn * vn) * n + c.kt * (ff.u - un * n) + c.ct * (ff.v - vn * n) + A * traction;
}

}  // namespace dsdem::boundary
