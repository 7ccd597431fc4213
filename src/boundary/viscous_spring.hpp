#pragma once
// Viscous-spring artificial boundary (docs/theory.md §5, paper §1.2 eqs. 16-17; Deeks &
// Randolph 1994; 2D constants of Liu Jingbo & Lu 1998). Pure per-node kernels: the
// solver calls them for each boundary node, nothing is allocated.
#include "model/model.hpp"
#include "model/types.hpp"

namespace dsdem::boundary {

// 2D correction factors of the spring stiffness: normal aN, tangential aT (the paper's
// Kb = G/(2 rb) is the tangential one).
constexpr double kAlphaNormal = 1.0;
constexpr double kAlphaTangential = 0.5;
// 3D correction factors (Liu Jingbo et al. 2006): aN = 4/3, aT = 2/3.
constexpr double kAlphaNormal3D = 4.0 / 3.0;
constexpr double kAlphaTangential3D = 2.0 / 3.0;

// Elastic medium outside the boundary (plane strain moduli).
struct ElasticMedium {
  double rho = 0.0;     // kg/m^3
  double G = 0.0;       // shear modulus, Pa
  double lambda = 0.0;  // Lame's first parameter, Pa
  double cp() const;    // sqrt((lambda + 2G)/rho), m/s
  double cs() const;    // sqrt(G/rho), m/s
};
// From a model material (uses its lambda(), mu(), rho). Throws on rho <= 0 or G <= 0.
ElasticMedium medium_from_material(const Material& m);

// Nodal coefficients of one boundary node with tributary area A (tributary length x
// thickness; per unit thickness in plane strain): springs kn = A aN G/R, kt = A aT G/R
// (N/m) and dashpots cn = A rho cp, ct = A rho cs (N s/m).
struct ViscousSpringCoefficients {
  double kn = 0.0, kt = 0.0;
  double cn = 0.0, ct = 0.0;
};
// R > 0 is the distance from the scattering source (the slope) to the boundary node.
// Throws std::runtime_error on A < 0, R <= 0 or a bad medium.
ViscousSpringCoefficients viscous_spring_coefficients(double A, const ElasticMedium& medium, double R,
                                                      double alpha_n = kAlphaNormal,
                                                      double alpha_t = kAlphaTangential);

// Distance from a scattering centre to a boundary node, the usual choice of R.
inline double scattering_distance(const Vec2& node, const Vec2& centre) { return (node - centre).norm(); }

// Force of the springs and dashpots on the node: -(K u + C v), split along the unit
// outward normal n and the tangent. u, v: the node's displacement and velocity
// measured from the state in which the boundary was attached (e.g. the end of the
// gravity stage), so that the static reactions, kept as loads, are not counted twice.
inline Vec2 viscous_spring_force(const ViscousSpringCoefficients& c, const Vec2& n, const Vec2& u, const Vec2& v) {
  const Vec2 t(-n.y(), n.x());
  const double fn = -(c.kn * u.dot(n) + c.cn * v.dot(n));
  const double ft = -(c.kt * u.dot(t) + c.ct * v.dot(t));
  return fn * n + ft * t;
}

// The same in 3D: the tangential part is the motion's projection on the boundary's plane.
// (Its own name: Eigen expressions convert to either vector, so overloads would be ambiguous.)
inline Vec3 viscous_spring_force_3d(const ViscousSpringCoefficients& c, const Vec3& n, const Vec3& u, const Vec3& v) {
  const double un = u.dot(n), vn = v.dot(n);
  return -(c.kn * un + c.cn * vn) * n - c.kt * (u - un * n) - c.ct * (v - vn * n);
}

}  // namespace dsdem::boundary
