#include "fem/bulk_law.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace dsdem::fem {

namespace {

// The entry of BulkKernels from position I on that implements `decl`.
template <std::size_t I>
BulkLaw make_from(const law::LawDecl& decl, std::span<const double> params, const ElasticConstants& elastic,
                  bool plane_stress) {
  if constexpr (I == BulkKernels::size) {
    throw std::logic_error(fmt::format("material law '{}' is declared but has no kernel in fem::BulkKernels", decl.name));
  } else {
    using K = BulkKernels::Kernel<I>;
    if (decl.name != K::name) return make_from<I + 1>(decl, params, elastic, plane_stress);
    if (decl.state.size() != state_size<K>())
      throw std::logic_error(fmt::format("material law '{}' declares {} state variables, its kernel holds {}", decl.name,
                                         decl.state.size(), state_size<K>()));
    return BulkLaw(BulkKernels::Model(std::in_place_index<I>, K::make(params, elastic, plane_stress)));
  }
}

}  // namespace

BulkLaw make_bulk_law(const law::LawDecl& decl, std::span<const double> params, const ElasticConstants& elastic,
                      bool plane_stress) {
  return make_from<0>(decl, params, elastic, plane_stress);
}

}  // namespace dsdem::fem
