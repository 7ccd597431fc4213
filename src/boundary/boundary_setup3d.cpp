#include "boundary/boundary_setup3d.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace dsdem::boundary {

namespace {

using Face = std::array<Index, 3>;
Face sorted(Face f) {
  std::sort(f.begin(), f.end());
  return f;
}

// The faces of the tetrahedra that belong to one tetrahedron only (the outer surface), each
// with its tetrahedron and the corner opposite it.
struct OuterFace {
  Index tet;
  Index opposite;
};
std::map<Face, OuterFace> outer_faces(const std::vector<std::array<Index, 4>>& tets) {
  std::map<Face, OuterFace> faces;
  std::map<Face, int> count;
  for (std::size_t t = 0; t < tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      const Face f = sorted({tets[t][(k + 1) % 4], tets[t][(k + 2) % 4], tets[t][(k + 3) % 4]});
      if (++count[f] == 1) faces[f] = {static_cast<Index>(t), tets[t][k]};
      else faces.erase(f);
    }
  return faces;
}

}  // namespace

SurfaceProfile3::SurfaceProfile3(const std::vector<Vec3>& X, const std::vector<std::array<Index, 4>>& tetrahedra) {
  for (const auto& [f, o] : outer_faces(tetrahedra)) faces_.push_back({X[f[0]], X[f[1]], X[f[2]]});
  if (faces_.empty()) return;
  double x1 = -std::numeric_limits<double>::infinity(), y1 = x1;
  x0_ = y0_ = std::numeric_limits<double>::infinity();
  double size = 0.0;
  for (const auto& f : faces_)
    for (const Vec3& p : f) {
      x0_ = std::min(x0_, p.x()), y0_ = std::min(y0_, p.y());
      x1 = std::max(x1, p.x()), y1 = std::max(y1, p.y());
    }
  for (const auto& f : faces_) size += (f[1] - f[0]).norm();
  // Cells about one face across (mean edge), at most ~4 faces' worth per cell in plan.
  width_ = std::max(size / static_cast<double>(faces_.size()), 1e-9 * std::max(x1 - x0_, y1 - y0_) + 1e-300);
  nx_ = static_cast<std::size_t>((x1 - x0_) / width_) + 1;
  ny_ = static_cast<std::size_t>((y1 - y0_) / width_) + 1;
  while (nx_ * ny_ > 4 * faces_.size() + 16) {
    width_ *= 2.0;
    nx_ = static_cast<std::size_t>((x1 - x0_) / width_) + 1;
    ny_ = static_cast<std::size_t>((y1 - y0_) / width_) + 1;
  }
  std::vector<std::vector<std::size_t>> bins(nx_ * ny_);
  for (std::size_t k = 0; k < faces_.size(); ++k) {
    const auto& f = faces_[k];
    const double fx0 = std::min({f[0].x(), f[1].x(), f[2].x()}), fx1 = std::max({f[0].x(), f[1].x(), f[2].x()});
    const double fy0 = std::min({f[0].y(), f[1].y(), f[2].y()}), fy1 = std::max({f[0].y(), f[1].y(), f[2].y()});
    const double pad = 1e-9 * width_;
    const std::size_t a0 = cell(fx0 - pad, y0_) % nx_, a1 = cell(fx1 + pad, y0_) % nx_;
    const std::size_t b0 = cell(x0_, fy0 - pad) / nx_, b1 = cell(x0_, fy1 + pad) / nx_;
    for (std::size_t b = b0; b <= b1; ++b)
      for (std::size_t a = a0; a <= a1; ++a) bins[b * nx_ + a].push_back(k);
  }
  std::vector<std::array<Vec3, 3>> ordered;
  offset_.assign(1, 0);
  for (const auto& bin : bins) {
    for (std::size_t k : bin) ordered.push_back(faces_[k]);
    offset_.push_back(ordered.size());
  }
  faces_ = std::move(ordered);
}

std::size_t SurfaceProfile3::cell(double x, double y) const {
  const auto clamp = [](double v, std::size_t n) {
    return static_cast<std::size_t>(std::clamp(v, 0.0, static_cast<double>(n - 1)));
  };
  return clamp(std::floor((y - y0_) / width_), ny_) * nx_ + clamp(std::floor((x - x0_) / width_), nx_);
}

double SurfaceProfile3::top(double x, double y) const {
  double top = -std::numeric_limits<double>::infinity();
  if (faces_.empty()) return top;
  const std::size_t c = cell(x, y);
  for (std::size_t k = offset_[c]; k < offset_[c + 1]; ++k) {
    const auto& f = faces_[k];
    // Barycentric coordinates of (x, y) in the face's plan; a face seen edge-on has none.
    const double x1 = f[1].x() - f[0].x(), y1 = f[1].y() - f[0].y();
    const double x2 = f[2].x() - f[0].x(), y2 = f[2].y() - f[0].y();
    const double det = x1 * y2 - x2 * y1;
    const double scale = x1 * x1 + y1 * y1 + x2 * x2 + y2 * y2;
    if (!(std::abs(det) > 1e-12 * scale)) continue;
    const double px = x - f[0].x(), py = y - f[0].y();
    const double b1 = (px * y2 - x2 * py) / det, b2 = (x1 * py - px * y1) / det, b0 = 1.0 - b1 - b2;
    constexpr double tol = -1e-9;
    if (b0 < tol || b1 < tol || b2 < tol) continue;
    top = std::max(top, b0 * f[0].z() + b1 * f[1].z() + b2 * f[2].z());
  }
  return top;
}

std::vector<BoundaryNode3> build_viscous_boundary_3d(const Model3& model, const std::vector<ViscousSurface>& surfaces) {
  const auto& nodes = model.nodes;
  const auto& tet = model.tetrahedra;
  const std::map<Face, OuterFace> outer = outer_faces(tet.conn);
  double z_base = std::numeric_limits<double>::infinity();
  for (const Vec3& X : nodes.X) z_base = std::min(z_base, X.z());

  std::vector<BoundaryNode3> out;
  std::map<Index, std::size_t> index_of;
  std::map<Index, const ViscousSurface*> surface_of;
  for (const ViscousSurface& s : surfaces) {
    const Index g = model.find_group(s.group);
    if (g == kNoIndex || model.groups[static_cast<std::size_t>(g)].dim != 2)
      throw std::invalid_argument(fmt::format("'{}' must be a surface group for a viscous-spring boundary", s.group));
    if (!s.R && !s.scattering_centre)
      throw std::invalid_argument(fmt::format("viscous-spring surface '{}' needs R or a scattering centre", s.group));
    for (const Face& f : model.groups[static_cast<std::size_t>(g)].faces) {
      const auto it = outer.find(sorted(f));
      if (it == outer.end())
        throw std::invalid_argument(fmt::format("surface '{}' is not on the model's outside", s.group));
      const Vec3 a = nodes.X[f[0]], b = nodes.X[f[1]], c = nodes.X[f[2]];
      Vec3 normal = (b - a).cross(c - a);
      const double area = 0.5 * normal.norm();
      normal.normalize();
      if (normal.dot(nodes.X[it->second.opposite] - a) > 0.0) normal = -normal;  // away from its tetrahedron
      const ElasticMedium medium =
          medium_from_material(model.materials[static_cast<std::size_t>(tet.material[it->second.tet])]);
      for (const Index n : f) {
        auto [at, fresh] = index_of.try_emplace(n, out.size());
        if (fresh) {
          surface_of[n] = &s;
          BoundaryNode3 bn;
          bn.node = n;
          bn.medium = medium;
          bn.free_field = s.free_field;
          out.push_back(bn);
        }
        BoundaryNode3& bn = out[at->second];
        bn.area += area / 3.0;
        bn.normal += area / 3.0 * normal;
      }
    }
  }
  const SurfaceProfile3 surface(nodes.X, tet.conn);
  for (auto& bn : out) {
    bn.normal.normalize();
    const ViscousSurface& s = *surface_of[bn.node];
    const Vec3 X = nodes.X[bn.node];
    const double R = s.R ? *s.R : (X - *s.scattering_centre).norm();
    bn.coef = viscous_spring_coefficients(bn.area, bn.medium, R, kAlphaNormal3D, kAlphaTangential3D);
    bn.height = X.z() - z_base;
    bn.H = surface.top(X.x(), X.y()) - z_base;
    bn.height = std::clamp(bn.height, 0.0, bn.H);
  }
  return out;
}

}  // namespace dsdem::boundary
