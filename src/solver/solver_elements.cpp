// The element and joint phases of the step (docs/theory.md §1 phases 3-4) as per-item kernels
// for the execution layer's region (exec::ElementRegion), and the stress on demand.
#include "fem/bulk_law.hpp"
#include "solver/solver.hpp"

namespace dsdem::solver {

namespace {
constexpr int kInverted = 1;  // the element region's status bit: some element had det F <= 0
}  // namespace

// The kernels of one step's element region: each item's physics, and where its forces go
// (exec::NodeScatter). What a triangle needs is fixed for the whole pass: stiffness damping
// (beta > 0), some material whose law has state, the water at rest, the stress stored each
// step. As template arguments, each pass's kernel tests and writes only what it uses.
template <bool Damping, bool LawState, bool Water, bool StoreStress>
struct ElementKernels {
  Solver& s;
  Nodes& n;
  Triangles& tri;
  Joints& J;
  Vec2* const damping_sum;  // the nodes' damping forces, when booked
  const std::array<Vec2, 2>* const joint_force;
  Index broken_now = 0;

  // One triangle (docs/theory.md §2): stress (when stored), strain energy, nodal forces and,
  // with Damping, the stiffness-damping forces into damping (else zeros, read by nobody).
  [[gnu::always_inline]] fem::TriangleResponse element(std::size_t t, std::array<Vec2, 3>& damping) const {
    fem::TriangleInput in = s.triangle_input(t);
    if constexpr (Damping) {  // without, in.beta stays 0: the kernel reads no v
      for (int k = 0; k < 3; ++k) in.v[k] = n.v[tri.conn[t][k]];
      in.beta = s.settings_.beta;
    }
    in.cauchy = StoreStress;
    fem::TriangleResponse r;
    const Index mat = tri.material[t];
    respond(t, in, mat, r, damping);
    // The water at rest (docs/theory.md §8): the pore pressure's part of the total stress and
    // the tractions on this triangle's exposed edges and joint faces.
    if constexpr (Water) s.water_.add(t, in.x, tri.conn[t], mat, n, J, s.settings_.dt, s.water_booking_, r.force);
    if constexpr (StoreStress) {
      tri.stress[t] = r.cauchy;
      tri.strain[t] = r.green;
    }
    s.element_strain_energy_[t] = r.strain_energy;
    return r;
  }
  // The material's response through its law (fem/bulk_law.hpp): a law with state from the
  // state at the step's start to its end, written to the triangle's state columns.
  [[gnu::always_inline]] void respond(std::size_t t, const fem::TriangleInput& in, Index mat, fem::TriangleResponse& r,
                                      std::array<Vec2, 3>& damping) const {
    if constexpr (LawState) {
      const Solver::MaterialLaw& law = s.laws_[mat];
      auto& v = tri.state.values;
      fem::triangle_response(law.kernel, in, &s.law_start_[s.law_stride_ * t], r, damping, [&](const auto& end) {
        for (std::size_t k = 0; k < end.size(); ++k) v[law.columns[k]][t] = end[k];
      });
    } else {
      fem::triangle_internal_force(in, s.elastic_[mat], r, damping);
    }
  }
  // shared() and own() inline every piece of the kernel (flatten): with a kernel per pass the
  // unit outgrows GCC's inlining budget, which would leave calls that pass the triangle
  // through memory.
  [[gnu::flatten]] int shared(std::size_t slot) {
    std::array<Vec2, 3> no_damping;  // without Damping: the kernel's zeros, read by nobody
    const fem::TriangleResponse r =
        element(s.scatter_.shared_triangle(slot), Damping ? s.scatter_.shared_damping_force(slot) : no_damping);
    s.scatter_.shared_force(slot) = r.force;
    return r.detF > 0.0 ? 0 : kInverted;
  }
  // Cohesive joints (docs/theory.md §3), breaking for good; any thread may take any block.
  void joint_blocks(std::size_t b0, std::size_t b1) {
    evaluate_joints(n, J, s.settings_.failure, s.model_.thickness, s.joint_buf_, broken_now, b0, b1);
  }
  [[gnu::flatten]] int own(std::size_t t0, std::size_t t1) const {
    int bits = 0;
    for (std::size_t t = t0; t < t1; ++t) {
      if (!s.scatter_.is_own(t)) continue;
      std::array<Vec2, 3> df;
      const fem::TriangleResponse r = element(t, df);
      if (!(r.detF > 0.0)) bits |= kInverted;
      s.scatter_.add_own(t, tri.conn[t], r.force, df, Damping, joint_force, s.forces_.scatter().data(), damping_sum);
    }
    return bits;
  }
  void gathered(std::size_t g) const { s.scatter_.gather(g, joint_force, s.forces_.scatter().data(), damping_sum); }
};

namespace {
// f.template operator()<b...>() with the run-time bools `flags` as template arguments.
template <bool... Fixed, class F>
void with_flags(F&& f) {
  f.template operator()<Fixed...>();
}
template <bool... Fixed, class F, class... Bools>
void with_flags(F&& f, bool first, Bools... flags) {
  if (first) with_flags<Fixed..., true>(f, flags...);
  else with_flags<Fixed..., false>(f, flags...);
}
}  // namespace

void Solver::add_element_and_joint_forces() {
  auto& J = model_.joints;
  const bool joints = J.size() > 0;
  Vec2* const damping_sum = damped() ? damping_force_.data() : nullptr;
  const std::array<Vec2, 2>* const joint_force = joint_buf_.force.empty() ? nullptr : joint_buf_.force.data();
  int bits = 0;
  Index broken_now = 0;
  with_flags(
      [&]<bool Damping, bool LawState, bool Water, bool StoreStress>() {
        ElementKernels<Damping, LawState, Water, StoreStress> k{*this, model_.nodes, model_.triangles, J, damping_sum,
                                                                joint_force};
        bits = element_region_.run(team_, model_.nodes.size(), scatter_, joints ? joint_blocks(J.size()) : 0, k);
        broken_now = k.broken_now;
      },
      settings_.beta > 0.0, any_law_state_, water_.active(), !stress_on_demand_);
  inverted_ = (bits & kInverted) != 0;
  if (joints) {
    energy_.joint_elastic = joint_buf_.energy();
    energy_.fracture_dissipated += joint_buf_.dissipation();
    broken_joints_ += broken_now;
    if (broken_now) record_new_breaks(model_.nodes, J, time_);
  }
}

void Solver::set_stress_on_demand(bool on) {
  stress_on_demand_ = on;
  auto& tri = model_.triangles;
  if (on) {
    release_stress();
  } else if (tri.stress.size() != tri.size()) {  // the element loop writes them every step
    tri.stress.assign(tri.size(), Vec3::Zero());
    tri.strain.assign(tri.size(), Vec3::Zero());
  }
}

void Solver::compute_stress(std::vector<Vec3>& stress, std::vector<Vec3>& strain) const {
  const auto& tri = model_.triangles;
  stress.resize(tri.size());
  strain.resize(tri.size());
  // The element loop's kernel on the same inputs (positions unchanged since the step):
  // the same stress and strain bits. Damping does not enter the Cauchy stress.
  exec::parallel_for(team_, tri.size(), [&](std::size_t t) {
    const fem::TriangleInput in = triangle_input(t);
    fem::TriangleResponse r;
    std::array<Vec2, 3> no_damping;
    const Index mat = tri.material[t];
    if (any_law_state_) {  // the step's update again, from the same start
      const MaterialLaw& law = laws_[mat];
      fem::triangle_response(law.kernel, in, &law_start_[law_stride_ * t], r, no_damping, [](const auto&) {});
    } else {
      fem::triangle_internal_force(in, elastic_[mat], r, no_damping);
    }
    stress[t] = r.cauchy;
    strain[t] = r.green;
  });
}

void Solver::update_stress() { compute_stress(model_.triangles.stress, model_.triangles.strain); }

void Solver::release_stress() {
  if (!stress_on_demand_) return;  // the steps write them
  std::vector<Vec3>().swap(model_.triangles.stress);
  std::vector<Vec3>().swap(model_.triangles.strain);
}

}  // namespace dsdem::solver
