#pragma once
// Constitutive law of a cohesive joint at one integration point (paper eqs. 6-9,
// DESIGN.md §3). Pure function: separations + history in, tractions + history out.
//
// Envelope (tension positive, wt = ft/kn, wn = 2*GI/ft, ws = fs/ks):
//   normal  sn = kn*dn up to ft, then ft*(1 - D) with D the damage below;
//   shear   strength fs = c - sn*tan(phi) (tension cut-off at sn = ft, eq. 8),
//           ss = ks*ds up to fs, then fr + (fs - fr)*(1 - D) with the residual
//           friction fr = <-sn>*tan(phi) (compression only);
//   damage  D = max over the history of
//           min(1, sqrt( (<dn_max - wt>/wn)^2 + (<s_max - ws>/wsII)^2 )),
//           i.e. the left-hand side of the elliptical criterion eq. 9 evaluated on
//           the largest opening and slip reached; the point fails when D reaches 1.
// Pure mode I and pure mode II reproduce eqs. 6 and 7 exactly. One damage variable
// drives both tractions so that in mixed mode both reach zero (or the residual
// friction) exactly on the ellipse: the law stays continuous at failure instead of
// dropping a finite traction. Unloading follows the secant toward the origin;
// compression is always carried by kn*dn.
//
// Interpretations beyond the paper's text (all reduce to it in pure modes):
//  * fs uses the normal traction of the normal law alone (eq. 6 with secant
//    unloading), as the paper computes sn before eq. 8; this keeps the law explicit.
//  * Shear softens from fs to the residual friction fr (not to zero, then jumping to
//    fr), and wsII = 2*GII/(fs - fr): the softening area above the friction line is
//    GII. Without compression fr = 0 and this is DESIGN.md's wsII = 2*GII/fs.
//  * Once the slip has passed ws the shear secant ks_sec = (fr + (fs - fr)*(1 - D)) /
//    s_max depends on sn. The shear traction therefore follows the secant slope
//    incrementally and is kept between 0 and ks_sec*ds: it does not jump up when
//    compression stiffens the secant at a fixed slip (that would create energy, and
//    oscillating normal separations would pump it without bound), and it drops to
//    the secant when the secant softens. Stored shear energy is ss^2/(2 ks_sec).
//    On any path along which ks_sec is constant this is exactly the secant law.
#include <algorithm>
#include <cmath>

#include "joint/joints.hpp"

namespace dsdem {

struct CohesiveResponse {
  double sn = 0.0;  // normal traction, Pa (tension > 0)
  double ss = 0.0;  // shear traction, Pa (same sign as the slip)
  JointPointState state;     // updated history (also records dn, ds, sn, ss)
  double energy = 0.0;       // elastic energy stored (recoverable on the secant), J/m^2
  double dissipation = 0.0;  // energy dissipated since the last evaluation, J/m^2
  bool failed = false;       // damage == 1 (now or earlier)
  bool failed_now = false;   // damage reached 1 in this evaluation
  BreakMode mode = BreakMode::None;  // when failed_now: which softening branches were entered
  double fs = 0.0;    // current shear strength, Pa
  double ws = 0.0;    // current elastic slip limit fs/ks, m
  double wsII = 0.0;  // current shear softening length, m
};

// Everything of the law that depends on the properties only, computed once per
// property set: the joint phase evaluates the law twice per joint per step, and
// recomputing tan(phi) there alone was 13 % of the joint phase (issue 7 profile).
struct JointLawConstants {
  double kn = 0.0, ks = 0.0, ft = 0.0, c = 0.0, GII = 0.0;
  double tan_phi = 0.0;  // tan(phi)
  double wt = 0.0;       // ft / kn: opening at the tensile strength (eq. 6)
  double wn = 0.0;       // 2 GI / ft: mode I softening length (area = GI)
  double tiny = 0.0;     // 1e-12 (c + ft): division guard for inadmissible properties
  bool scale_ks = false;  // ks follows a joint's stiffness_scale (penalty ks, not given)
};
JointLawConstants law_constants(const JointProperties& p);
// The constants of one joint whose stiffness is s times its property's (local penalty
// size, DESIGN.md §3): kn (and ks when scale_ks) times s, wt = ft / kn again.
JointLawConstants scaled(const JointLawConstants& k, double s);

// dn: opening (m, > 0 opens), ds: slip (m), p: properties (validate() must pass),
// old: history from the previous evaluation. With damage_enabled = false (gravity
// stage) the history is frozen: no damage accrues and the law is the current secant.
// The dissipation of an increment is the trapezoidal work of the tractions (split at
// dn = 0) minus the change of stored energy; it is zero on elastic and secant paths.
// Both overloads give bit-identical results; the second one is the hot path.
CohesiveResponse cohesive_law(double dn, double ds, const JointProperties& p,
                              const JointPointState& old, bool damage_enabled = true);
inline CohesiveResponse cohesive_law(double dn, double ds, const JointLawConstants& k,
                                     const JointPointState& old, bool damage_enabled = true);

// Inline so that the joint force evaluates its two end points as one interleaved
// instruction stream (the law is a chain of divisions: latency-bound alone).
inline CohesiveResponse cohesive_law(double dn, double ds, const JointLawConstants& p,
                                     const JointPointState& old, bool damage_enabled) {
  CohesiveResponse r;
  JointPointState st = old;
  const double s = std::abs(ds);
  const double tan_phi = p.tan_phi;
  const double wt = p.wt;  // opening at the tensile strength (eq. 6)
  const double wn = p.wn;  // mode I softening length: area = GI

  // Fast path, most joints most of the time: an undamaged point whose largest opening
  // and slip stay inside the elastic limits wt and ws = fs/ks. There the law is linear
  // (sn = kn dn, ss = ks ds, eqs. 6-7) and stores all its work (dissipation 0): the
  // general branch below gives the same values up to rounding, through six divisions.
  if (old.damage == 0.0) {
    const double dn_max = damage_enabled ? std::max(old.dn_max, dn) : old.dn_max;
    const double s_max = damage_enabled ? std::max(old.s_max, s) : old.s_max;
    const double sn = p.kn * dn;
    const double fs = std::max(p.c - std::min(sn, p.ft) * tan_phi, p.tiny);  // eq. 8
    if (dn_max <= wt && s_max * p.ks <= fs) {
      r.sn = sn;
      r.ss = p.ks * ds;
      r.energy = 0.5 * (sn * dn + r.ss * ds);
      st.dn_max = dn_max;
      st.s_max = s_max;
      st.dn = dn;
      st.ds = ds;
      st.sn = r.sn;
      st.ss = r.ss;
      st.ks_sec = p.ks;
      r.state = st;
      r.fs = fs;
      r.ws = fs / p.ks;
      r.wsII = 2.0 * p.GII / std::max(fs - std::max(-sn, 0.0) * tan_phi, p.tiny);
      return r;
    }
  }
  if (damage_enabled) {
    st.dn_max = std::max(old.dn_max, dn);
    st.s_max = std::max(old.s_max, s);
  }

  // Normal traction of the normal law alone (eq. 6, secant unloading): enters eq. 8.
  double sn_normal;
  if (dn <= 0.0) {
    sn_normal = p.kn * dn;
  } else {
    const double past = std::max(0.0, st.dn_max - wt);
    const double d_normal = std::min(1.0, past != 0.0 ? past / wn : past);  // 0/wn = 0: skip the division
    sn_normal = p.ft * (1.0 - d_normal) * dn / std::max(st.dn_max, wt);
  }
  // Eq. 8 with the tension cut-off; fr is the residual friction (compression only).
  // The floor only guards division by zero for properties validate() rejects.
  const double tiny = p.tiny;
  const double fs = std::max(p.c - std::min(sn_normal, p.ft) * tan_phi, tiny);
  const double fr = std::max(-sn_normal, 0.0) * tan_phi;
  const double ws = fs / p.ks;
  const double wsII = 2.0 * p.GII / std::max(fs - fr, tiny);

  // Eq. 9 on the largest opening and slip reached; damage never decreases.
  // Intact joints sit below both limits: the numerators are +0 and the quotients +0
  // without dividing (divisions are most of the law's latency).
  const double past_n = std::max(st.dn_max - wt, 0.0), past_s = std::max(st.s_max - ws, 0.0);
  const double en = past_n != 0.0 ? past_n / wn : past_n;
  const double es = past_s != 0.0 ? past_s / wsII : past_s;
  // hypot(x, 0) = |x| exactly (C Annex F): skip the libm call in the common cases.
  const double e = en == 0.0 ? es : (es == 0.0 ? en : std::hypot(en, es));
  if (damage_enabled) st.damage = std::max(old.damage, std::min(1.0, e));
  const double D = st.damage;

  // Secant tractions: the envelope value at the largest separation, scaled back
  // linearly toward the origin (eqs. 6-7 on loading, secant on unloading).
  r.sn = dn <= 0.0 ? p.kn * dn : p.ft * (1.0 - D) * dn / std::max(st.dn_max, wt);
  // The shear secant stiffness depends on the normal traction (fs, fr) once the slip
  // has passed ws. A secant that stiffens under compression at a fixed slip would hand
  // out elastic energy that was never stored (ks_sec * ds^2 / 2 grows without work):
  // normal oscillations then pump energy into the joint without bound. So the shear
  // traction moves incrementally with the current secant slope and is kept between 0
  // and the secant value: it never rises without slip (stiffening releases nothing),
  // and drops onto the secant when the secant softens (dissipated, like friction).
  // Whenever the secant stiffness stays constant along a path this is the secant law.
  const double tau_env = fr + (fs - fr) * (1.0 - D);
  const double k_sec = tau_env / std::max(st.s_max, ws);
  const double ss_secant = k_sec * ds;
  const double ss_trial = old.ss + k_sec * (ds - old.ds);
  r.ss = std::clamp(ss_trial, std::min(0.0, ss_secant), std::max(0.0, ss_secant));

  auto shear_energy = [](double ss, double k) { return k > 0.0 ? 0.5 * ss * ss / k : 0.0; };
  r.energy = 0.5 * r.sn * dn + shear_energy(r.ss, k_sec);
  // Dissipation = trapezoidal work - change of stored energy. The normal law has a kink
  // at dn = 0 (secant on one side, kn on the other, both through the origin): a step
  // across it is integrated in two pieces, so closing a crack dissipates nothing.
  const double e_old = 0.5 * old.sn * old.dn + shear_energy(old.ss, old.ks_sec);
  const double work_n = old.dn * dn < 0.0 ? 0.5 * (r.sn * dn - old.sn * old.dn)
                                          : 0.5 * (old.sn + r.sn) * (dn - old.dn);
  // A shear traction held at 0 after its trial value crossed zero within the step is
  // integrated in two pieces too (slope k_sec down to zero, then nothing).
  const bool held_at_zero = r.ss == 0.0 && old.ss != 0.0 && k_sec > 0.0 && (ss_trial > 0.0) != (old.ss > 0.0);
  const double work_s = held_at_zero ? 0.5 * old.ss * (-old.ss / k_sec) : 0.5 * (old.ss + r.ss) * (ds - old.ds);
  r.dissipation = work_n + work_s - (r.energy - e_old);
  r.failed = D >= 1.0;
  r.failed_now = r.failed && old.damage < 1.0;
  if (r.failed_now) {
    r.mode = (en > 0.0 && es > 0.0) ? BreakMode::Mixed : (en > 0.0 ? BreakMode::Tension
                                                                    : BreakMode::Shear);
    st.mode = r.mode;
  }
  st.dn = dn;
  st.ds = ds;
  st.sn = r.sn;
  st.ss = r.ss;
  st.ks_sec = k_sec;
  r.state = st;
  r.fs = fs;
  r.ws = ws;
  r.wsII = wsII;
  return r;
}

}  // namespace dsdem
