#pragma once
// The simulated model as structures of arrays (docs/developer-guide.md §1): contiguous node and
// element fields, no object per node. Built by mesh/model_builder from a Gmsh mesh
// and a scenario; read and written by the solver phases.
#include <string>
#include <vector>

#include "model/contact_properties.hpp"
#include "model/joints.hpp"
#include "model/state_arrays.hpp"
#include "model/types.hpp"

namespace dsdem {

// Zone of a triangle (docs/theory.md §1): A breaks and collides, B is plain FEM, C is FEM
// whose surface takes part in contact.
enum class Zone : std::uint8_t { Discrete = 0, Bedrock = 1, ContactBedrock = 2 };

// The nodes of a model of dimension D (2 or 3): the same arrays and the same integrator
// (solver/integrator.hpp) in both.
template <int D>
struct NodeArrays {
  using Vec = VecD<D>;
  std::vector<Vec> X;    // reference position, m
  std::vector<Vec> u;    // displacement, m (current position x = X + u)
  std::vector<Vec> v;    // velocity, m/s
  // Acceleration, m/s^2, between steps (outputs, gauges, checkpoint, the next step's
  // first half-kick). During a step the solver sums the nodal forces in this same array
  // (N; per unit thickness in plane strain) and finish_velocities() divides them by the
  // masses in place: the force of a step is dead once its acceleration exists, so one
  // array holds both (8 D bytes per node).
  std::vector<Vec> a;
  std::vector<double> m;  // lumped mass, kg
  std::vector<Index> origin;       // the mesh node this node was split from (joint insertion)
  // Prescribed motions are solver::PrescribedDof lists (per stage), not per-node arrays.

  std::size_t size() const { return X.size(); }
  void resize(std::size_t n) {
    X.resize(n, Vec::Zero());
    u.resize(n, Vec::Zero());
    v.resize(n, Vec::Zero());
    a.resize(n, Vec::Zero());
    m.resize(n, 0.0);
    origin.resize(n, kNoIndex);
  }
  Vec x(Index i) const { return X[i] + u[i]; }
};
using Nodes = NodeArrays<2>;

struct Triangles {
  std::vector<std::array<Index, 3>> conn;  // counter-clockwise node indices
  std::vector<Index> group;                // index into Model::groups (a surface group)
  std::vector<Index> material;             // index into Model::materials
  std::vector<Zone> zone;
  std::vector<Mat2> Dm_inv;   // inverse of the reference edge matrix [X1-X0, X2-X0]
  std::vector<double> area0;  // reference area, m^2
  // Output buffers of the current state, empty unless filled (48 B per
  // triangle): Solver::update_stress() fills them for a field frame and
  // release_stress() empties them again; a solver whose stress is not on demand (the
  // default, used by tests) keeps them sized and writes them every step.
  std::vector<Vec3> stress;   // Cauchy stress (xx, yy, xy), Pa
  std::vector<Vec3> strain;   // Green-Lagrange strain (xx, yy, 2*xy engineering shear)
  // Initial (in-situ) stress kept from an earlier stage, Pa; empty = zero everywhere (the
  // usual case: 24 B per triangle saved). Read it through initial_stress().
  std::vector<Vec3> stress0;
  // State variables of the material laws in use (plastic strains, ...), one column per
  // declared variable, zeros at first; empty for a purely elastic model.
  StateArrays state;

  std::size_t size() const { return conn.size(); }
  Vec3 initial_stress(std::size_t t) const { return stress0.empty() ? Vec3(Vec3::Zero()) : stress0[t]; }
  void resize(std::size_t n) {
    conn.resize(n, {kNoIndex, kNoIndex, kNoIndex});
    group.resize(n, kNoIndex);
    material.resize(n, kNoIndex);
    zone.resize(n, Zone::Bedrock);
    Dm_inv.resize(n, Mat2::Identity());
    area0.resize(n, 0.0);
  }
};

enum class GroupKind : std::uint8_t { Surface = 2, Curve = 1, Point = 0 };

// A Gmsh physical group, after joint insertion: the model's triangles (surfaces),
// the model's nodes on it (curves and points; every copy of a split node), and the
// mesh edges on it (curves, as pairs of original mesh node ids).
struct Group {
  std::string name;
  GroupKind kind = GroupKind::Surface;
  int gmsh_tag = -1;
  std::vector<Index> triangles;
  std::vector<Index> nodes;
  std::vector<std::array<Index, 2>> mesh_edges;
};

// A bulk material: its law (by name, from law/registry) and the law's parameters. The
// elastic constants are also held by name, for the elastic kernel and the time step.
struct Material {
  std::string name;
  std::string model = "linear_elastic";
  double E = 0.0;       // Young's modulus, Pa
  double nu = 0.0;      // Poisson's ratio
  double rho = 0.0;     // density, kg/m^3
  bool plane_stress = false;
  double thickness = 1.0;  // m (plane strain: unit thickness)
  Index law = 0;  // index of `model` in law::material_laws() (0: linear_elastic)
  // The law's parameters in its declaration order, in the declared units (angles in
  // degrees); E, nu, rho are among them. Empty for a material made in code (tests).
  std::vector<double> params;
  // Columns of Triangles::state holding the law's declared state variables, in
  // declaration order; set by the model builder, empty when the law declares none.
  std::vector<Index> state_columns;
  double lambda() const {
    return plane_stress ? E * nu / (1.0 - nu * nu) : E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  }
  double mu() const { return E / (2.0 * (1.0 + nu)); }
  double p_wave_modulus() const { return lambda() + 2.0 * mu(); }
  double cp() const { return std::sqrt(p_wave_modulus() / rho); }
  double cs() const { return std::sqrt(mu() / rho); }
};

}  // namespace dsdem

namespace dsdem {

// Contact set-up of a model (docs/theory.md §4): which triangles are spheropolygons, their
// rounding radii, which continuous body they belong to, and the pair parameters.
struct ContactSetup {
  bool enabled = false;
  std::vector<std::uint8_t> active;  // per triangle: zones A and C
  std::vector<double> radius;        // per triangle: rounding radius, m
  std::vector<Index> body;           // per triangle: continuous body id (zone C), -1 for discrete
  ContactProperties defaults;  // kn, ks already times the thickness
  struct Pair {
    Index group_a, group_b;
    ContactProperties props;
  };
  std::vector<Pair> pairs;
  double max_kn = 0.0;  // stiffest pair, for the stable time step
  double skin = 0.0;    // 0 = automatic
  bool output = false;
};

// Everything the solver advances. Joints and contact state live in their own modules'
// arrays, owned here too once those modules are wired in.
struct Model {
  Nodes nodes;
  Triangles triangles;
  std::vector<Group> groups;
  std::vector<Material> materials;
  Joints joints;                                // cohesive joints of the discrete zones
  std::vector<JointProperties> joint_properties;
  ContactSetup contact;
  bool plane_stress = false;
  double thickness = 1.0;  // m

  Index find_group(const std::string& name) const {
    for (std::size_t i = 0; i < groups.size(); ++i)
      if (groups[i].name == name) return static_cast<Index>(i);
    return kNoIndex;
  }
};

}  // namespace dsdem
