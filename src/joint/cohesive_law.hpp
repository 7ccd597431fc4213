#pragma once
// Constitutive law of a cohesive joint at one integration point (paper eqs. 6-9,
// docs/theory.md §3). Pure function: separations + history in, tractions + history out.
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
//    GII. Without compression fr = 0 and this is docs/theory.md §3's wsII = 2*GII/fs.
//  * Once the slip has passed ws the shear secant ks_sec = (fr + (fs - fr)*(1 - D)) /
//    s_max depends on sn. The shear traction therefore follows the secant slope
//    incrementally and is kept between 0 and ks_sec*ds: it does not jump up when
//    compression stiffens the secant at a fixed slip (that would create energy, and
//    oscillating normal separations would pump it without bound), and it drops to
//    the secant when the secant softens. Stored shear energy is ss^2/(2 ks_sec).
//    On any path along which ks_sec is constant this is exactly the secant law.
#include <algorithm>
#include <cmath>

#include "model/joints.hpp"
#include "model/branchless.hpp"

namespace dsdem {

// One evaluation of the law at an end point (the history is updated in place).
struct CohesivePoint {
  double sn = 0.0;  // normal traction, Pa (tension > 0)
  double ss = 0.0;  // shear traction, Pa (same sign as the slip)
  double energy = 0.0;       // elastic energy stored (recoverable on the secant), J/m^2
  double dissipation = 0.0;  // energy dissipated since the last evaluation, J/m^2
  bool failed = false;       // damage == 1 (now or earlier)
  bool failed_now = false;   // damage reached 1 in this evaluation
  BreakMode mode = BreakMode::None;  // when failed_now: which softening branches were entered
  double fs = 0.0;    // current shear strength, Pa
  double ws = 0.0;    // current elastic slip limit fs/ks, m (0 from the elastic fast path)
  double wsII = 0.0;  // current shear softening length, m (0 from the elastic fast path)
};

// The same with the updated history as a value (the reference interface, for tests).
struct CohesiveResponse : CohesivePoint {
  JointPointState state;  // updated history
};

// Everything of the law that depends on the properties only, computed once per
// property set: the joint phase evaluates the law twice per joint per step, too often
// to recompute tan(phi) and the like each time.
struct JointLawConstants {
  double kn = 0.0, ks = 0.0, ft = 0.0, c = 0.0, GII = 0.0;
  double tan_phi = 0.0;  // tan(phi)
  double wn = 0.0;       // 2 GI / ft: mode I softening length (area = GI)
  double tiny = 0.0;     // 1e-12 (c + ft): division guard for inadmissible properties
  bool scale_ks = false;  // ks follows a joint's stiffness_scale (penalty ks, not given)
};
JointLawConstants law_constants(const JointProperties& p);
// The constants of one joint whose stiffness is s times its property's (local penalty
// size, docs/theory.md §3): kn (and ks when scale_ks) times s.
inline JointLawConstants scaled(const JointLawConstants& k, double s) {
  JointLawConstants r = k;
  r.kn = k.kn * s;
  r.ks = k.scale_ks ? k.ks * s : k.ks;
  return r;
}

// dn: opening (m, > 0 opens), ds: slip (m), p: properties (validate() must pass),
// old: history from the previous evaluation. With damage_enabled = false (gravity
// stage) the history is frozen: no damage accrues and the law is the current secant.
// The dissipation of an increment is the trapezoidal work of the tractions (split at
// dn = 0) minus the change of stored energy; it is zero on elastic and secant paths.
// All three give bit-identical results; cohesive_update() is the hot path (history
// updated in place, nothing copied).
CohesiveResponse cohesive_law(double dn, double ds, const JointProperties& p,
                              const JointPointState& old, bool damage_enabled = true);
inline CohesiveResponse cohesive_law(double dn, double ds, const JointLawConstants& k,
                                     const JointPointState& old, bool damage_enabled = true);
[[gnu::always_inline]] inline CohesivePoint cohesive_update(double dn, double ds, const JointLawConstants& k,
                                                            JointPointState& st, bool damage_enabled = true);

// The normal traction and the shear secant stiffness of the evaluation that left the
// history st (its dn, ds and maxima): the same operations on the same values as that
// evaluation, so the same bits. The elastic fast path is recognised by its own test
// (an undamaged point inside the limits it checks stays so with the maxima it stored).
struct LastTractions {
  double sn = 0.0;      // Pa
  double ks_sec = 0.0;  // Pa/m (stored shear energy ss^2 / (2 ks_sec))
};
inline LastTractions last_tractions(const JointPointState& st, const JointLawConstants& p);

// Normal traction of the normal law alone (eq. 6, secant unloading) at opening dn with
// the largest opening dn_max: enters eq. 8.
inline double normal_law_traction(double dn, double dn_max, double wt, const JointLawConstants& p) {
  if (dn <= 0.0) return p.kn * dn;
  const double past = std::max(0.0, dn_max - wt);
  const double d_normal = std::min(1.0, past != 0.0 ? past / p.wn : past);  // 0/wn = 0: skip the division
  return p.ft * (1.0 - d_normal) * dn / std::max(dn_max, wt);
}

inline LastTractions last_tractions(const JointPointState& st, const JointLawConstants& p) {
  if (st.damage == 0.0) {  // the fast path's test with the maxima it stored
    const double sn = p.kn * st.dn;
    const double fs = std::max(p.c - std::min(sn, p.ft) * p.tan_phi, p.tiny);
    if (st.dn_max * p.kn <= p.ft && st.s_max * p.ks <= fs) return {sn, p.ks};
  }
  // The general branch of cohesive_update, on the stored history.
  const double wt = p.ft / p.kn;
  const double sn_normal = normal_law_traction(st.dn, st.dn_max, wt, p);
  const double fs = std::max(p.c - std::min(sn_normal, p.ft) * p.tan_phi, p.tiny);
  const double fr = std::max(-sn_normal, 0.0) * p.tan_phi;
  const double ws = fs / p.ks;
  const double D = st.damage;
  LastTractions t;
  t.sn = st.dn <= 0.0 ? p.kn * st.dn : p.ft * (1.0 - D) * st.dn / std::max(st.dn_max, wt);
  t.ks_sec = (fr + (fs - fr) * (1.0 - D)) / std::max(st.s_max, ws);
  return t;
}

// The elastic fast path inline (the joint phase evaluates it twice per joint per step);
// the general branch, rare, out of line (cohesive_law.cpp).
CohesivePoint cohesive_update_general(double dn, double ds, const JointLawConstants& p, JointPointState& st,
                                      bool damage_enabled);

// The damage measure of eq. 9, sqrt(en^2 + es^2) (std::hypot), for max(damage_before,
// min(1, .)): where the root is provably below damage_before, damage_before itself, which
// that max() turns into the same damage bit for bit, without the libm call.
double mixed_mode_damage(double en, double es, double damage_before);

[[gnu::always_inline]] inline CohesivePoint cohesive_update(double dn, double ds, const JointLawConstants& p,
                                                            JointPointState& st, bool damage_enabled) {
  // Fast path, most joints most of the time: an undamaged point whose largest opening
  // and slip stay inside the elastic limits wt and ws = fs/ks. There the law is linear
  // (sn = kn dn, ss = ks ds, eqs. 6-7) and stores all its work (dissipation 0): the
  // general branch gives the same values up to rounding, through six divisions.
  // last_tractions() repeats this test on the stored history: keep the two alike.
  if (st.damage == 0.0) [[likely]] {
    const double dn_max = damage_enabled ? std::max(st.dn_max, dn) : st.dn_max;
    const double s_max = damage_enabled ? std::max(st.s_max, std::abs(ds)) : st.s_max;
    const double sn = p.kn * dn;
    const double fs = std::max(p.c - std::min(sn, p.ft) * p.tan_phi, p.tiny);  // eq. 8
    if (dn_max * p.kn <= p.ft && s_max * p.ks <= fs) [[likely]] {  // dn_max <= wt = ft/kn, s_max <= ws
      CohesivePoint r;
      r.sn = sn;
      r.ss = p.ks * ds;
      r.energy = 0.5 * (sn * dn + r.ss * ds);
      st.dn_max = dn_max;
      st.s_max = s_max;
      st.dn = dn;
      st.ds = ds;
      st.ss = r.ss;
      r.fs = fs;  // ws and wsII are left 0 here: two divisions nobody needs while elastic
      return r;
    }
  }
  return cohesive_update_general(dn, ds, p, st, damage_enabled);
}

inline CohesiveResponse cohesive_law(double dn, double ds, const JointLawConstants& p,
                                     const JointPointState& old, bool damage_enabled) {
  CohesiveResponse r;
  r.state = old;
  static_cast<CohesivePoint&>(r) = cohesive_update(dn, ds, p, r.state, damage_enabled);
  return r;
}

}  // namespace dsdem
