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

// dn: opening (m, > 0 opens), ds: slip (m), p: properties (validate() must pass),
// old: history from the previous evaluation. With damage_enabled = false (gravity
// stage) the history is frozen: no damage accrues and the law is the current secant.
// The dissipation of an increment is the trapezoidal work of the tractions (split at
// dn = 0) minus the change of stored energy; it is zero on elastic and secant paths.
CohesiveResponse cohesive_law(double dn, double ds, const JointProperties& p,
                              const JointPointState& old, bool damage_enabled = true);

}  // namespace dsdem
