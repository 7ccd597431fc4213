#pragma once
// The data of the contact phase (ContactForces): pair parameters, settings, the model
// arrays it reads, its records of each contact and its step statistics.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "contact/contact_history.hpp"
#include "contact/contact_law.hpp"
#include "contact/narrow_phase.hpp"
#include "contact/positions.hpp"

namespace dsdem::contact {

// Contact parameters per pair of groups (any per-triangle index: material, surface
// group, ...), symmetric, with a default for pairs not set. Restitution is turned
// into a damping ratio when an entry is set, not per contact.
class ContactParamTable {
 public:
  explicit ContactParamTable(const ContactProperties& default_props = {});
  void set_default(const ContactProperties& p);
  void set(Index g1, Index g2, const ContactProperties& p);  // g >= 0
  // Parameters of a pair; the default when either index is negative or was never set.
  const ContactLawParams& get(Index g1, Index g2) const {
    if (g1 < 0 || g2 < 0 || g1 >= n_ || g2 >= n_) return entries_[0];
    return entries_[table_[static_cast<std::size_t>(g1) * n_ + g2]];
  }

 private:
  Index n_ = 0;
  std::vector<ContactLawParams> entries_;  // [0] = default
  std::vector<Index> table_;               // n_ x n_ -> entry
};

struct ContactSettings {
  // Broad-phase skin, m: boxes are enlarged by skin/2 per side and the pair list is
  // rebuilt when a node has moved more than skin/2. <= 0: 0.5 * the mean inradius of
  // the contact triangles at the first call.
  double skin = 0.0;
  // Below this many candidate pairs the pair loop runs on one thread.
  std::size_t min_pairs_per_parallel_run = 128;
  // Below this many pairs examined in a step (after the parallel filter), the first thread
  // alone computes their edge data, contacts and forces: a split costs three barriers,
  // which a few dozen pairs do not repay.
  std::size_t min_examined_pairs_to_split = 64;
  // false: every loop on one thread (the solver turns OpenMP off for small models; a
  // parallel region there costs more than it saves, and far more on a loaded machine).
  bool parallel = true;
  // Where the cores' edge data are computed (ContactForces::edge_scales_): automatic
  // chooses each step; the others force one way (tests: the results are the same).
  enum class EdgeScales { automatic, with_shapes, examined_only };
  EdgeScales edge_scales = EdgeScales::automatic;
  // Several threads: one partition of the contact triangles per step (ContactForces::
  // compute_partitioned): each thread updates the shapes of a contiguous run of them,
  // then filters and examines the pairs whose triangle i is in its run, with no barrier
  // between its filter and its pair loop. false: the shapes, the filter and the pair loop
  // are split each on its own (tests: the results are the same).
  bool one_partition = true;
};

// The model arrays the contact phase reads (sizes: nodes for x, v, mass, u; triangles
// for conn, active, rounding_radius, group, body).
struct ContactInput {
  std::span<const Vec2> x;       // current node positions, m (reference positions when u is given)
  std::span<const Vec2> v;       // node velocities, m/s (the half-step ones in Verlet)
  std::span<const double> mass;  // lumped node masses, kg (per unit thickness)
  std::span<const std::array<Index, 3>> conn;
  std::span<const std::uint8_t> active;      // != 0: the triangle takes part (zones A, C)
  std::span<const double> rounding_radius;   // per triangle, m (see rounding_radius())
  std::span<const Index> group;              // per triangle, index into ContactParamTable
  // Optional, per triangle: two triangles with the same body id >= 0 never interact
  // (e.g. 0 for every zone-C triangle: one continuous mesh that cannot separate), and
  // such pairs are left out of the broad phase. Empty: only the shared-node rule.
  std::span<const Index> body = {};
  // Optional node displacements, m: the current positions are then x + u (NodePositions).
  std::span<const Vec2> u = {};
  NodePositions positions() const { return {x, u}; }
};

// One contact of the last call. The constructor leaves the values unset: the contact
// phase writes every field, so a zero-fill would be wasted work on every record.
struct ContactRecord {
  ContactRecord() {}  // user-provided: emplace_back() does not zero-fill either
  // What scatter_forces() reads comes first and together (key, force, Ni, Nj: 80 B, two
  // cache lines, not three): on two threads each thread reads every record.
  ContactKey key;  // triangles i < j and feature (see ContactGeometry)
  ContactKind kind;
  std::uint8_t other;
  bool sliding;
  Vec2 force;                    // total force on i (on j: -force)
  Vec3 Ni;                       // shape functions of i and j at the point
  Vec3 Nj;
  double overlap;                // m
  double fn;                     // normal force on i, N/m
  Vec2 normal;                   // from j to i
  Vec2 point;                    // contact point, m
  Vec2 ft;                       // tangential force on i, N/m
  double elastic_energy;         // J/m
  double friction_dissipation;   // J/m this step
  // The dashpot's part of fn (ContactLawResult::dashpot_force), N/m, and the half of its
  // work booked at this step; the other half is booked at the next call (settle_previous).
  double damping_dissipation;    // J/m
  double dashpot_force;
};
static_assert(sizeof(ContactRecord) <= 176, "keep the contact record compact (memory per contact)");

// What a contact's dashpot force needs for the second half of its work (a checkpoint keeps
// these between a run and its restart; see ContactForces::settle_previous).
struct DashpotRecord {
  ContactKey key;
  Vec3 Ni, Nj;
  Vec2 normal;
  double dashpot_force = 0.0;
};


struct ContactStepStats {
  Index active_contacts = 0;
  Index sliding_contacts = 0;
  Index candidate_pairs = 0;
  // Candidates known to be apart (not examined): their cores or boxes were apart by more
  // than they have moved since.
  Index skipped_pairs = 0;
  Index examined_pairs = 0;  // candidates sent to the narrow phase
  bool rebuilt = false;                  // the broad phase was rebuilt this call
  double elastic_energy = 0.0;           // stored in all contacts now, J/m
  double elastic_energy_increment = 0.0; // change since the previous call, J/m
  double friction_dissipation = 0.0;     // Coulomb sliding this step, J/m
  // Normal dashpots' work this step, J/m: half of this call's forces' (at the half-step
  // velocity they were computed with) and half of the last call's (at this call's).
  double damping_dissipation = 0.0;
};

}  // namespace dsdem::contact
