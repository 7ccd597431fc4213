#pragma once
// Execution layer: the deterministic scatter of element and joint forces into the node
// force sums (docs/developer-guide.md §3). Every node's sum is formed as f + fd + fj in a fixed order
// (its element force, its element damping force, then its joints' forces in joint order),
// so the bits do not depend on which thread computed what.
// An "own" triangle, whose three nodes belong to no other triangle (every triangle of a
// discrete zone), adds its forces and its joints' forces to its nodes itself; no buffer
// per element and no incidence per node. The other, "shared" triangles (continuous zones,
// or a triangle with more than 3 joints) write their forces into slots, and their nodes
// and the nodes of no triangle (the "gathered" nodes) sum them, and their joints'
// forces, through incidence lists.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "model/types.hpp"

namespace dsdem::exec {

class NodeScatter {
 public:
  // conn: each triangle's nodes; joint_nodes: (a0, a1, b0, b1) of each joint, which
  // glues face a of triangle tri_a to face b of tri_b. Throws std::logic_error when a
  // joint's nodes are not its triangles'.
  void build(std::span<const std::array<Index, 3>> conn, std::span<const std::array<Index, 4>> joint_nodes,
             std::span<const Index> tri_a, std::span<const Index> tri_b, std::size_t n_nodes);

  bool is_own(std::size_t t) const { return own_corners_[t] != kSharedTriangle; }
  // Joints of triangle t in ascending order, then kNoIndex (the first 3 of a shared one).
  const std::array<Index, 3>& joints_of(std::size_t t) const { return triangle_joints_[t]; }
  // Own triangles before triangle t (size + 1): the own loop's weights for a split.
  std::span<const Index> own_prefix() const { return own_prefix_; }
  std::size_t shared_count() const { return shared_triangles_.size(); }
  std::size_t shared_triangle(std::size_t s) const { return static_cast<std::size_t>(shared_triangles_[s]); }
  std::size_t gathered_count() const { return gathered_nodes_.size(); }

  // Slots of the shared triangles' forces and, while kept, their damping forces.
  std::array<Vec2, 3>& shared_force(std::size_t s) { return shared_force_[s]; }
  std::array<Vec2, 3>& shared_damping_force(std::size_t s) { return shared_damping_force_[s]; }
  bool has_shared_damping() const { return !shared_damping_force_.empty(); }
  // Sizes the damping slots (on) or frees them (off): they exist only while a stage
  // damps the elements.
  void keep_shared_damping(bool on);

  // Own triangle t: adds its element force f and damping force fd (zeros unless
  // element_damping) and its joints' forces (joint_force[j]: face a's two nodes; face b
  // takes minus these) to sum at its nodes, and fd to damping_sum when given.
  [[gnu::always_inline]] void add_own(std::size_t t, std::span<const Index, 3> nodes, const std::array<Vec2, 3>& f,
                                      const std::array<Vec2, 3>& fd, bool element_damping,
                                      const std::array<Vec2, 2>* joint_force, Vec2* sum, Vec2* damping_sum) const {
    const std::uint16_t code = own_corners_[t];
    // The joints' forces per corner, in joint order (as a per-node incidence would).
    std::array<Vec2, 3> fj{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
    for (int s = 0; s < 3; ++s) {
      const Index j = triangle_joints_[t][s];
      if (j == kNoIndex) break;
      const unsigned c = static_cast<unsigned>(code) >> (5 * s);
      const std::array<Vec2, 2>& F = joint_force[j];
      if (c & 16u) {  // face b: minus face a's force, bit for bit as adding it negated
        fj[c & 3u] -= F[0];
        fj[(c >> 2) & 3u] -= F[1];
      } else {
        fj[c & 3u] += F[0];
        fj[(c >> 2) & 3u] += F[1];
      }
    }
    for (int k = 0; k < 3; ++k) {
      const Index i = nodes[k];
      // The sums a gather over one element would form: +0 + force (and damping force).
      Vec2 fe = Vec2::Zero(), fde = Vec2::Zero();
      fe += f[k];
      if (element_damping) fde += fd[k];  // without damping fde stays +0
      sum[i] += fe + fde + fj[k];
      if (damping_sum) damping_sum[i] += fde;
    }
  }

  // Gathered node g: the sum of its shared slots' forces and its joints' forces.
  [[gnu::always_inline]] void gather(std::size_t g, const std::array<Vec2, 2>* joint_force, Vec2* sum,
                                     Vec2* damping_sum) const {
    const Index i = gathered_nodes_[g];
    // Flat views: entry 3 s + k is slot s's corner k, entry 2 j + e joint j's end e.
    const Vec2* sf = shared_force_.empty() ? nullptr : shared_force_[0].data();
    const Vec2* sdf = shared_damping_force_.empty() ? nullptr : shared_damping_force_[0].data();
    const Vec2* jf = joint_force ? joint_force[0].data() : nullptr;
    Vec2 f = Vec2::Zero(), fd = Vec2::Zero();
    for (Index k = gather_offset_[g]; k < gather_offset_[g + 1]; ++k) {
      const Index e = gather_entry_[k];
      f += sf[e];
      if (sdf) fd += sdf[e];  // without damping slots fd stays +0
    }
    Vec2 fj = Vec2::Zero();
    for (Index k = gather_joint_offset_[g]; k < gather_joint_offset_[g + 1]; ++k) {
      const Index c = gather_joint_entry_[k];
      if (c & 1) fj -= jf[c >> 1];  // face b: minus face a's force, bit for bit as adding it negated
      else fj += jf[c >> 1];
    }
    sum[i] += f + fd + fj;
    if (damping_sum) damping_sum[i] += fd;
  }

 private:
  // The steps of build(), in order.
  void assign_triangle_joints(std::size_t n_triangles, std::span<const Index> tri_a, std::span<const Index> tri_b);
  void share_triangles_with_shared_nodes(std::span<const std::array<Index, 3>> conn, std::size_t n_nodes);
  void encode_own_corners(std::span<const std::array<Index, 3>> conn, std::span<const std::array<Index, 4>> joint_nodes,
                          std::span<const Index> tri_b);
  void list_shared_and_gathered(std::span<const std::array<Index, 3>> conn, std::size_t n_nodes);
  void build_shared_gather(std::span<const std::array<Index, 3>> conn, std::vector<Index>& fill);
  void build_joint_gather(std::span<const std::array<Index, 4>> joint_nodes, std::vector<Index>& fill);
  void check_joints_covered(std::size_t n_joints) const;
  // Position of node in gathered_nodes_, or kNoIndex.
  Index gathered_slot(Index node) const;

  // own_corners_[t]: kSharedTriangle for a shared triangle; for an own one, per joint
  // slot s of triangle_joints_[t], bits 5s..5s+4: the corner of the joint's end 0 (2
  // bits), of its end 1 (2 bits), and 1 when t is the joint's face b (minus the force).
  static constexpr std::uint16_t kSharedTriangle = 0x8000;
  std::vector<std::array<Index, 3>> triangle_joints_;
  std::vector<std::uint16_t> own_corners_;
  std::vector<Index> own_prefix_;
  std::vector<Index> shared_triangles_;  // ascending; shared slot s = position here
  std::vector<std::array<Vec2, 3>> shared_force_, shared_damping_force_;
  std::vector<Index> gathered_nodes_;  // ascending
  // Per gathered node: shared slot entries 3 s + corner (ascending triangle), joint
  // entries 2 (2 j + end) + side (ascending joint; side 1 = face b, negated).
  std::vector<Index> gather_offset_, gather_entry_;
  std::vector<Index> gather_joint_offset_, gather_joint_entry_;
};

}  // namespace dsdem::exec
