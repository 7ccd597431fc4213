#include "exec/node_scatter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace dsdem::exec {

void NodeScatter::build(std::span<const std::array<Index, 3>> conn, std::span<const std::array<Index, 4>> joint_nodes,
                        std::span<const Index> tri_a, std::span<const Index> tri_b, std::size_t n_nodes) {
  assign_triangle_joints(conn.size(), tri_a, tri_b);
  share_triangles_with_shared_nodes(conn, n_nodes);
  encode_own_corners(conn, joint_nodes, tri_b);
  list_shared_and_gathered(conn, n_nodes);
  std::vector<Index> fill;
  build_shared_gather(conn, fill);
  build_joint_gather(joint_nodes, fill);
  check_joints_covered(joint_nodes.size());
  if (!shared_damping_force_.empty()) keep_shared_damping(true);
}

// Joints per triangle, in joint order. A triangle with more than 3 joints (not made by
// joint insertion: one joint per edge) is left shared; its slots keep the first 3.
void NodeScatter::assign_triangle_joints(std::size_t n_triangles, std::span<const Index> tri_a,
                                         std::span<const Index> tri_b) {
  triangle_joints_.assign(n_triangles, {kNoIndex, kNoIndex, kNoIndex});
  own_corners_.assign(n_triangles, 0);
  for (std::size_t j = 0; j < tri_a.size(); ++j)
    for (Index t : {tri_a[j], tri_b[j]}) {
      auto& slots = triangle_joints_[t];
      auto free = std::find(slots.begin(), slots.end(), kNoIndex);
      if (free == slots.end()) own_corners_[t] = kSharedTriangle;
      else *free = static_cast<Index>(j);
    }
}

// Own triangles: each of their nodes in this triangle only (a count per node, 0..2).
void NodeScatter::share_triangles_with_shared_nodes(std::span<const std::array<Index, 3>> conn, std::size_t n_nodes) {
  std::vector<std::uint8_t> count(n_nodes, 0);
  for (const auto& c : conn)
    for (Index i : c) count[i] = static_cast<std::uint8_t>(std::min(count[i] + 1, 2));
  for (std::size_t t = 0; t < conn.size(); ++t)
    for (Index i : conn[t])
      if (count[i] != 1) own_corners_[t] = kSharedTriangle;
}

// Corners of each own triangle's joints: end e of joint j is node joint_nodes[j][e] on
// face a and joint_nodes[j][2 + e] on face b.
void NodeScatter::encode_own_corners(std::span<const std::array<Index, 3>> conn,
                                     std::span<const std::array<Index, 4>> joint_nodes, std::span<const Index> tri_b) {
  for (std::size_t t = 0; t < conn.size(); ++t) {
    if (own_corners_[t] == kSharedTriangle) continue;
    std::uint16_t code = 0;
    for (int s = 0; s < 3; ++s) {
      const Index j = triangle_joints_[t][s];
      if (j == kNoIndex) break;
      const bool face_b = tri_b[j] == static_cast<Index>(t);
      unsigned bits = face_b ? 16u : 0u;
      for (int e = 0; e < 2; ++e) {
        const Index node = joint_nodes[j][2 * face_b + e];
        const auto& c = conn[t];
        const auto k = std::find(c.begin(), c.end(), node) - c.begin();
        if (k == 3) throw std::logic_error(fmt::format("joint {} does not use the nodes of its triangle {}", j, t));
        bits |= static_cast<unsigned>(k) << (2 * e);
      }
      code = static_cast<std::uint16_t>(code | (bits << (5 * s)));
    }
    own_corners_[t] = code;
  }
}

// The own prefix, the shared triangles (with their force slots), and the nodes gathered
// by incidence: those of shared triangles and those of no triangle at all (their sums
// stay as the gather leaves them).
void NodeScatter::list_shared_and_gathered(std::span<const std::array<Index, 3>> conn, std::size_t n_nodes) {
  const std::size_t ne = conn.size();
  own_prefix_.assign(ne + 1, 0);
  for (std::size_t t = 0; t < ne; ++t) own_prefix_[t + 1] = own_prefix_[t] + (is_own(t) ? 1 : 0);
  shared_triangles_.clear();
  std::vector<std::uint8_t> gathered(n_nodes, 1);
  for (std::size_t t = 0; t < ne; ++t) {
    if (!is_own(t)) shared_triangles_.push_back(static_cast<Index>(t));
    else for (Index i : conn[t]) gathered[i] = 0;
  }
  gathered_nodes_.clear();
  for (std::size_t i = 0; i < n_nodes; ++i)
    if (gathered[i]) gathered_nodes_.push_back(static_cast<Index>(i));
  std::vector<std::uint8_t>().swap(gathered);
  shared_force_.assign(shared_triangles_.size(), {Vec2::Zero(), Vec2::Zero(), Vec2::Zero()});
}

Index NodeScatter::gathered_slot(Index node) const {
  const auto it = std::lower_bound(gathered_nodes_.begin(), gathered_nodes_.end(), node);
  return it != gathered_nodes_.end() && *it == node ? static_cast<Index>(it - gathered_nodes_.begin()) : kNoIndex;
}

// CSR of the shared slots' corners over the gathered nodes, in ascending triangle order.
// fill: scratch for the next free entry per gathered node.
void NodeScatter::build_shared_gather(std::span<const std::array<Index, 3>> conn, std::vector<Index>& fill) {
  const std::size_t ng = gathered_nodes_.size();
  gather_offset_.assign(ng + 1, 0);
  for (Index t : shared_triangles_)
    for (Index i : conn[t]) ++gather_offset_[gathered_slot(i) + 1];
  for (std::size_t g = 0; g < ng; ++g) gather_offset_[g + 1] += gather_offset_[g];
  gather_entry_.assign(gather_offset_[ng], 0);
  fill.assign(gather_offset_.begin(), gather_offset_.end() - 1);
  for (std::size_t s = 0; s < shared_triangles_.size(); ++s)
    for (int k = 0; k < 3; ++k)
      gather_entry_[fill[gathered_slot(conn[shared_triangles_[s]][k])]++] = static_cast<Index>(3 * s + k);
}

// CSR of the joints' ends at gathered nodes, in ascending joint order.
void NodeScatter::build_joint_gather(std::span<const std::array<Index, 4>> joint_nodes, std::vector<Index>& fill) {
  const std::size_t ng = gathered_nodes_.size();
  gather_joint_offset_.assign(ng + 1, 0);
  for (const auto& nd : joint_nodes)
    for (Index i : nd)
      if (const Index g = gathered_slot(i); g != kNoIndex) ++gather_joint_offset_[g + 1];
  for (std::size_t g = 0; g < ng; ++g) gather_joint_offset_[g + 1] += gather_joint_offset_[g];
  gather_joint_entry_.assign(gather_joint_offset_[ng], 0);
  fill.assign(gather_joint_offset_.begin(), gather_joint_offset_.end() - 1);
  for (std::size_t j = 0; j < joint_nodes.size(); ++j)
    // Entry 2 (2 j + e) + side: force slot 2 j + e (end e), side 1 = face b (negated).
    for (int k = 0; k < 4; ++k)
      if (const Index g = gathered_slot(joint_nodes[j][k]); g != kNoIndex)
        gather_joint_entry_[fill[g]++] = static_cast<Index>(2 * (2 * j + k % 2) + k / 2);
}

// Every (joint, node) once: by its own triangle's slot or by a gathered node.
void NodeScatter::check_joints_covered(std::size_t n_joints) const {
  std::size_t covered = gather_joint_entry_.size();
  for (std::size_t t = 0; t < own_corners_.size(); ++t)
    if (is_own(t))
      for (Index j : triangle_joints_[t]) covered += j != kNoIndex ? 2 : 0;
  if (covered != 4 * n_joints)
    throw std::logic_error(
        fmt::format("joint nodes outside their triangles: {} of {} joint-node pairs reached", covered, 4 * n_joints));
}

void NodeScatter::keep_shared_damping(bool on) {
  if (!on) {
    std::vector<std::array<Vec2, 3>>().swap(shared_damping_force_);
  } else if (shared_damping_force_.size() != shared_triangles_.size()) {
    shared_damping_force_.assign(shared_triangles_.size(), {Vec2::Zero(), Vec2::Zero(), Vec2::Zero()});
  }
}

}  // namespace dsdem::exec
