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
  k.wt = p.ft / p.kn;
  k.wn = 2.0 * p.GI / p.ft;
  k.tiny = 1e-12 * (p.c + p.ft);
  k.scale_ks = p.penalty_h > 0.0 && !p.ks_given;
  return k;
}

JointLawConstants scaled(const JointLawConstants& k, double s) {
  JointLawConstants r = k;
  r.kn = k.kn * s;
  if (k.scale_ks) r.ks = k.ks * s;
  r.wt = k.ft / r.kn;
  return r;
}

CohesiveResponse cohesive_law(double dn, double ds, const JointProperties& p,
                              const JointPointState& old, bool damage_enabled) {
  return cohesive_law(dn, ds, law_constants(p), old, damage_enabled);
}

}  // namespace dsdem
