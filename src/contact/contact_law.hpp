#pragma once
// Contact law of one spheropolygon contact (docs/theory.md §4; paper eqs. 2-4): linear
// normal spring with an optional dashpot, incremental tangential spring with the
// Coulomb cap, no tension. A pure function of the contact's geometry, the relative
// velocity at the contact point, dt, the stored tangential force and parameters.
#include "model/contact_properties.hpp"
#include "model/types.hpp"

namespace dsdem::contact {

using dsdem::ContactProperties;  // what the user gives per pair of groups

// What the law uses: restitution turned into a damping ratio once, at set-up.
struct ContactLawParams {
  double kn = 0.0;
  double ks = 0.0;
  double mu = 0.0;
  double damping_ratio = 0.0;  // zeta; dashpot c = 2 zeta sqrt(m_eff kn)
};

// zeta of the linear spring-dashpot whose free bounce (contact ending when the
// spring crosses zero, tension allowed) has restitution e:
// zeta = -ln e / sqrt(pi^2 + ln^2 e).
double damping_ratio_linear(double e);

// Restitution of the bounce with our no-tension law: the contact ends when the total
// normal force (spring + dashpot) reaches zero, before the spring crosses zero, so the
// bounce is livelier than the linear formula says (e = 0.5 gives 0.55). Closed form
// (Schwager & Poeschel 2007, Granular Matter 9:465) for a two-body bounce.
double restitution_no_tension(double zeta);

// zeta that makes the no-tension law bounce with restitution e (inverts
// restitution_no_tension by bisection; it decreases monotonically from 1 at zeta=0).
// This is what ContactLawParams uses, so the set e is what a collision gives.
// Throws std::invalid_argument unless 0 < e <= 1.
double damping_ratio_from_restitution(double e);

ContactLawParams law_params(const ContactProperties& p);

// The stored tangential force carried into the current contact frame: turned
// (not projected) onto the current tangent t = (-n_y, n_x), keeping its magnitude and
// its side, so a contact that rotates rigidly keeps its force.
Vec2 rotate_into_frame(const Vec2& ft_prev, const Vec2& normal);

struct ContactLawResult {
  double fn = 0.0;             // normal force on i along +normal, >= 0, N/m
  Vec2 ft = Vec2::Zero();      // tangential force on i (also the new stored history)
  Vec2 force = Vec2::Zero();   // total force on i = fn*normal + ft (on j: -force)
  bool sliding = false;        // the Coulomb cap was active
  double elastic_energy = 0.0;        // kn delta^2/2 + |ft|^2/(2 ks), J/m
  double friction_dissipation = 0.0;  // this step, J/m
  // The dashpot's part of fn (fn - kn delta, N/m along +normal; <= 0 while separating) and
  // its power over dt at the given v_rel, -(fn - kn delta) vn dt >= 0, J/m. Velocity Verlet
  // applies the force half before and half after v_rel's half step: ContactForces books
  // half of this now and half with the next half-step velocity (docs/theory.md §7).
  double dashpot_force = 0.0;
  double damping_dissipation = 0.0;
};

// overlap delta (> 0 for a contact), normal n from j to i, v_rel = velocity of i minus
// velocity of j at the contact point, dt, the previous tangential force (zero for a
// new contact), effective mass of the pair at the point (for the dashpot; 0 or inf
// turns it off).
//   Fn = max(0, kn*delta - c*(v_rel.n))           (no tension)
//   Ft = rot(Ft_prev) - ks*(v_rel tangential)*dt  (paper eq. 2)
//   |Ft| <= mu*Fn                                 (paper eq. 3)
ContactLawResult contact_law(double overlap, const Vec2& normal, const Vec2& v_rel, double dt,
                             const Vec2& ft_prev, double m_eff, const ContactLawParams& p);

}  // namespace dsdem::contact
