#pragma once
// Current node positions as the contact phase reads them: x itself, or X + u when the
// displacements are given too. The solver passes its reference positions and
// displacements, so no per-step copy of the positions is kept (16 B per node);
// X + u is the same sum the copy held, so the results do not change.
#include <cstddef>
#include <span>
#include <vector>

#include "model/types.hpp"

namespace dsdem::contact {

struct NodePositions {
  std::span<const Vec2> x;      // current positions, or reference positions when u is given
  std::span<const Vec2> u = {};  // displacements (empty: x is current)

  NodePositions(std::span<const Vec2> x_, std::span<const Vec2> u_ = {}) : x(x_), u(u_) {}
  NodePositions(const std::vector<Vec2>& x_) : x(x_) {}
  Vec2 operator[](std::size_t i) const { return u.empty() ? Vec2(x[i]) : Vec2(x[i] + u[i]); }
  std::size_t size() const { return x.size(); }
};

}  // namespace dsdem::contact
