#include "law/strength_reduction.hpp"

#include <algorithm>
#include <cmath>

#include "law/laws.hpp"

namespace dsdem::law {

double reduced_angle(double phi, double F) { return std::atan(std::tan(phi) / F); }

JointProperties reduce_joint(const JointProperties& p, double F, const ReductionOptions& o) {
  JointProperties r = p;
  r.c = p.c / F;
  r.phi = reduced_angle(p.phi, F);
  if (!o.keep_tension) {
    r.ft = p.ft / F;
    // F < 1 may raise ft past c'/tan(phi'), where eq. 8 has no shear strength left.
    const double tan_phi = std::tan(r.phi);
    if (tan_phi > 0.0) r.ft = std::min(r.ft, 0.99 * r.c / tan_phi);
  }
  // Softening lengths kept: wn = 2 GI/ft and wsII = 2 GII/c (see the header).
  r.GI = p.GI * (r.ft / p.ft);
  r.GII = p.GII / F;
  return r;
}

Material reduce_material(const Material& m, double F, const ReductionOptions& o) {
  const LawDecl* law = material_laws().find(m.model);
  if (!law || !law->reduce || m.params.size() != law->params.size()) return m;
  Material r = m;
  r.params = law->reduce(*law, m.params, F, o);
  return r;
}

ContactProperties reduce_contact(const ContactProperties& p, double F) {
  ContactProperties r = p;
  r.mu = p.mu / F;
  return r;
}

FullStrengths full_strengths(const Model& model) {
  FullStrengths s;
  s.joints = model.joint_properties;
  s.materials = model.materials;
  s.contact_defaults = model.contact.defaults;
  for (const auto& pair : model.contact.pairs) s.contact_pairs.push_back(pair.props);
  return s;
}

FullStrengths full_strengths(const Model3& model) {
  FullStrengths s;
  s.materials = model.materials;
  return s;
}

namespace {
void reduce_materials(const FullStrengths& full, double F, const ReductionOptions& o, std::vector<Material>& out) {
  for (std::size_t k = 0; k < full.materials.size(); ++k) out[k] = reduce_material(full.materials[k], F, o);
}
}  // namespace

void apply_reduction(const FullStrengths& full, double F, const ReductionOptions& o, Model3& model) {
  reduce_materials(full, F, o, model.materials);
}

void apply_reduction(const FullStrengths& full, double F, const ReductionOptions& o, Model& model) {
  for (std::size_t k = 0; k < full.joints.size(); ++k) model.joint_properties[k] = reduce_joint(full.joints[k], F, o);
  reduce_materials(full, F, o, model.materials);
  model.contact.defaults = reduce_contact(full.contact_defaults, F);
  for (std::size_t k = 0; k < full.contact_pairs.size(); ++k)
    model.contact.pairs[k].props = reduce_contact(full.contact_pairs[k], F);
}

}  // namespace dsdem::law
