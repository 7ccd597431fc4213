#pragma once
// State variables that laws declare (law/registry.hpp), one array of doubles per
// variable over all items (triangles or joints), named after the declaration. Empty when
// no law in use declares state, so a purely elastic model carries nothing.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "model/types.hpp"

namespace dsdem {

struct StateArrays {
  std::vector<std::string> names;           // as declared, e.g. "plastic_strain_xx"
  std::vector<std::string> units;           // SI unit text, "" when dimensionless
  std::vector<std::vector<double>> values;  // values[column][item]

  bool empty() const { return names.empty(); }
  std::size_t columns() const { return names.size(); }
  // The column of a variable, or kNoIndex.
  Index find(std::string_view name) const {
    for (std::size_t k = 0; k < names.size(); ++k)
      if (names[k] == name) return static_cast<Index>(k);
    return kNoIndex;
  }
  // The column of a variable, added (zeros over n items) when new. Two laws that declare
  // the same name share its column.
  Index add(std::string_view name, std::string_view unit, std::size_t n) {
    if (const Index k = find(name); k != kNoIndex) return k;
    names.emplace_back(name);
    units.emplace_back(unit);
    values.emplace_back(n, 0.0);
    return static_cast<Index>(names.size() - 1);
  }
};

}  // namespace dsdem
