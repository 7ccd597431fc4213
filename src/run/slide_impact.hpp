#pragma once
// Where a slide meets the reservoir (docs/theory.md §12): the bank from the bedrock's surface,
// and the slide measured at its first entry into the water (speed, thickness, mass, the
// bank's angle), the inputs of the Heller & Hager (2010) impulse-wave estimate.
#include <optional>
#include <span>
#include <vector>

#include "io/scenario.hpp"
#include "model/model.hpp"
#include "water/heller_hager.hpp"

namespace dsdem::run {

// The reservoir's bank on the slide's side, in the reference configuration.
struct Shore {
  double level = 0.0;               // m, the still level
  double x_min = 0.0, x_max = 0.0;  // m, the reservoir
  double density = 1000.0;          // kg/m^3
  double depth = 0.0;               // m: the level above the lowest bed inside the reservoir
  Vec2 shoreline = Vec2::Zero();    // where the bank meets the level
  double slope_deg = 0.0;           // the bank's angle from the level down to half the depth
  Vec2 downslope = Vec2::Zero();    // unit vector down the bank
};

// Whether the model has a discrete zone: a slide that may enter the reservoir. Without one the
// reservoir is water alone (docs/theory.md §12): no shore, no slide, no Heller & Hager estimate.
bool has_slide(const Model& model);

// The bank facing the discrete zone (the end of the reservoir nearer its centroid) on the
// surface of the triangles outside the discrete zone. Throws io::ScenarioError at the
// reservoir's key when the model has no discrete zone, no bed below the level inside the
// reservoir, or no bank rising through the level on that side.
Shore find_shore(const Model& model, const io::ReservoirSpec& spec);

struct SlideAtImpact {
  double time = 0.0;            // s: the first observation with the slide in the water
  Vec2 entry = Vec2::Zero();    // m: its lowest node in the water then
  water::SlideImpact slide;     // speed, thickness, mass, slope and depth
};

// A triangle of the discrete zone moving faster than this (m/s, at its centroid) belongs
// to the slide.
inline constexpr double kSlideSpeed = 0.5;

// The slide at a moment: the moving triangles of the discrete zone, their mass (per unit
// width), the speed of their centre of mass, and their largest thickness across the bank's
// direction (in bins along it 4 mean element sizes wide). Zero mass when none moves.
water::SlideImpact measure_slide(const Model& model, const Shore& shore);

// Where the wave runs from the slide's bank along x: +1 toward +x, -1 toward -x.
inline int wave_direction(const Shore& shore) { return shore.downslope.x() < 0.0 ? -1 : 1; }

// The slide's foremost point along x in the wave's direction: the x of the node of the
// discrete zone furthest toward the open water (the deposit's toe once it has stopped).
double slide_front(const Model& model, const Shore& shore);
// The top of the slide's rock over each x of `xs`: the highest node of the discrete triangles
// that span x and have a node moved more than `min_displacement` (m) from where it started
// (rock shaken in place is not the slide); -infinity where there is none.
std::vector<double> moved_rock_tops(const Model& model, std::span<const double> xs, double min_displacement);

// Watches for the slide's first entry into the reservoir; observe() at each history row.
class SlideImpactWatch {
 public:
  explicit SlideImpactWatch(Shore shore) : shore_(shore) {}
  // Records the impact the first time a node of a moving discrete triangle that started
  // above the level is below it inside the reservoir; true when it did so now.
  bool observe(const Model& model, double time);
  const std::optional<SlideAtImpact>& impact() const { return impact_; }
  void restore(std::optional<SlideAtImpact> impact) { impact_ = impact; }
  const Shore& shore() const { return shore_; }

 private:
  Shore shore_;
  std::optional<SlideAtImpact> impact_;
};

}  // namespace dsdem::run
