// The declarations of the registered laws. A parameter's text here is the scenario
// reference's text for its key (io/schema.cpp builds the keys from these).
#include <fmt/format.h>

#include <cmath>

#include "law/laws.hpp"
#include "law/strength_reduction.hpp"

namespace dsdem::law {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

ParamDecl param(std::string name, std::string unit, std::string def, double min, double max, std::string doc,
                bool min_excl = false, bool max_excl = false) {
  ParamDecl p;
  p.name = std::move(name);
  p.unit = std::move(unit);
  p.default_text = std::move(def);
  p.min = min;
  p.max = max;
  p.min_exclusive = min_excl;
  p.max_exclusive = max_excl;
  p.doc = std::move(doc);
  return p;
}

// The elastic constants every bulk law starts from (docs/theory.md §2).
std::vector<ParamDecl> elastic_params() {
  return {param("E", "Pa", "required", 0, kInf, "Young's modulus.", true),
          param("nu", "", "required", -1, 0.5, "Poisson's ratio.", true, true),
          param("rho", "kg/m^3", "required", 0, kInf, "Density.", true)};
}

// psi <= phi: with a larger dilation angle the plastic flow would create energy.
std::vector<ParamProblem> check_dilation(const LawDecl& law, std::span<const double> v) {
  std::vector<ParamProblem> out;
  const double phi = law.value(v, "friction_angle"), psi = law.value(v, "dilation_angle");
  if (psi > phi)
    out.push_back({"dilation_angle", fmt::format("{} deg exceeds friction_angle {} deg: the plastic flow would "
                                                 "create energy (psi <= phi)", psi, phi)});
  return out;
}

// Strength reduction of the envelope (docs/theory.md §9): c / F, tan(phi) / F and
// tan(psi) / F, so that psi' <= phi' as before.
std::vector<double> reduce_envelope(const LawDecl& law, std::span<const double> full, double F) {
  std::vector<double> v(full.begin(), full.end());
  const auto at = [&](std::string_view name) { return static_cast<std::size_t>(law.param_index(name)); };
  v[at("cohesion")] = full[at("cohesion")] / F;
  v[at("friction_angle")] = degrees(reduced_angle(radians(full[at("friction_angle")]), F));
  v[at("dilation_angle")] = degrees(reduced_angle(radians(full[at("dilation_angle")]), F));
  return v;
}

// A plane-strain plastic law on a Mohr-Coulomb envelope (docs/theory.md §10): the elastic
// constants, the envelope's c and phi with the flow's dilation angle psi <= phi, the
// plastic point's state (law::plastic_state) and the envelope's strength reduction. Plane
// strain only: the out-of-plane stress is a stress the return moves (plane stress,
// sigma_zz = 0, would be a constraint on the return instead).
LawDecl plastic_law(std::string_view name, std::string doc) {
  LawDecl d;
  d.category = Category::Material;
  d.name = name;
  d.doc = std::move(doc);
  d.plane_stress = false;
  d.params = elastic_params();
  d.params.push_back(param("cohesion", "Pa", "required", 0, kInf, "Cohesion c of the Mohr-Coulomb envelope."));
  d.params.push_back(param("friction_angle", "deg", "required", 0, 90, "Friction angle phi of the envelope.", false, true));
  d.params.push_back(param("dilation_angle", "deg", "0", 0, 90,
                           "Dilation angle psi of the plastic flow (non-associated; at most friction_angle).", false,
                           true));
  for (const StateVariable& v : plastic_state::kVariables) d.state.push_back({v.name, v.unit, v.doc});
  d.check = check_dilation;
  d.reduce = [](const LawDecl& law, std::span<const double> full, double F, const ReductionOptions&) {
    return reduce_envelope(law, full, F);
  };
  return d;
}

}  // namespace

LawDecl linear_elastic_decl() {
  LawDecl d;
  d.category = Category::Material;
  d.name = linear_elastic::kName;
  d.doc = "St Venant-Kirchhoff elasticity on the Green strain (docs/theory.md §2).";
  d.params = elastic_params();
  return d;
}

// Mohr-Coulomb plasticity with a tension cut-off, non-associated (docs/theory.md §10).
LawDecl mohr_coulomb_decl() {
  LawDecl d = plastic_law(mohr_coulomb::kName,
                          "Elastic-perfectly plastic Mohr-Coulomb with a tension cut-off and a dilation angle (docs/theory.md "
                          "§10); plane strain only.");
  ParamDecl ft = param("tensile_strength", "Pa", "c / tan(phi)", 0, kInf,
                       "Tension cut-off on the largest principal stress (default: the apex of the envelope, no "
                       "cut-off; none when phi = 0).");
  // The apex of the envelope: the cut-off then removes nothing (infinite for phi = 0).
  ft.rule = [](const LawDecl& law, std::span<const double> v) {
    return envelope_apex(law.value(v, "cohesion"), radians(law.value(v, "friction_angle")));
  };
  d.params.push_back(std::move(ft));
  d.check = [](const LawDecl& law, std::span<const double> v) {
    std::vector<ParamProblem> out = check_dilation(law, v);
    const double apex = envelope_apex(law.value(v, "cohesion"), radians(law.value(v, "friction_angle")));
    if (law.value(v, "tensile_strength") > apex)
      out.push_back({"tensile_strength", fmt::format("{} Pa is above the apex c / tan(phi) = {} Pa of the "
                                                     "Mohr-Coulomb envelope, where no tension is left to cut off",
                                                     law.value(v, "tensile_strength"), apex)});
    return out;
  };
  // The envelope's, and ft / F unless tension is kept, capped at the apex c / tan(phi),
  // which does not move with F (a cut-off above it would mean none).
  d.reduce = [](const LawDecl& law, std::span<const double> full, double F, const ReductionOptions& o) {
    namespace mc = mohr_coulomb;
    std::vector<double> v = reduce_envelope(law, full, F);
    const double ft = full[mc::tensile_strength];
    if (!o.keep_tension && std::isfinite(ft)) v[mc::tensile_strength] = ft / F;
    v[mc::tensile_strength] =
        std::min(v[mc::tensile_strength], envelope_apex(full[mc::cohesion], radians(full[mc::friction_angle])));
    return v;
  };
  return d;
}

// Drucker-Prager plasticity matched to the Mohr-Coulomb envelope in plane strain
// (docs/theory.md §10): the envelope's parameters, state and strength reduction.
LawDecl drucker_prager_decl() {
  return plastic_law(drucker_prager::kName,
                     "Elastic-perfectly plastic Drucker-Prager cone matched to the Mohr-Coulomb envelope (c, phi, psi) "
                     "in plane strain (docs/theory.md §10): the same plane-strain limit loads with associated flow, a "
                     "smooth surface and its apex as the tension limit; plane strain only.");
}

LawDecl cohesive_joint_decl() {
  LawDecl d;
  d.category = Category::Joint;
  d.name = "cohesive";
  d.doc = "Linear softening in tension and shear, Mohr-Coulomb strength with a tension cut-off, elliptical "
          "mixed-mode failure (paper eqs. 6-9, docs/theory.md §3).";
  d.params = {
      param("kn", "Pa/m", "p*E/h", 0, kInf,
            "Normal stiffness (default: penalty p*E/h with h the local element size, logged).", true),
      param("ks", "Pa/m", "kn", 0, kInf, "Shear stiffness (default: kn).", true),
      param("penalty", "", "10", 0, kInf,
            "p in the penalty rule kn = p*E/h when kn is absent; h is each joint's local element size (mean "
            "sqrt(2A) of its two triangles).",
            true),
      param("ft", "Pa", "required", 0, kInf, "Tensile strength.", true),
      param("c", "Pa", "required", 0, kInf, "Cohesion.", true),
      param("phi", "deg", "required", 0, 90, "Friction angle.", false, true),
      param("GI", "N/m", "required", 0, kInf, "Mode I fracture energy.", true),
      param("GII", "N/m", "required", 0, kInf, "Mode II fracture energy.", true)};
  d.module_state = "per end point: largest opening and slip, damage, last opening, slip and shear traction; "
                   "per joint: broken (Joints, written as cracks)";
  return d;
}

LawDecl spring_dashpot_coulomb_decl() {
  LawDecl d;
  d.category = Category::Contact;
  d.name = "spring_dashpot_coulomb";
  d.doc = "Linear normal spring with a restitution dashpot, incremental tangential spring capped by Coulomb "
          "friction (paper eqs. 1-5, docs/theory.md §4).";
  d.params = {
      param("penalty", "", "1", 0, kInf, "p_c in kn = p_c * E (E of the softer side) when kn is absent.", true),
      param("kn", "Pa", "p_c*E", 0, kInf, "Normal contact stiffness, force per unit thickness per unit overlap.", true),
      param("ks_ratio", "", "1", 0, kInf, "Tangential stiffness as a fraction of kn.", true),
      param("friction", "", "0.5", 0, kInf, "Coulomb friction coefficient mu (default for every pair of groups)."),
      param("restitution", "", "1", 0, 1,
            "Normal coefficient of restitution e of each contact's dashpot (1: no contact damping). The dashpot is "
            "sized on the reduced mass of the two touching triangles, not of the bodies, so meshed blocks rebound "
            "livelier than e: two blocks of 4 x 4 cells meeting face to face with the default kn rebound with an "
            "effective e of about 0.8 for e = 0.5.",
            true)};
  for (auto& p : d.params)  // what one pair of surface groups may set for itself (contact.pairs[])
    p.per_pair = p.name == "kn" || p.name == "friction" || p.name == "restitution";
  d.module_state = "per touching feature pair: tangential force (the contact history)";
  return d;
}

}  // namespace dsdem::law
