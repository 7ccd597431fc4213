#pragma once
// Viscous-spring boundary nodes of a model (docs/theory.md §5): tributary length, outward
// normal, the medium behind them, the free-field column each one sees, and the static
// reaction kept as a load when the boundary replaces the supports of a gravity stage.
#include <array>
#include <vector>

#include "boundary/free_field.hpp"
#include "boundary/viscous_spring.hpp"
#include "io/scenario.hpp"
#include "model/model.hpp"

namespace dsdem::boundary {

// A node of the viscous-spring boundary of a model of dimension D (2 or 3).
template <int D>
struct BoundaryNodeD {
  using Vec = VecD<D>;
  Index node = kNoIndex;
  Vec normal = Vec::Zero();  // unit outward normal
  double area = 0.0;         // tributary area, m^2 (2D: tributary length x thickness; per unit thickness: m)
  ViscousSpringCoefficients coef;
  ElasticMedium medium;
  double height = 0.0;  // height above the model base (along y in 2D, z in 3D), m
  double H = 0.0;       // height of the free-field column above this point's base, m
  bool free_field = true;
  Vec static_force = Vec::Zero();  // reaction of the previous stage's supports, kept as a load, N
  Vec u_ref = Vec::Zero();         // displacement when the boundary was attached, m
  Vec u_prev = Vec::Zero();        // displacement before this step's drift, m (solver scratch, for the work)
};
using BoundaryNode = BoundaryNodeD<2>;

// Height of the model's top outline above each x, in the reference configuration: the
// highest point where the vertical line at x meets a triangle edge (docs/theory.md §5: the
// free-field column runs from the base to the free surface above a boundary point).
// Built once in O(triangles) over a uniform grid of x-columns; a query scans one column.
class SurfaceProfile {
 public:
  SurfaceProfile(const std::vector<Vec2>& X, const std::vector<std::array<Index, 3>>& conn);
  // -infinity where the vertical line at x misses the mesh.
  double top(double x) const;

 private:
  std::size_t column(double x) const;
  double x0_ = 0.0, width_ = 1.0;
  std::size_t columns_ = 1;
  std::vector<std::size_t> offset_;              // column c holds edges_[offset_[c] .. offset_[c + 1])
  std::vector<std::array<Vec2, 2>> edges_;       // end points, the smaller x first
};

// All nodes of the viscous-spring curve groups in `boundaries`. Throws io::ScenarioError
// (naming the scenario key) when a group is not a curve on the model's outline.
std::vector<BoundaryNode> build_viscous_boundary(const Model& model, const std::vector<io::BoundarySpec>& boundaries);

}  // namespace dsdem::boundary
