#include "joint/cohesive_law.hpp"

#include <algorithm>
#include <cmath>

namespace dsdem {

JointLawConstants law_constants(const JointProperties& p) {
  JointLawConstants k;
  k.kn = p.kn;
  k.ks = p.ks;
  k.ft = p.ft;
  k.c = p.c;
  k.GII = p.GII;
  k.tan_phi = std::tan(p.phi);
  k.wn = 2.0 * p.GI / p.ft;
  k.tiny = 1e-12 * (p.c + p.ft);
  k.scale_ks = p.penalty_h > 0.0 && !p.ks_given;
  return k;
}

double mixed_mode_damage(double en, double es, double damage_before) {
  // hypot(x, 0) = |x| exactly (C Annex F): skip the libm call in the common cases.
  if (en == 0.0) return es;
  if (es == 0.0) return en;
  // Only e above damage_before raises the damage (eq. 9 keeps the maximum). hypot is
  // within an ulp or so of sqrt(en^2 + es^2); its square below damage_before^2 by a
  // margin far above that gives a value whose max() with damage_before is damage_before:
  // return that, not the libm call (costly in the joint phase's hot path). The floor on
  // damage_before keeps en^2 + es^2 clear of underflow. NaN takes hypot.
  if (damage_before >= 1e-100 && en * en + es * es <= damage_before * damage_before * (1.0 - 1e-9))
    return damage_before;
  return std::hypot(en, es);
}

// The general branch of cohesive_update (past the elastic limits, or damaged).
CohesivePoint cohesive_update_general(double dn, double ds, const JointLawConstants& p, JointPointState& st,
                                      bool damage_enabled) {
  CohesivePoint r;
  const double s = std::abs(ds);
  const double tan_phi = p.tan_phi;
  const double wn = p.wn;  // mode I softening length: area = GI
  const JointPointState old = st;
  const LastTractions old_t = last_tractions(old, p);  // the last evaluation's sn and shear secant
  const double wt = p.ft / p.kn;  // opening at the tensile strength (eq. 6)
  if (damage_enabled) {
    st.dn_max = branchless_max(old.dn_max, dn);
    st.s_max = branchless_max(old.s_max, s);
  }

  // Normal traction of the normal law alone (eq. 6, secant unloading): enters eq. 8.
  const double sn_normal = normal_law_traction(dn, st.dn_max, wt, p);
  // Eq. 8 with the tension cut-off; fr is the residual friction (compression only).
  // The floor only guards division by zero for properties validate() rejects.
  const double tiny = p.tiny;
  const double fs = branchless_max(p.c - branchless_min(sn_normal, p.ft) * tan_phi, tiny);
  const double fr = branchless_max(-sn_normal, 0.0) * tan_phi;
  const double ws = fs / p.ks;
  const double wsII = 2.0 * p.GII / branchless_max(fs - fr, tiny);

  // Eq. 9 on the largest opening and slip reached; damage never decreases.
  // Intact joints sit below both limits: the numerators are +0 and the quotients +0
  // without dividing.
  const double past_n = branchless_max(st.dn_max - wt, 0.0), past_s = branchless_max(st.s_max - ws, 0.0);
  const double en = past_n != 0.0 ? past_n / wn : past_n;
  const double es = past_s != 0.0 ? past_s / wsII : past_s;
  if (damage_enabled) st.damage = branchless_max(old.damage, branchless_min(1.0, mixed_mode_damage(en, es, old.damage)));
  const double D = st.damage;

  // Secant tractions: the envelope value at the largest separation, scaled back
  // linearly toward the origin (eqs. 6-7 on loading, secant on unloading).
  r.sn = dn <= 0.0 ? p.kn * dn : p.ft * (1.0 - D) * dn / branchless_max(st.dn_max, wt);
  // The shear secant stiffness depends on the normal traction (fs, fr) once the slip
  // has passed ws. A secant that stiffens under compression at a fixed slip would hand
  // out elastic energy that was never stored (ks_sec * ds^2 / 2 grows without work):
  // normal oscillations then pump energy into the joint without bound. So the shear
  // traction moves incrementally with the current secant slope and is kept between 0
  // and the secant value: it never rises without slip (stiffening releases nothing),
  // and drops onto the secant when the secant softens (dissipated, like friction).
  // Whenever the secant stiffness stays constant along a path this is the secant law.
  // (last_tractions() recomputes sn and k_sec from the stored history: keep alike.)
  const double tau_env = fr + (fs - fr) * (1.0 - D);
  const double k_sec = tau_env / branchless_max(st.s_max, ws);
  const double ss_secant = k_sec * ds;
  const double ss_trial = old.ss + k_sec * (ds - old.ds);
  r.ss = branchless_clamp(ss_trial, branchless_min(0.0, ss_secant), branchless_max(0.0, ss_secant));

  auto shear_energy = [](double ss, double k) { return k > 0.0 ? 0.5 * ss * ss / k : 0.0; };
  r.energy = 0.5 * r.sn * dn + shear_energy(r.ss, k_sec);
  // Dissipation = trapezoidal work - change of stored energy. The normal law has a kink
  // at dn = 0 (secant on one side, kn on the other, both through the origin): a step
  // across it is integrated in two pieces, so closing a crack dissipates nothing.
  const double e_old = 0.5 * old_t.sn * old.dn + shear_energy(old.ss, old_t.ks_sec);
  const double work_n = old.dn * dn < 0.0 ? 0.5 * (r.sn * dn - old_t.sn * old.dn)
                                          : 0.5 * (old_t.sn + r.sn) * (dn - old.dn);
  // A shear traction held at 0 after its trial value crossed zero within the step is
  // integrated in two pieces too (slope k_sec down to zero, then nothing).
  const bool held_at_zero = r.ss == 0.0 && old.ss != 0.0 && k_sec > 0.0 && (ss_trial > 0.0) != (old.ss > 0.0);
  const double work_s = held_at_zero ? 0.5 * old.ss * (-old.ss / k_sec) : 0.5 * (old.ss + r.ss) * (ds - old.ds);
  r.dissipation = work_n + work_s - (r.energy - e_old);
  r.failed = D >= 1.0;
  r.failed_now = r.failed && old.damage < 1.0;
  if (r.failed_now)
    r.mode = (en > 0.0 && es > 0.0) ? BreakMode::Mixed : (en > 0.0 ? BreakMode::Tension
                                                                    : BreakMode::Shear);
  st.dn = dn;
  st.ds = ds;
  st.ss = r.ss;
  r.fs = fs;
  r.ws = ws;
  r.wsII = wsII;
  return r;
}

CohesiveResponse cohesive_law(double dn, double ds, const JointProperties& p,
                              const JointPointState& old, bool damage_enabled) {
  return cohesive_law(dn, ds, law_constants(p), old, damage_enabled);
}

}  // namespace dsdem
