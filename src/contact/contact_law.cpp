#include "contact/contact_law.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace dsdem::contact {

double damping_ratio_linear(double e) {
  if (!(e > 0.0 && e <= 1.0)) throw std::invalid_argument("restitution must be in (0, 1]");
  const double le = std::log(e);
  return -le / std::sqrt(kPi * kPi + le * le);
}

double restitution_no_tension(double zeta) {
  // Unit mass and stiffness (e depends on zeta only). Overlap from delta(0)=0,
  // delta'(0)=1; the contact ends at t_c where delta + 2 zeta delta' = 0, and
  // e = -delta'(t_c).
  if (zeta <= 0.0) return 1.0;
  if (std::abs(zeta - 1.0) < 1e-9) zeta = 1.0 + 1e-9;  // critical: use the limit
  if (zeta < 1.0) {
    const double w = std::sqrt(1.0 - zeta * zeta);
    // tan(w t_c) = -2 zeta w / (1 - 2 zeta^2), with w t_c in (0, pi).
    const double wt = kPi - std::atan2(2.0 * zeta * w, 1.0 - 2.0 * zeta * zeta);
    const double t = wt / w;
    return std::exp(-zeta * t) * std::abs(std::cos(wt) - zeta / w * std::sin(wt));
  }
  // Overdamped: roots l1 > l2 of l^2 + 2 zeta l + 1; delta = (e^{l1 t} - e^{l2 t})/(l1 - l2);
  // the force vanishes when l1^2 e^{l1 t} = l2^2 e^{l2 t}.
  const double s = std::sqrt(zeta * zeta - 1.0);
  const double l1 = -zeta + s;
  const double l2 = -zeta - s;
  const double t = 2.0 * std::log(l2 / l1) / (l1 - l2);
  return -(l1 * std::exp(l1 * t) - l2 * std::exp(l2 * t)) / (l1 - l2);
}

double damping_ratio_from_restitution(double e) {
  if (!(e > 0.0 && e <= 1.0)) {
    throw std::invalid_argument("contact restitution must be in (0, 1], got " + std::to_string(e));
  }
  if (e == 1.0) return 0.0;
  double lo = 0.0, hi = 1.0;
  while (restitution_no_tension(hi) > e) hi *= 2.0;  // e(zeta) -> 0 as zeta -> inf
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (restitution_no_tension(mid) > e ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

ContactLawParams law_params(const ContactProperties& p) {
  return {p.kn, p.ks, p.mu, damping_ratio_from_restitution(p.restitution)};
}

Vec2 rotate_into_frame(const Vec2& ft_prev, const Vec2& normal) {
  const Vec2 t(-normal.y(), normal.x());
  const double mag = ft_prev.norm();
  return (ft_prev.dot(t) >= 0.0 ? mag : -mag) * t;
}

ContactLawResult contact_law(double overlap, const Vec2& normal, const Vec2& v_rel, double dt,
                             const Vec2& ft_prev, double m_eff, const ContactLawParams& p) {
  ContactLawResult r;
  if (!(overlap > 0.0)) return r;

  const double vn = v_rel.dot(normal);  // > 0: separating
  const double c = (p.damping_ratio > 0.0 && m_eff > 0.0 && std::isfinite(m_eff))
                       ? 2.0 * p.damping_ratio * std::sqrt(m_eff * p.kn)
                       : 0.0;
  const double fe = p.kn * overlap;
  r.fn = std::max(0.0, fe - c * vn);  // no tensile normal force
  // Work of the dashpot part actually applied, at the half-step vn: -(fn - fe) * vn * dt >= 0.
  r.dashpot_force = r.fn - fe;
  r.damping_dissipation = -r.dashpot_force * vn * dt;

  const Vec2 vt = v_rel - vn * normal;
  const Vec2 prev = rotate_into_frame(ft_prev, normal);
  const Vec2 trial = prev - (p.ks * dt) * vt;
  const double cap = p.mu * r.fn;
  const double trial_mag = trial.norm();
  if (trial_mag > cap) {
    r.sliding = true;
    r.ft = trial_mag > 0.0 ? Vec2(trial * (cap / trial_mag)) : Vec2::Zero();
    // Heat = work of the tangential force over the slip of the step (trapezoidal, with
    // the force actually applied, not the trial one) minus the change of the stored
    // spring energy. Steady sliding gives exactly mu*Fn*slip; a stick step gives 0.
    // (The trial-state formula (trial^2 - cap^2)/(2 ks) adds ks*slip^2/2 per step, which
    // is no work of any force and breaks the energy balance of run-out runs.) It is
    // negative on a step where the force swings across zero to a smaller cap: kept, so
    // the ledger books the work velocity Verlet applies (docs/theory.md §7).
    if (p.ks > 0.0) {
      const double work = 0.5 * (prev + r.ft).dot(trial - prev) / p.ks;
      const double d_elastic = 0.5 * (r.ft.squaredNorm() - prev.squaredNorm()) / p.ks;
      r.friction_dissipation = work - d_elastic;
    }
  } else {
    r.ft = trial;
  }
  r.force = r.fn * normal + r.ft;
  r.elastic_energy = 0.5 * p.kn * overlap * overlap +
                     (p.ks > 0.0 ? 0.5 * r.ft.squaredNorm() / p.ks : 0.0);
  return r;
}

}  // namespace dsdem::contact
