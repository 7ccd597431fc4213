#pragma once
// The plastic point of the linear tetrahedron (tet4.hpp): what the plastic laws share in 3D,
// as plastic_point.hpp is in plane strain (docs/theory.md §10). E = Ee + Ep on the Green
// strain, S = S0 + D (E - Ep); Voigt (xx, yy, zz, yz, xz, xy), strains with engineering
// shears, stresses with tensor components. Tension positive.
#include <cmath>

#include "fem/bulk_kernel.hpp"
#include "fem/cst.hpp"
#include "fem/plastic_point.hpp"
#include "fem/tet4.hpp"

namespace dsdem::fem {

// State of one tetrahedron (one material point), seven doubles.
struct PlasticState3D {
  Vec6 ep = Vec6::Zero();     // plastic Green strain, engineering shears
  double plastic_work = 0.0;  // accumulated dissipation per unit reference volume, J/m^3
};

// The elastic trial: elastic strain Ee = E - Ep, its stress D Ee and S = S0 + D Ee.
struct ElasticTrial3D {
  Vec6 Ee;
  Vec6 DEe;
  Vec6 S;
};
[[gnu::always_inline]] inline ElasticTrial3D elastic_trial(const ElasticConstants& c, const Vec6& E, const Vec6& S0,
                                                           const PlasticState3D& start) {
  ElasticTrial3D t;
  t.Ee = E - start.ep;
  t.DEe = svk_stress(t.Ee, c);
  t.S = S0 + t.DEe;
  return t;
}

// Stored energy S0 : Ee + Ee : D : Ee / 2 (the Voigt dot is the double contraction).
inline double stored_energy(const Vec6& S0, const Vec6& Ee, const Vec6& DEe) { return S0.dot(Ee) + 0.5 * DEe.dot(Ee); }

// dEp = D^-1 (S_trial - S), engineering shears.
inline Vec6 plastic_increment(const Compliance& d, const Vec6& S_trial, const Vec6& S) {
  const Vec6 ds = S_trial - S;
  const double vol = d.inv_vol * (ds[0] + ds[1] + ds[2]);
  Vec6 dep;
  dep << d.inv_2mu * ds[0] - vol, d.inv_2mu * ds[1] - vol, d.inv_2mu * ds[2] - vol, ds[3] / d.mu, ds[4] / d.mu,
      ds[5] / d.mu;
  return dep;
}

// The result of one update of a 3D plastic law whose return regions are Region (Elastic = 0).
template <class Region>
struct PlasticResult3D {
  Vec6 S = Vec6::Zero();       // PK2 stress, Pa
  double dissipation = 0.0;    // S : dEp of this update at the returned stress, J/m^3, >= 0
  double strain_energy = 0.0;  // stored elastic energy, J/m^3
  Region region = Region::Elastic;
  bool yielded() const { return region != Region::Elastic; }
};

template <class Result>
[[gnu::always_inline]] inline Result elastic_result(const ElasticTrial3D& t, const Vec6& S0,
                                                    const PlasticState3D& start, PlasticState3D& end) {
  end = start;
  Result out;
  out.S = t.S;
  out.strain_energy = stored_energy(S0, t.Ee, t.DEe);
  return out;
}

// The end of a return from the trial S_trial to out.S: the plastic strain, the update's
// dissipation dissipation(dEp) (the law's S : dEp), the plastic work and the stored energy at
// the step's end (`end` may be `start`).
template <class Result, class Dissipation>
void finish_return(const Compliance& d, const Vec6& E, const Vec6& S0, const Vec6& S_trial, const PlasticState3D& start,
                   PlasticState3D& end, Result& out, Dissipation&& dissipation) {
  const Vec6 dep = plastic_increment(d, S_trial, out.S);
  end.ep = start.ep + dep;
  out.dissipation = dissipation(dep);
  end.plastic_work = start.plastic_work + out.dissipation;
  out.strain_energy = stored_energy(S0, E - end.ep, out.S - S0);
}

// S : dEp clamped at 0 (round-off at an apex).
inline double plastic_work(const Vec6& dep, const Vec6& S) {
  const double w = S.dot(dep);
  return w > 0.0 ? w : 0.0;
}

// What the tetrahedron's element loop (bulk_law.hpp) needs of a plastic law that runs in
// 3D, with the update Update3D(model, E, S0, start, end): the 3D plastic point's state, its
// plastic work the accumulated dissipation. A law's kernel derives from this beside
// PlasticKernel.
template <class M, class Result3D,
          Result3D (*Update3D)(const M&, const Vec6&, const Vec6&, const PlasticState3D&, PlasticState3D&)>
struct PlasticKernel3D {
  using State3D = PlasticState3D;
  // The state as doubles (the element's record): the six plastic strains, then the work.
  static constexpr std::size_t kState3D = 7;
  static constexpr int kDissipation3D = 6;
  static State3D load_3d(const double* p) {
    State3D s;
    s.ep = Eigen::Map<const Vec6>(p);
    s.plastic_work = p[6];
    return s;
  }
  static void store_3d(const State3D& s, double* p) {
    Eigen::Map<Vec6> ep(p);
    ep = s.ep;
    p[6] = s.plastic_work;
  }
  [[gnu::always_inline]] static BulkResponse3D update_3d(const M& m, const Vec6& E, const Vec6& S0,
                                                         const State3D& start, State3D& end) {
    const Result3D r = Update3D(m, E, S0, start, end);
    return {r.S, r.strain_energy, r.dissipation};
  }
};

}  // namespace dsdem::fem
