#include "fem/mohr_coulomb.hpp"

#include <sstream>
#include <stdexcept>

namespace dsdem::fem {

std::string validate(const MohrCoulombParameters& p, bool plane_stress) {
  std::ostringstream err;
  check_envelope(err, p.c, p.phi, p.psi, plane_stress);
  if (!(p.ft >= 0.0)) err << "ft must be >= 0 (got " << p.ft << "); ";
  if (p.phi > 0.0 && p.phi < 0.5 * kPi && p.c >= 0.0 && std::isfinite(p.ft)) {
    const double apex = law::envelope_apex(p.c, p.phi);
    if (p.ft > apex)
      err << "ft must not exceed c / tan(phi) = " << apex << " Pa, the apex of the Mohr-Coulomb cone (got " << p.ft
          << "); ";
  }
  return validation_text(law::mohr_coulomb::kName, err);
}

const char* to_string(MohrCoulombRegion r) {
  switch (r) {
    case MohrCoulombRegion::Elastic: return "elastic";
    case MohrCoulombRegion::ShearPlane: return "shear_plane";
    case MohrCoulombRegion::ShearEdgeCompression: return "shear_edge_compression";
    case MohrCoulombRegion::ShearEdgeExtension: return "shear_edge_extension";
    case MohrCoulombRegion::ShearApex: return "shear_apex";
    case MohrCoulombRegion::TensionPlane: return "tension_plane";
    case MohrCoulombRegion::TensionEdge: return "tension_edge";
    case MohrCoulombRegion::TensionApex: return "tension_apex";
    case MohrCoulombRegion::ShearTensionLine: return "shear_tension_line";
    case MohrCoulombRegion::ShearTensionCompression: return "shear_tension_compression";
    case MohrCoulombRegion::ShearTensionExtension: return "shear_tension_extension";
  }
  return "unknown";
}

namespace {

using P3 = std::array<double, 3>;

double dot(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// D b of the isotropic elasticity in principal space: lambda (sum b) 1 + 2 mu b.
P3 elastic_image(const ElasticConstants& c, const P3& b) {
  const double l = c.lambda * (b[0] + b[1] + b[2]);
  return {l + 2.0 * c.mu * b[0], l + 2.0 * c.mu * b[1], l + 2.0 * c.mu * b[2]};
}

}  // namespace

MohrCoulombModel make_mohr_coulomb(const MohrCoulombParameters& p, const ElasticConstants& elastic) {
  MohrCoulombModel mc;
  mc.elastic = elastic;
  const double sp = std::sin(p.phi);
  const double ss = std::sin(p.psi);
  mc.k = (1.0 + sp) / (1.0 - sp);
  mc.m = (1.0 + ss) / (1.0 - ss);
  mc.sc = 2.0 * p.c * std::cos(p.phi) / (1.0 - sp);
  mc.mc_scale = 0.5 * (1.0 - sp);
  mc.apex = law::envelope_apex(p.c, p.phi);
  mc.cutoff = p.ft < mc.apex;
  mc.ft = mc.cutoff ? p.ft : std::numeric_limits<double>::infinity();
  mc.compliance = compliance(elastic);
  // Shear planes of the sector s1 >= s2 >= s3 and of its two neighbours (the edges), with
  // the potential g = m s_max - s_min (Clausen et al. 2007, with tension positive).
  const double k = mc.k, m = mc.m;
  const P3 a_shear[3] = {{k, 0.0, -1.0}, {0.0, k, -1.0}, {k, -1.0, 0.0}};
  const P3 b_shear[3] = {{m, 0.0, -1.0}, {0.0, m, -1.0}, {m, -1.0, 0.0}};
  for (int i = 0; i < 3; ++i) mc.plane[i] = {a_shear[i], elastic_image(elastic, b_shear[i]), mc.sc, 0.0};
  // Rankine cut-off s_i <= ft, associated.
  for (int i = 0; i < 3; ++i) {
    P3 e{0.0, 0.0, 0.0};
    e[i] = 1.0;
    mc.plane[3 + i] = {e, elastic_image(elastic, e), mc.ft, 0.0};
  }
  for (PrincipalPlane& pl : mc.plane) pl.inv_ar = 1.0 / dot(pl.a, pl.r);
  return mc;
}

std::array<double, 3> principal_stresses(const Vec3& S, double S_zz) {
  const double C = 0.5 * (S[0] + S[1]);
  const double d = 0.5 * (S[0] - S[1]);
  const double R = std::sqrt(d * d + S[2] * S[2]);
  std::array<double, 3> s{C + R, C - R, S_zz};
  if (s[2] > s[0]) std::swap(s[2], s[0]);
  if (s[2] > s[1]) std::swap(s[2], s[1]);
  return {s[0], s[1], s[2]};
}

double yield_function(const MohrCoulombModel& mc, const std::array<double, 3>& s) {
  const double shear = mc.mc_scale * (mc.k * s[0] - s[2] - mc.sc);
  return std::max(shear, s[0] - mc.ft);
}

namespace {

// One candidate of the return: the active planes and the region they stand for.
struct Candidate {
  MohrCoulombRegion region;
  int n;
  std::array<int, 3> planes;
};

// Faces first, then lines, then points. Without a cut-off the apex takes what the plane
// and the two edges do not: with psi < phi its return direction is not in the cone of the
// potential gradients (Clausen et al. 2007: the apex region is bounded by the planes
// through the apex spanned by the edges' return directions, and lies beyond the apex in
// mean stress, so the dissipation there stays >= 0). The shear-tension compression corner
// is where four planes meet (k s1 - s3, k s2 - s3, s1, s2); the trial returns there when
// it lies in the cone of their four return directions, i.e. in the cone of some three.
constexpr Candidate kShearOnly[] = {
    {MohrCoulombRegion::ShearPlane, 1, {0, 0, 0}},
    {MohrCoulombRegion::ShearEdgeCompression, 2, {0, 1, 0}},
    {MohrCoulombRegion::ShearEdgeExtension, 2, {0, 2, 0}},
};
constexpr Candidate kWithCutoff[] = {
    {MohrCoulombRegion::ShearPlane, 1, {0, 0, 0}},
    {MohrCoulombRegion::TensionPlane, 1, {3, 0, 0}},
    {MohrCoulombRegion::ShearEdgeCompression, 2, {0, 1, 0}},
    {MohrCoulombRegion::ShearEdgeExtension, 2, {0, 2, 0}},
    {MohrCoulombRegion::ShearTensionLine, 2, {0, 3, 0}},
    {MohrCoulombRegion::TensionEdge, 2, {3, 4, 0}},
    {MohrCoulombRegion::ShearTensionExtension, 3, {0, 2, 3}},
    {MohrCoulombRegion::TensionApex, 3, {3, 4, 5}},
    {MohrCoulombRegion::ShearTensionCompression, 3, {0, 1, 3}},
    {MohrCoulombRegion::ShearTensionCompression, 3, {0, 3, 4}},
    {MohrCoulombRegion::ShearTensionCompression, 3, {0, 1, 4}},
    {MohrCoulombRegion::ShearTensionCompression, 3, {1, 3, 4}},
};

// Solves G x = f for n = 1, 2, 3 (Cramer); false when G is singular.
bool solve(int n, const double G[3][3], const double f[3], double x[3]) {
  if (n == 1) {
    if (G[0][0] == 0.0) return false;
    x[0] = f[0] / G[0][0];
    return true;
  }
  if (n == 2) {
    const double det = G[0][0] * G[1][1] - G[0][1] * G[1][0];
    if (det == 0.0) return false;
    x[0] = (f[0] * G[1][1] - G[0][1] * f[1]) / det;
    x[1] = (G[0][0] * f[1] - f[0] * G[1][0]) / det;
    return true;
  }
  auto det3 = [](const double a[3], const double b[3], const double c[3]) {
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  };
  // Columns of G as rows of its transpose.
  double c0[3] = {G[0][0], G[1][0], G[2][0]}, c1[3] = {G[0][1], G[1][1], G[2][1]}, c2[3] = {G[0][2], G[1][2], G[2][2]};
  const double det = det3(c0, c1, c2);
  if (det == 0.0 || !std::isfinite(det)) return false;
  x[0] = det3(f, c1, c2) / det;
  x[1] = det3(c0, f, c2) / det;
  x[2] = det3(c0, c1, f) / det;
  return true;
}

struct Trial {
  P3 s;                 // returned principal stresses
  double violation;     // largest violation of the return's conditions, Pa
};

// Return of sB to the planes of `cand` (one plane, a line of two, a point of three;
// Clausen et al. 2006): s = sB - sum dl_j r_j with a_i . s = rhs_i; valid when every
// dl_j >= 0, the order s1 >= s2 >= s3 holds and s is admissible.
Trial try_return(const MohrCoulombModel& mc, const P3& sB, const Candidate& cand) {
  double G[3][3], f[3], dl[3] = {0.0, 0.0, 0.0};
  for (int i = 0; i < cand.n; ++i) {
    const PrincipalPlane& pi = mc.plane[cand.planes[i]];
    f[i] = dot(pi.a, sB) - pi.rhs;
    for (int j = 0; j < cand.n; ++j) G[i][j] = dot(pi.a, mc.plane[cand.planes[j]].r);
  }
  Trial t{sB, std::numeric_limits<double>::infinity()};
  if (!solve(cand.n, G, f, dl)) return t;
  double v = -std::numeric_limits<double>::infinity();
  for (int j = 0; j < cand.n; ++j) {
    const P3& r = mc.plane[cand.planes[j]].r;
    for (int q = 0; q < 3; ++q) t.s[q] -= dl[j] * r[q];
    v = std::max(v, -dl[j] * G[j][j]);
  }
  // The cut-off planes fix their principal stress exactly.
  for (int j = 0; j < cand.n; ++j)
    if (cand.planes[j] >= 3) t.s[cand.planes[j] - 3] = mc.ft;
  v = std::max({v, t.s[1] - t.s[0], t.s[2] - t.s[1], mc.k * t.s[0] - t.s[2] - mc.sc});
  if (mc.cutoff) v = std::max(v, t.s[0] - mc.ft);
  t.violation = v;
  return t;
}

// Principal stresses of the trial: the in-plane pair sa >= sb along the angle 2theta (cos
// c2, sin s2) and S_zz, sorted into s; `zpos` is where S_zz sits in s (scalars rather than
// an indexed store, which the loads after it would stall on).
struct PrincipalTrial {
  P3 s;
  double c2, s2;
  int zpos;
};

PrincipalTrial principal_trial(const Vec3& S, double S_zz) {
  const double C = 0.5 * (S[0] + S[1]);
  const double d = 0.5 * (S[0] - S[1]);
  const double R = std::sqrt(d * d + S[2] * S[2]);
  PrincipalTrial p;
  p.c2 = R > 0.0 ? d / R : 1.0;
  p.s2 = R > 0.0 ? S[2] / R : 0.0;
  const double sa = C + R, sb = C - R;
  p.zpos = S_zz > sa ? 0 : (S_zz > sb ? 1 : 2);
  p.s = p.zpos == 0 ? P3{S_zz, sa, sb} : (p.zpos == 1 ? P3{sa, S_zz, sb} : P3{sa, sb, S_zz});
  return p;
}

// The returned principal stresses and the region they were returned to.
struct Returned {
  P3 s;
  MohrCoulombRegion region;
};

// Closed-form return of sB (f_shear = k s1 - s3 - sc > 0) to the shear plane k s1 - s3 = sc;
// violation 0 when the order s1 >= s2 >= s3 and the cut-off hold, else 1.
Trial shear_plane_return(const MohrCoulombModel& mc, const P3& sB, double f_shear) {
  const PrincipalPlane& shear = mc.plane[0];
  const double dl = f_shear * shear.inv_ar;
  Trial t;
  t.s = {sB[0] - dl * shear.r[0], sB[1] - dl * shear.r[1], sB[2] - dl * shear.r[2]};
  t.violation = t.s[0] >= t.s[1] && t.s[1] >= t.s[2] && t.s[0] <= mc.ft ? 0.0 : 1.0;
  return t;
}

// Closed-form return of sB (s1 > ft) to the cut-off plane s1 = ft; violation 0 when s2
// stays below the cut-off and s is inside the shear envelope, else 1.
Trial tension_plane_return(const MohrCoulombModel& mc, const P3& sB) {
  const PrincipalPlane& tension = mc.plane[3];
  const double dl = (sB[0] - mc.ft) * tension.inv_ar;
  Trial t;
  t.s = {mc.ft, sB[1] - dl * tension.r[1], sB[2] - dl * tension.r[2]};
  t.violation = t.s[1] <= mc.ft && mc.k * t.s[0] - t.s[2] - mc.sc <= 0.0 ? 0.0 : 1.0;
  return t;
}

// The first candidate whose conditions hold to round-off (1e-13 of the stress scale, some
// hundred ulps); the regions tile the plastic domain, so one does up to that round-off.
// Without a cut-off the apex takes what no candidate does. `region` is the result's
// region when no candidate's system can be solved. Out of line, so that the common
// closed-form returns are not slowed by this loop's registers.
[[gnu::noinline]] Returned candidate_return(const MohrCoulombModel& mc, const P3& sB, MohrCoulombRegion region) {
  const double tol = 1e-13 * (std::abs(sB[0]) + std::abs(sB[2]) + mc.sc + (mc.cutoff ? std::abs(mc.ft) : 0.0));
  const Candidate* begin = mc.cutoff ? std::begin(kWithCutoff) : std::begin(kShearOnly);
  const Candidate* stop = mc.cutoff ? std::end(kWithCutoff) : std::end(kShearOnly);
  Trial best{sB, std::numeric_limits<double>::infinity()};
  for (const Candidate* cand = begin; cand != stop; ++cand) {
    const Trial t = try_return(mc, sB, *cand);
    if (t.violation < best.violation) {
      best = t;
      region = cand->region;
    }
    if (t.violation <= tol) break;
  }
  if (best.violation > tol && !mc.cutoff && mc.k > 1.0)
    return {{mc.apex, mc.apex, mc.apex}, MohrCoulombRegion::ShearApex};
  return {best.s, region};
}

// Return of the trial sB (outside the envelope) onto it. The two plane returns first, in
// closed form: the common cases, and their conditions hold strictly, so the candidate
// search would return the same.
Returned return_to_envelope(const MohrCoulombModel& mc, const P3& sB) {
  Trial best{sB, std::numeric_limits<double>::infinity()};
  MohrCoulombRegion region = MohrCoulombRegion::ShearPlane;
  const double f_shear = mc.k * sB[0] - sB[2] - mc.sc;
  if (f_shear > 0.0) best = shear_plane_return(mc, sB, f_shear);
  if (best.violation > 0.0 && mc.cutoff && sB[0] > mc.ft) {
    best = tension_plane_return(mc, sB);
    region = MohrCoulombRegion::TensionPlane;
  }
  if (best.violation > 0.0) return candidate_return(mc, sB, region);
  return {best.s, region};
}

// Rotates the returned principal stresses s back to (S_xx, S_yy, S_xy) and S_zz: the return
// keeps the principal directions (isotropic D).
void rotate_back(const PrincipalTrial& trial, const P3& s, Vec3& S, double& S_zz) {
  const double ra = trial.zpos == 0 ? s[1] : s[0];
  const double rb = trial.zpos == 2 ? s[1] : s[2];
  const double Cn = 0.5 * (ra + rb);
  const double Rn = 0.5 * (ra - rb);
  S = Vec3(Cn + Rn * trial.c2, Cn - Rn * trial.c2, Rn * trial.s2);
  S_zz = s[trial.zpos];
}

// S : dEp at the returned stress s, in principal space (coaxial). It is sum dl_j s . b_j
// >= 0 for admissible s and 0 <= psi; the clamp removes round-off at the apex.
double plastic_dissipation(const MohrCoulombModel& mc, const P3& sB, const P3& s) {
  const Compliance& d = mc.compliance;
  const double pvol = d.inv_vol * ((sB[0] - s[0]) + (sB[1] - s[1]) + (sB[2] - s[2]));
  double diss = 0.0;
  for (int q = 0; q < 3; ++q) diss += s[q] * (d.inv_2mu * (sB[q] - s[q]) - pvol);
  return std::max(0.0, diss);
}

}  // namespace

namespace detail {

MohrCoulombResult mohr_coulomb_return(const MohrCoulombModel& mc, const Vec3& E, const Vec3& S0, double S0_zz,
                                      const Vec3& S, double S_zz, const MohrCoulombState& start,
                                      MohrCoulombState& end) {
  const PrincipalTrial trial = principal_trial(S, S_zz);
  const Returned ret = return_to_envelope(mc, trial.s);
  MohrCoulombResult out;
  rotate_back(trial, ret.s, out.S, out.S_zz);
  out.region = ret.region;
  finish_return(mc.compliance, E, S0, S0_zz, S, S_zz, start, end, out,
                [&](const PlasticIncrement&) { return plastic_dissipation(mc, trial.s, ret.s); });
  return out;
}

}  // namespace detail

MohrCoulombResult3D mohr_coulomb_update_3d(const MohrCoulombModel& mc, const Vec6& E, const Vec6& S0,
                                           const PlasticState3D& start, PlasticState3D& end) {
  const ElasticTrial3D t = elastic_trial(mc.elastic, E, S0, start);
  // Elastic for sure, without the eigensystem: the principal stresses lie within
  // p +- 2 sqrt(J2 / 3) of the mean p, so k s1 - s3 - sc <= k (p + r) - (p - r) - sc (k >= 1).
  // The margin keeps states within rounding of the envelope on the exact check below.
  {
    const Vec6& s = t.S;
    const double p = (s[0] + s[1] + s[2]) / 3.0;
    const double dx = s[0] - p, dy = s[1] - p, dz = s[2] - p;
    const double j2 = 0.5 * (dx * dx + dy * dy + dz * dz) + s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
    const double r = 2.0 * std::sqrt(j2 / 3.0);
    const double margin = 1e-12 * (std::abs(p) + r + mc.sc);
    if (mc.k * (p + r) - (p - r) - mc.sc <= -margin && p + r <= mc.ft - margin)
      return elastic_result<MohrCoulombResult3D>(t, S0, start, end);
  }
  // Eigenvalues ascending, eigenvectors as columns: s1 >= s2 >= s3 is the reverse order.
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(detail::to_tensor(t.S));
  const Vec3& ev = eig.eigenvalues();
  const P3 sB{ev[2], ev[1], ev[0]};
  if (mc.k * sB[0] - sB[2] - mc.sc <= 0.0 && sB[0] <= mc.ft)
    return elastic_result<MohrCoulombResult3D>(t, S0, start, end);
  const Returned ret = return_to_envelope(mc, sB);
  const Mat3& Q = eig.eigenvectors();
  const Mat3 S = Q * Vec3(ret.s[2], ret.s[1], ret.s[0]).asDiagonal() * Q.transpose();
  MohrCoulombResult3D out;
  out.S << S(0, 0), S(1, 1), S(2, 2), 0.5 * (S(1, 2) + S(2, 1)), 0.5 * (S(0, 2) + S(2, 0)), 0.5 * (S(0, 1) + S(1, 0));
  out.region = ret.region;
  finish_return(mc.compliance, E, S0, t.S, start, end, out,
                [&](const Vec6&) { return plastic_dissipation(mc, sB, ret.s); });
  return out;
}

MohrCoulombKernel::Model MohrCoulombKernel::make(std::span<const double> params, const ElasticConstants& elastic,
                                                 bool plane_stress) {
  const auto [c, phi, psi] = law::envelope(params);
  // The declared default is the envelope's apex c / tan(phi): no cut-off of its own.
  const double ft = params[law::mohr_coulomb::tensile_strength];
  MohrCoulombParameters p{c, phi, psi,
                          std::isfinite(ft) && ft < law::envelope_apex(c, phi) ? ft
                                                                               : std::numeric_limits<double>::infinity()};
  if (const std::string why = validate(p, plane_stress); !why.empty()) throw std::invalid_argument(why);
  return make_mohr_coulomb(p, elastic);
}

}  // namespace dsdem::fem
