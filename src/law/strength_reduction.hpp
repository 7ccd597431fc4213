#pragma once
// Strength reduction by a trial factor F (docs/theory.md §9; Dawson, Roth & Drescher 1999):
// c/F, tan(phi)/F and (unless tension is kept) ft/F for every joint law, every material
// whose law has a strength (the law reduces its own parameters: LawDecl::reduce) and the
// contacts' Coulomb friction. Pure functions: the full strengths in, the reduced ones out;
// the stiffnesses are never touched.
//
// Fracture energies: the softening lengths are kept (wn = 2 GI/ft and the shear
// wsII = 2 GII/c of a joint in compression, docs/theory.md §3), so GI and GII scale like the
// strengths, by 1/F (G = strength x length / 2). The joint then softens over the same
// displacement at every F: the bisection compares one mechanism at different strengths,
// not a joint that grows more ductile (G kept, wsII x F) or more brittle (G/F^2, the
// brittleness wn/wt kept) as F grows.
#include <vector>

#include "law/registry.hpp"
#include "model/contact_properties.hpp"
#include "model/joints.hpp"
#include "model/model.hpp"
#include "model/model3d.hpp"

namespace dsdem::law {

// tan(phi') = tan(phi) / F, phi in radians.
double reduced_angle(double phi, double F);

// One cohesive joint property set. For F < 1 without keep_tension, ft is capped at
// 0.99 c'/tan(phi') so that the shear strength at the tension cut-off c' - ft' tan(phi')
// stays positive (eq. 8, validate()).
JointProperties reduce_joint(const JointProperties& p, double F, const ReductionOptions& o = {});
// One material: its law's reduction of its parameters (LawDecl::reduce; Mohr-Coulomb:
// c/F, phi' and psi' = atan(tan(psi)/F), so psi' <= phi' as before, and ft/F capped at the
// envelope's apex c/tan(phi), law/laws.cpp). A law without a strength (linear elastic), or
// a material made in code without its parameters, is returned as it is.
Material reduce_material(const Material& m, double F, const ReductionOptions& o = {});
// Contact friction mu/F: a broken joint's strength is its contacts' friction.
ContactProperties reduce_contact(const ContactProperties& p, double F);

// The strengths of a model at full strength (F = 1), kept to reduce from at every trial.
struct FullStrengths {
  std::vector<JointProperties> joints;
  std::vector<Material> materials;
  ContactProperties contact_defaults;
  std::vector<ContactProperties> contact_pairs;
};
FullStrengths full_strengths(const Model& model);
// A 3D model's: its materials (it has no joints or contact yet).
FullStrengths full_strengths(const Model3& model);
// Writes the strengths of `full` reduced by F into the model (its joint properties,
// materials and contact parameters); everything else is left alone.
void apply_reduction(const FullStrengths& full, double F, const ReductionOptions& o, Model& model);
void apply_reduction(const FullStrengths& full, double F, const ReductionOptions& o, Model3& model);

}  // namespace dsdem::law
