#include "solver/constraints.hpp"

#include <map>
#include <type_traits>

namespace dsdem::solver {

template <class M>
std::vector<PrescribedDof> build_constraints(const M& model, const std::vector<io::BoundarySpec>& boundaries,
                                             double t_start) {
  constexpr int D = std::remove_cvref_t<decltype(model.nodes.X[0])>::RowsAtCompileTime;
  // (node, dir) -> dof; std::map keeps the output order deterministic.
  std::map<std::pair<Index, int>, PrescribedDof> dofs;
  for (const auto& b : boundaries) {
    const Index g = model.find_group(b.group);
    if (g == kNoIndex) continue;  // validated before: cannot happen
    const auto hx = b.x ? std::make_shared<const io::TimeHistory>(*b.x) : nullptr;
    const auto hy = b.y ? std::make_shared<const io::TimeHistory>(*b.y) : nullptr;
    const auto hz = b.z ? std::make_shared<const io::TimeHistory>(*b.z) : nullptr;
    for (Index n : model.groups[static_cast<std::size_t>(g)].nodes) {
      auto set = [&](int dir, PrescribedDof::Kind kind, std::shared_ptr<const io::TimeHistory> h) {
        PrescribedDof d;
        d.node = n;
        d.dir = dir;
        d.kind = kind;
        d.history = h;
        d.u_start = model.nodes.u[n][dir];
        d.t_start = t_start;
        dofs[{n, dir}] = d;
      };
      switch (b.type) {
        case io::BoundaryType::Fixed:
          for (int dir = 0; dir < D; ++dir) set(dir, PrescribedDof::Fixed, nullptr);
          break;
        case io::BoundaryType::Roller:
          set(b.direction, PrescribedDof::Fixed, nullptr);
          break;
        case io::BoundaryType::Velocity:
        case io::BoundaryType::Displacement: {
          const auto kind = b.type == io::BoundaryType::Velocity ? PrescribedDof::Velocity : PrescribedDof::Displacement;
          if (hx) set(0, kind, hx);
          if (hy) set(1, kind, hy);
          if (D == 3 && hz) set(2, kind, hz);
          break;
        }
        case io::BoundaryType::Free:
        case io::BoundaryType::ViscousSpring:  // released: the boundary module acts on it
          for (int dir = 0; dir < D; ++dir) dofs.erase({n, dir});
          break;
      }
    }
  }
  std::vector<PrescribedDof> out;
  out.reserve(dofs.size());
  for (auto& [key, d] : dofs) out.push_back(d);
  return out;
}

template std::vector<PrescribedDof> build_constraints(const Model&, const std::vector<io::BoundarySpec>&, double);
template std::vector<PrescribedDof> build_constraints(const Model3&, const std::vector<io::BoundarySpec>&, double);

double prescribed_velocity(const PrescribedDof& d, double t) {
  switch (d.kind) {
    case PrescribedDof::Fixed: return 0.0;
    case PrescribedDof::Velocity: return d.history->at(t - d.t_start);
    case PrescribedDof::Displacement: return d.history->rate_at(t - d.t_start);
  }
  return 0.0;
}

double prescribed_acceleration(const PrescribedDof& d, double t) {
  if (d.kind == PrescribedDof::Velocity) return d.history->rate_at(t - d.t_start);
  return 0.0;
}

}  // namespace dsdem::solver
