#pragma once
// The viscous-spring boundary of a 3D model (docs/theory.md §5, §14): each node of the named
// surfaces with its tributary area (a third of each boundary triangle's), the area-weighted
// outward normal, the springs and dashpots with aN = 4/3, aT = 2/3, and its free-field column
// from the model's base to the top surface above it.
#include <optional>
#include <string>
#include <vector>

#include "boundary/boundary_setup.hpp"
#include "model/model3d.hpp"

namespace dsdem::boundary {

using BoundaryNode3 = BoundaryNodeD<3>;

// One named surface of the boundary: R given, or the distance from a scattering centre.
struct ViscousSurface {
  std::string group;
  std::optional<double> R;
  std::optional<Vec3> scattering_centre;
  bool free_field = true;
};

// The highest point of the model where the vertical line at (x, y) meets its outer surface,
// in the reference configuration; -infinity where the line misses the model. A uniform grid
// over the outer triangles' plan boxes; a query scans one cell.
class SurfaceProfile3 {
 public:
  SurfaceProfile3(const std::vector<Vec3>& X, const std::vector<std::array<Index, 4>>& tetrahedra);
  double top(double x, double y) const;

 private:
  std::size_t cell(double x, double y) const;
  double x0_ = 0.0, y0_ = 0.0, width_ = 1.0;
  std::size_t nx_ = 1, ny_ = 1;
  std::vector<std::size_t> offset_;             // cell c holds faces_[offset_[c] .. offset_[c + 1])
  std::vector<std::array<Vec3, 3>> faces_;
};

// The boundary nodes of `surfaces`; a node on two surfaces takes both areas and the averaged
// normal, and the first surface's R. Throws std::invalid_argument naming a group that is
// not a surface of the model's outside, or a surface without R or centre.
std::vector<BoundaryNode3> build_viscous_boundary_3d(const Model3& model, const std::vector<ViscousSurface>& surfaces);

}  // namespace dsdem::boundary
