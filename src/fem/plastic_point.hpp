#pragma once
// What the plane-strain plastic laws of the bulk share (mohr_coulomb.hpp): one material
// point of the total Lagrangian CST (cst.hpp). Small strain and large rotation: the Green
// strain splits additively, E = Ee + Ep, and the second Piola-Kirchhoff stress is
// S = S0 + D (E - Ep). Plane strain: the total E_zz is 0, the out-of-plane plastic strain is
// state (Ee_zz = -Ep_zz) and S_zz is a stress of the return like the others. Voigt (xx, yy,
// xy) with engineering shear strain; tension positive.
#include <ostream>
#include <sstream>
#include <string>
#include <string_view>

#include "fem/bulk_kernel.hpp"
#include "fem/cst.hpp"
#include "law/laws.hpp"

namespace dsdem::fem {

// State of one element (one CST = one material point), five doubles in the order the laws
// declare them (law::plastic_state in law/laws.hpp).
struct PlasticState {
  double ep_xx = 0.0;  // plastic Green strain
  double ep_yy = 0.0;
  double ep_xy = 0.0;  // engineering shear 2 Ep_xy
  double ep_zz = 0.0;  // out-of-plane plastic strain; the elastic part is -ep_zz
  double plastic_work = 0.0;  // accumulated dissipation per unit reference volume, J/m^3
};
static_assert(sizeof(PlasticState) == 5 * sizeof(double), "the state is read as 5 doubles");

// The elastic trial of a point: its elastic strain Ee (xx, yy, 2xy) and Ee_zz, their
// stress D Ee (DEe, DEzz) and the trial S = S0 + D Ee, S_zz = S0_zz + (D Ee)_zz.
struct ElasticTrial {
  Vec3 Ee;
  double ezz;
  Vec3 DEe;
  double DEzz;
  Vec3 S;
  double S_zz;
};

[[gnu::always_inline]] inline ElasticTrial elastic_trial(const ElasticConstants& c, const Vec3& E, const Vec3& S0, double S0_zz,
                                  const PlasticState& start) {
  ElasticTrial t;
  t.Ee = Vec3(E[0] - start.ep_xx, E[1] - start.ep_yy, E[2] - start.ep_xy);
  t.ezz = -start.ep_zz;
  const double tr = t.Ee[0] + t.Ee[1] + t.ezz;
  t.DEe = Vec3(c.lambda * tr + 2.0 * c.mu * t.Ee[0], c.lambda * tr + 2.0 * c.mu * t.Ee[1], c.mu * t.Ee[2]);
  t.DEzz = c.lambda * tr + 2.0 * c.mu * t.ezz;
  t.S = S0 + t.DEe;
  t.S_zz = S0_zz + t.DEzz;
  return t;
}

// Stored energy S0 : Ee + Ee : D : Ee / 2 with DEe = S - S0 given as (xx, yy, xy, zz); the
// order of the sums is the elastic kernel's (triangle_internal_force) when Ee_zz = 0.
[[gnu::always_inline]] inline double stored_energy(const Vec3& S0, double S0_zz, const Vec3& Ee, double ezz, const Vec3& DEe, double DEzz) {
  return S0.dot(Ee) + S0_zz * ezz + 0.5 * (DEe[0] * Ee[0] + DEe[1] * Ee[1] + DEe[2] * Ee[2] + DEzz * ezz);
}
[[gnu::always_inline]] inline double stored_energy(const ElasticTrial& t, const Vec3& S0, double S0_zz) {
  return stored_energy(S0, S0_zz, t.Ee, t.ezz, t.DEe, t.DEzz);
}

// What a return needs of D^-1 = I / (2 mu) - lambda / (2 mu (3 lambda + 2 mu)) 1 x 1.
struct Compliance {
  double mu = 0.0;
  double inv_2mu = 0.0;  // 1 / (2 mu)
  double inv_vol = 0.0;  // lambda / (2 mu (3 lambda + 2 mu))
};
inline Compliance compliance(const ElasticConstants& e) {
  return {e.mu, 1.0 / (2.0 * e.mu), e.lambda / (2.0 * e.mu * (3.0 * e.lambda + 2.0 * e.mu))};
}

// The plastic strain of a return from the trial (S_trial, S_trial_zz) to (S, S_zz):
// dEp = D^-1 (S_trial - S), (xx, yy, 2xy, zz).
struct PlasticIncrement {
  double xx, yy, xy, zz;
};
inline PlasticIncrement plastic_increment(const Compliance& d, const Vec3& S_trial, double S_trial_zz, const Vec3& S,
                                          double S_zz) {
  const double dxx = S_trial[0] - S[0], dyy = S_trial[1] - S[1], dxy = S_trial[2] - S[2], dzz = S_trial_zz - S_zz;
  const double vol = d.inv_vol * (dxx + dyy + dzz);
  return {d.inv_2mu * dxx - vol, d.inv_2mu * dyy - vol, dxy / d.mu, d.inv_2mu * dzz - vol};
}
// end.ep = start.ep + dEp (`end` may be `start`).
inline void add_plastic_strain(const PlasticIncrement& dep, const PlasticState& start, PlasticState& end) {
  end.ep_xx = start.ep_xx + dep.xx;
  end.ep_yy = start.ep_yy + dep.yy;
  end.ep_xy = start.ep_xy + dep.xy;
  end.ep_zz = start.ep_zz + dep.zz;
}
// The plastic work S : dEp at the returned stress, per unit reference volume, clamped at 0
// (a return to an admissible S with psi <= phi dissipates, up to round-off).
inline double plastic_work(const PlasticIncrement& dep, const Vec3& S, double S_zz) {
  const double w = S[0] * dep.xx + S[1] * dep.yy + S[2] * dep.xy + S_zz * dep.zz;
  return w > 0.0 ? w : 0.0;
}

// The result of one update of a plastic law whose return regions are Region (Elastic = 0).
template <class Region>
struct PlasticResult {
  Vec3 S = Vec3::Zero();       // PK2 stress (xx, yy, xy), Pa
  double S_zz = 0.0;           // out-of-plane PK2 stress, Pa
  double dissipation = 0.0;    // S : dEp of this update at the returned stress, J/m^3, >= 0
  double strain_energy = 0.0;  // stored elastic energy S0 : Ee + Ee : D : Ee / 2, J/m^3
  Region region = Region::Elastic;
  bool yielded() const { return region != Region::Elastic; }
};

// The result of an update that stays inside the yield surface: the trial's stress and
// stored energy, and the state unchanged.
template <class Result>
[[gnu::always_inline]] inline Result elastic_result(const ElasticTrial& t, const Vec3& S0, double S0_zz,
                                                    const PlasticState& start, PlasticState& end) {
  end = start;
  Result out;
  out.S = t.S;
  out.S_zz = t.S_zz;
  out.strain_energy = stored_energy(t, S0, S0_zz);
  return out;
}

// The end of a return from the trial (S_trial, S_trial_zz) to (out.S, out.S_zz): the
// plastic strain dEp = D^-1 (S_trial - S), the update's dissipation dissipation(dEp) (the
// law's S : dEp), the plastic work and the stored energy Ee = E - Ep at the step's end
// (`end` may be `start`).
template <class Result, class Dissipation>
void finish_return(const Compliance& d, const Vec3& E, const Vec3& S0, double S0_zz, const Vec3& S_trial,
                   double S_trial_zz, const PlasticState& start, PlasticState& end, Result& out,
                   Dissipation&& dissipation) {
  const PlasticIncrement dep = plastic_increment(d, S_trial, S_trial_zz, out.S, out.S_zz);
  add_plastic_strain(dep, start, end);
  out.dissipation = dissipation(dep);
  end.plastic_work = start.plastic_work + out.dissipation;
  const Vec3 Ee(E[0] - end.ep_xx, E[1] - end.ep_yy, E[2] - end.ep_xy);
  out.strain_energy = stored_energy(S0, S0_zz, Ee, -end.ep_zz, out.S - S0, out.S_zz - S0_zz);
}

// The checks every plane-strain plastic law makes of its envelope (c, phi and psi in
// radians), each failed one a clause "...; " into err: c >= 0, phi in [0, 90) deg,
// psi in [0, phi], some strength, and plane strain.
void check_envelope(std::ostream& err, double c, double phi, double psi, bool plane_stress);
// A law's validation message from its clauses: "law: clause; clause", or empty.
std::string validation_text(std::string_view law, const std::ostringstream& err);

// The out-of-plane stress of a plane-strain elastic state reached from zero, for an
// initial stress that came from an elastic stage: S_zz = lambda / (2 (lambda + mu)) (S_xx + S_yy).
inline double plane_strain_sigma_zz(const Vec3& S, const ElasticConstants& c) {
  return c.lambda / (2.0 * (c.lambda + c.mu)) * (S[0] + S[1]);
}

// What the element loop (bulk_law.hpp) needs of a plane-strain plastic law with the update
// Update(model, E, S0, S0_zz, start, end), whose result has S, S_zz, strain_energy and
// dissipation: the plastic point's state, its plastic work the accumulated dissipation.
// A law's kernel adds its name and make().
template <class M, class Result,
          Result (*Update)(const M&, const Vec3&, const Vec3&, double, const PlasticState&, PlasticState&)>
struct PlasticKernel {
  using Model = M;
  using State = PlasticState;
  static constexpr int kDissipation = law::plastic_state::plastic_dissipation;
  [[gnu::always_inline]] static BulkResponse update(const Model& m, const Vec3& E, const Vec3& S0, double S0_zz,
                                                    const State& start, State& end) {
    const Result r = Update(m, E, S0, S0_zz, start, end);
    return {r.S, r.S_zz, r.strain_energy, r.dissipation};
  }
};

}  // namespace dsdem::fem
