#pragma once
// The bulk laws' kernels in one closed list (docs/developer-guide.md §5). Each material's
// law picks its entry once, when the solver is built (make_bulk_law); the element loop then
// dispatches every triangle through that entry: a switch on its position in the list, no
// law's name compared and no virtual call, each kernel inlined into the loop.
#include <algorithm>
#include <array>
#include <bit>
#include <exception>
#include <span>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <variant>

#include "fem/bulk_kernel.hpp"
#include "fem/cst.hpp"
#include "fem/drucker_prager.hpp"
#include "fem/mohr_coulomb.hpp"
#include "fem/tet4.hpp"
#include "law/laws.hpp"

namespace dsdem::fem {

// St Venant-Kirchhoff elasticity: no state; its triangle is cst.hpp's kernel.
struct LinearElasticKernel {
  static constexpr std::string_view name = law::linear_elastic::kName;
  using Model = ElasticConstants;
  static constexpr int kDissipation = -1;
  static Model make(std::span<const double>, const ElasticConstants& elastic, bool) { return elastic; }
};

template <class... Kernels>
struct KernelList;

// Every bulk law's kernel, one entry per law (bulk_kernel.hpp says what an entry is).
using BulkKernels = KernelList<LinearElasticKernel, MohrCoulombKernel, DruckerPragerKernel>;

template <class K>
concept StatefulKernel = requires { typename K::State; };
// A law's kernel runs in 3D: the elastic tetrahedron, or a 3D update of its state.
template <class K>
concept Stateful3DKernel = requires { typename K::State3D; };
template <class K>
constexpr bool runs_in_3d() {
  return Stateful3DKernel<K> || !StatefulKernel<K>;
}
template <class K>
constexpr std::size_t state_size_3d() {
  if constexpr (Stateful3DKernel<K>) {
    static_assert(K::kState3D <= kMaxBulkState3D);
    return K::kState3D;
  } else {
    return 0;
  }
}
template <class K>
constexpr int dissipation_3d() {
  if constexpr (Stateful3DKernel<K>) return K::kDissipation3D;
  else return -1;
}

// How many doubles a kernel's state holds.
template <class K>
constexpr std::size_t state_size() {
  if constexpr (StatefulKernel<K>) {
    static_assert(std::is_trivially_copyable_v<typename K::State> && sizeof(typename K::State) % sizeof(double) == 0);
    static_assert(sizeof(typename K::State) / sizeof(double) <= kMaxBulkState);
    return sizeof(typename K::State) / sizeof(double);
  } else {
    return 0;
  }
}

template <class... Kernels>
struct KernelList {
  static constexpr std::size_t size = sizeof...(Kernels);
  template <std::size_t I>
  using Kernel = std::tuple_element_t<I, std::tuple<Kernels...>>;
  using Model = std::variant<typename Kernels::Model...>;  // one alternative per kernel, in order
  // What the solver asks of a kernel outside the element loop, by position.
  static constexpr std::array<std::string_view, size> names{Kernels::name...};
  static constexpr std::array<std::size_t, size> state_sizes{fem::state_size<Kernels>()...};
  static constexpr std::array<int, size> dissipations{Kernels::kDissipation...};
  // The same in 3D (the tetrahedron); a law whose kernel does not run in 3D is refused there.
  static constexpr std::array<bool, size> in_3d{fem::runs_in_3d<Kernels>()...};
  static constexpr std::array<std::size_t, size> state_sizes_3d{fem::state_size_3d<Kernels>()...};
  static constexpr std::array<int, size> dissipations_3d{fem::dissipation_3d<Kernels>()...};
};

// A material's bulk law as the element loop sees it: its kernel's position in BulkKernels
// and that kernel's model.
class BulkLaw {
 public:
  BulkLaw() = default;  // linear elastic, zero constants
  explicit BulkLaw(BulkKernels::Model model) : model_(std::move(model)) {}

  std::size_t index() const { return model_.index(); }
  template <std::size_t I>
  const typename BulkKernels::Kernel<I>::Model& model() const {
    return *std::get_if<I>(&model_);
  }
  std::string_view name() const { return BulkKernels::names[index()]; }  // the law's
  std::size_t state_size() const { return BulkKernels::state_sizes[index()]; }
  // The position in the state of the accumulated dissipation, or -1.
  int dissipation() const { return BulkKernels::dissipations[index()]; }
  // The same for the tetrahedron (3D); runs_in_3d() false: the law is plane-only.
  bool runs_in_3d() const { return BulkKernels::in_3d[index()]; }
  std::size_t state_size_3d() const { return BulkKernels::state_sizes_3d[index()]; }
  int dissipation_3d() const { return BulkKernels::dissipations_3d[index()]; }

 private:
  BulkKernels::Model model_;
};

// The bulk law of a material of the declared law `decl`, from its parameter values in
// declaration order (units as declared) and its elastic constants: the kernel that
// implements `decl`. Throws std::invalid_argument for inadmissible parameters, and
// std::logic_error for a declared law without a kernel or whose state the kernel does not hold.
BulkLaw make_bulk_law(const law::LawDecl& decl, std::span<const double> params, const ElasticConstants& elastic,
                      bool plane_stress);

// The total Lagrangian CST (cst.hpp) with a bulk law that has state: the same deformation
// gradient, nodal forces P = F S and Cauchy stress as the elastic kernel, with S from the
// law's update from `start`, the state at the step's start, to `end` (a separate record:
// evaluating twice from the same start gives the same bits). The initial stress's
// out-of-plane part is an elastic stage's (plane_strain_sigma_zz). Stiffness-proportional
// Rayleigh damping stays the viscous stress beta D Edot on the elastic D (docs/theory.md §6).
template <class K>
[[gnu::always_inline]] inline BulkResponse triangle_internal_force_law(const TriangleInput& in,
                                                                       const typename K::Model& m,
                                                                       const typename K::State& start,
                                                                       typename K::State& end, TriangleResponse& out,
                                                                       std::array<Vec2, 3>& damping_force) {
  const double S0_zz = plane_strain_sigma_zz(in.S0, m.elastic);
  const Mat2 F = deformation_gradient(in.x[0], in.x[1], in.x[2], in.Dm_inv);
  out.detF = F.determinant();
  const Vec3 E = green_strain(F);
  const BulkResponse r = K::update(m, E, in.S0, S0_zz, start, end);
  const double scale = in.area0 * in.thickness;
  detail::nodal_forces(F * detail::to_tensor(r.S), in.Dm_inv, scale, out.force);
  out.green = E;
  if (in.cauchy) out.cauchy = cauchy_from_pk2(F, r.S);
  out.strain_energy = scale * r.strain_energy;
  if (in.beta > 0.0) {
    const Mat2 Fdot = deformation_gradient(in.v[0], in.v[1], in.v[2], in.Dm_inv);
    const Vec3 Sd = in.beta * svk_stress(strain_rate(F, Fdot), m.elastic);
    detail::nodal_forces(F * detail::to_tensor(Sd), in.Dm_inv, scale, damping_force);
  } else {
    damping_force = {Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  }
  return r;
}

// One triangle through its material's law: the elastic kernel, or the law's update from
// the state at the step's start (`start`, the law's state_size() doubles); the state at
// the step's end goes to store(const std::array<double, n>&), n the law's state size. The dispatch is a
// chain of tests of the kernel's position, I = 0, 1, ..., each kernel inlined straight into
// the element loop (not through a generic lambda, with which GCC keeps the triangle's
// input in memory).
template <std::size_t I = 0, class Store>
[[gnu::always_inline]] inline void triangle_response(const BulkLaw& law, const TriangleInput& in, const double* start,
                                                     TriangleResponse& out, std::array<Vec2, 3>& damping_force,
                                                     Store&& store) {
  using K = BulkKernels::Kernel<I>;
  if constexpr (I + 1 < BulkKernels::size) {
    if (law.index() != I) return triangle_response<I + 1>(law, in, start, out, damping_force, store);
  }
  const typename K::Model& m = law.template model<I>();
  if constexpr (StatefulKernel<K>) {
    using Doubles = std::array<double, fem::state_size<K>()>;
    Doubles s0;
    std::copy_n(start, s0.size(), s0.begin());
    typename K::State end;
    triangle_internal_force_law<K>(in, m, std::bit_cast<typename K::State>(s0), end, out, damping_force);
    store(std::bit_cast<Doubles>(end));
  } else {
    triangle_internal_force(in, m, out, damping_force);
  }
}

// f(std::integral_constant<std::size_t, n>{}) with n the state size of the law's kernel,
// a constant of each kernel.
template <std::size_t I = 0, class F>
[[gnu::always_inline]] inline void with_state_size(const BulkLaw& law, F&& f) {
  if constexpr (I + 1 < BulkKernels::size) {
    if (law.index() != I) return with_state_size<I + 1>(law, f);
  }
  f(std::integral_constant<std::size_t, fem::state_size<BulkKernels::Kernel<I>>()>{});
}

// The tetrahedron (tet4.hpp) with a bulk law that has a 3D state: the same deformation
// gradient, nodal forces P = F S and Cauchy stress as the elastic kernel, with S from the
// law's 3D update from `start` (the state at the step's start) to `end`. Stiffness-
// proportional Rayleigh damping stays the viscous stress beta D Edot on the elastic D.
template <class K>
[[gnu::always_inline]] inline BulkResponse3D tet_internal_force_law(const TetInput& in, const typename K::Model& m,
                                                                    const typename K::State3D& start,
                                                                    typename K::State3D& end, TetResponse& out,
                                                                    std::array<Vec3, 4>& damping_force) {
  const Mat3 F = deformation_gradient(in.x[0], in.x[1], in.x[2], in.x[3], in.Dm_inv);
  out.detF = F.determinant();
  const Vec6 E = green_strain(F);
  const BulkResponse3D r = K::update_3d(m, E, in.S0, start, end);
  detail::tet_nodal_forces(F * detail::to_tensor(r.S), in.Dm_inv, in.volume0, out.force);
  out.green = E;
  if (in.cauchy) out.cauchy = cauchy_from_pk2(F, r.S);
  out.strain_energy = in.volume0 * r.strain_energy;
  if (in.beta > 0.0) {
    const Mat3 Fdot = deformation_gradient(in.v[0], in.v[1], in.v[2], in.v[3], in.Dm_inv);
    const Vec6 Sd = in.beta * svk_stress(strain_rate(F, Fdot), m.elastic);
    detail::tet_nodal_forces(F * detail::to_tensor(Sd), in.Dm_inv, in.volume0, damping_force);
  } else {
    damping_force = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  }
  return r;
}

// One tetrahedron through its material's law, as triangle_response: the elastic kernel, or
// the law's 3D update from `start` (state_size_3d() doubles) to `end` (as many).
template <std::size_t I = 0>
[[gnu::always_inline]] inline void tet_response(const BulkLaw& law, const TetInput& in, const double* start,
                                                double* end, TetResponse& out, std::array<Vec3, 4>& damping_force) {
  using K = BulkKernels::Kernel<I>;
  if constexpr (I + 1 < BulkKernels::size) {
    if (law.index() != I) return tet_response<I + 1>(law, in, start, end, out, damping_force);
  }
  const typename K::Model& m = law.template model<I>();
  if constexpr (Stateful3DKernel<K>) {
    typename K::State3D s_end;
    tet_internal_force_law<K>(in, m, K::load_3d(start), s_end, out, damping_force);
    K::store_3d(s_end, end);
  } else if constexpr (!StatefulKernel<K>) {
    tet_internal_force(in, m, out, damping_force);
  } else {
    std::terminate();  // a plane-only law: refused before any tetrahedron is built with it
  }
}

}  // namespace dsdem::fem
