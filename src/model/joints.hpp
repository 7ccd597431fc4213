#pragma once
// Cohesive joint elements (docs/theory.md §3): their properties and all joints of a model
// as a structure of arrays (docs/developer-guide.md §1). Filled by mesh/joint_insertion, updated by
// the joint phase of the time step.
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "model/state_arrays.hpp"
#include "model/types.hpp"

namespace dsdem {

// Parameters of the joint law (paper eqs. 6-9, docs/theory.md §3). Stiffnesses are tractions
// per unit relative displacement; strengths are tractions; energies per unit area.
struct JointProperties {
  std::string name;
  double kn = 0.0;   // normal stiffness, Pa/m
  double ks = 0.0;   // shear stiffness, Pa/m
  double ft = 0.0;   // tensile strength, Pa
  double c = 0.0;    // cohesion, Pa
  double phi = 0.0;  // friction angle, rad
  double GI = 0.0;   // mode I fracture energy, N/m
  double GII = 0.0;  // mode II fracture energy, N/m
  bool initially_broken = false;  // every joint with these properties starts broken
  // > 0 when kn came from the penalty rule p*E/h (docs/theory.md §3) with h = penalty_h, m:
  // each joint then rescales kn (and ks unless ks_given) to its own local element size,
  // so small elements get stiff joints and the joints' compliance stays a fixed
  // fraction of their elements' (Joints::stiffness_scale).
  double penalty_h = 0.0;
  bool ks_given = false;  // ks was given by the scenario: never rescaled
  Index law = 0;          // index in law::joint_laws() (0: the cohesive law above)
};

// Empty when p is admissible, else a message naming the offending fields. Besides
// positivity, the shear strength under the tension cut-off c - ft*tan(phi) must stay
// positive, otherwise eq. 8 gives fs <= 0 and wsII = 2*GII/fs is undefined.
std::string validate(const JointProperties& p);

// How a joint broke. Initial: it was declared broken by the scenario (pre-existing crack).
enum class BreakMode : std::uint8_t { None = 0, Tension = 1, Shear = 2, Mixed = 3, Initial = 4 };
const char* to_string(BreakMode m);

// History of one integration (end) point of a joint, 48 B. The maxima and the damage are
// the irreversible state (docs/theory.md §3); the separations and the shear traction of the
// last evaluation let the law report the dissipation of the next increment and move the
// shear traction incrementally. The normal traction and the shear secant of the last
// evaluation are functions of these (last_tractions() in cohesive_law.hpp recomputes
// them, bit for bit), so they are not stored (memory per element).
struct JointPointState {
  double dn_max = 0.0;  // largest opening reached (>= 0), m
  double s_max = 0.0;   // largest |slip| reached (>= 0), m
  double damage = 0.0;  // in [0, 1]; 1 = this point has failed (eq. 9 reached)
  double dn = 0.0;      // opening at the last evaluation, m
  double ds = 0.0;      // slip at the last evaluation, m
  double ss = 0.0;      // shear traction at the last evaluation, Pa
};

// How each end point of a joint failed (None while its damage < 1).
using JointEndModes = std::array<BreakMode, 2>;

// A broken joint: when and where it broke (its current mid-point then).
struct BreakRecord {
  Index joint = kNoIndex;
  double time = 0.0;               // s (0 for joints broken from the start)
  Vec2 position = Vec2::Zero();    // m
};

// All joints of a model. Joint j glues edge (a0, a1) of triangle tri_a to edge (b0, b1)
// of triangle tri_b: a0 coincides with b0 and a1 with b1 in the reference
// configuration, and a0 -> a1 runs counter-clockwise along tri_a (so tri_b lies on the
// right of a0 -> a1, and the joint normal points from a to b). End point 0 is
// (a0, b0), end point 1 is (a1, b1).
struct Joints {
  std::vector<std::array<Index, 4>> nodes;  // (a0, a1, b0, b1) model node ids
  std::vector<Index> tri_a;
  std::vector<Index> tri_b;
  std::vector<Index> property;     // index into the joint property table
  std::vector<Index> curve_group;  // named mesh curve the joint lies on, or kNoIndex
  std::vector<double> length0;     // reference length, m
  std::vector<std::array<JointPointState, 2>> state;  // per end point
  std::vector<JointEndModes> end_mode;                // per end point
  // 1 once broken, for good. The joint phase marks a joint that breaks with
  // kBreakPending and record_new_breaks() (joint_phase.hpp) turns it into 1 with its
  // break record; both are non-zero, i.e. broken, for every reader.
  std::vector<std::uint8_t> broken;
  static constexpr std::uint8_t kBreakPending = 2;
  // The broken joints in the order they broke (ties: by joint index): a list, not a
  // time and a position per joint (memory per element).
  std::vector<BreakRecord> breaks;
  // The joint's kn (and ks, unless given) is its property's times this factor:
  // penalty_h / local element size for penalty stiffnesses, 1 otherwise (docs/theory.md §3).
  std::vector<double> stiffness_scale;
  // State variables that the joint laws in use declare (law/registry.hpp), one column
  // each, sized by the model builder; empty while none does (the cohesive law keeps its
  // history in `state` above).
  StateArrays law_state;

  std::size_t size() const { return nodes.size(); }
  // Room for n joints in every array (joint insertion adds them one at a time).
  void reserve(std::size_t n) {
    nodes.reserve(n);
    tri_a.reserve(n);
    tri_b.reserve(n);
    property.reserve(n);
    curve_group.reserve(n);
    length0.reserve(n);
    state.reserve(n);
    end_mode.reserve(n);
    broken.reserve(n);
    stiffness_scale.reserve(n);
  }
  void resize(std::size_t n) {
    nodes.resize(n, {kNoIndex, kNoIndex, kNoIndex, kNoIndex});
    tri_a.resize(n, kNoIndex);
    tri_b.resize(n, kNoIndex);
    property.resize(n, kNoIndex);
    curve_group.resize(n, kNoIndex);
    length0.resize(n, 0.0);
    state.resize(n, {JointPointState{}, JointPointState{}});
    end_mode.resize(n, {BreakMode::None, BreakMode::None});
    broken.resize(n, 0);
    stiffness_scale.resize(n, 1.0);
  }

  // Mean of the two end points' damage, in [0, 1].
  double damage(std::size_t j) const { return 0.5 * (state[j][0].damage + state[j][1].damage); }
  // How joint j broke: both ends' mode if equal, else Mixed; None while intact.
  BreakMode break_mode(std::size_t j) const {
    if (!broken[j]) return BreakMode::None;
    const BreakMode m0 = end_mode[j][0], m1 = end_mode[j][1];
    return m0 == m1 ? m0 : BreakMode::Mixed;
  }
  // The break record of joint j, or null while it is intact (linear search).
  const BreakRecord* find_break(std::size_t j) const;
  // Break time per joint (NaN while intact), for output.
  std::vector<double> break_times() const;

  // Declare joint j broken from the start (pre-existing crack): fully damaged, time 0,
  // position = mid-point of its reference edge given as a0/a1 positions.
  void set_initially_broken(std::size_t j, const Vec2& xa0, const Vec2& xa1);
};

// Local element size of joint j, m: the mean of sqrt(2 A) of its two triangles (the
// size measure of the penalty rule; area0: the triangles' reference areas).
double joint_local_size(const Joints& joints, std::size_t j, const std::vector<double>& area0);

// Sets stiffness_scale = penalty_h / joint_local_size for every joint whose property has
// a penalty stiffness (penalty_h > 0); 1 for the others.
void set_local_penalty_scales(Joints& joints, const std::vector<JointProperties>& properties,
                              const std::vector<double>& area0);

// Break every joint whose property has initially_broken set (X: model reference
// positions, indexed by the joints' node ids).
void mark_initially_broken(Joints& joints, const std::vector<JointProperties>& properties,
                           const std::vector<Vec2>& X);

}  // namespace dsdem
