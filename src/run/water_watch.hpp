#pragma once
// What engineers read off the moving water (docs/theory.md §12) at each history row: the
// free surface at gauges, the wave's amplitude above the still level (where and when), the
// run-up on banks, the water past crests, the force and peak pressure on curves, the energy
// the water gained; their peaks for summary.json.
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "io/history_writer.hpp"
#include "io/scenario.hpp"
#include "run/moving_water.hpp"
#include "sph/surface.hpp"

namespace dsdem::run {

// The wave's crest at a moment: the highest free surface above `level` over the columns xs
// (surface NaN: dry) that lie beyond the slide's front, x > front for direction +1 (the wave
// runs toward +x), x < front for -1; every column for direction 0 or a NaN front. The water
// above and behind the slide's front (its splash, the water it displaces as it sinks, its
// deposit) is not the impulse wave of Heller & Hager (2010), measured by gauges clear of the
// slide. x NaN and amplitude NaN when no wet column qualifies.
struct Crest {
  double amplitude = 0.0, x = 0.0;
};
Crest crest_beyond(std::span<const double> xs, std::span<const double> surface, double level, double front,
                   int direction);

// Where the wave is sought (docs/theory.md §12): columns of width dx from x_min, bottom[b] the
// lowest still water in column b (infinite: none). The x of every column whose still water is
// at least min_depth deep, and whether it stands against a wall: the first or last column, or
// one beside a column with no water at rest. A crest there is the wave's reflection, up to twice
// the incident wave, and a sloping bank's shallows end the search without one.
struct WaveColumns {
  std::vector<double> x;
  std::vector<bool> at_wall;
};
WaveColumns wave_columns(std::span<const double> bottom, double x_min, double dx, double level, double min_depth);

// The mean of the wet columns' free surface (NaN: dry; NaN when none is wet).
double mean_surface(std::span<const double> surface);

// Fluid particles strictly inside a triangle of the model at its current position (cells of
// `cell` m bin the particles).
long particles_in_solid(const sph::FluidParticles& f, const Model& m, double cell);

// The measurements at history rows, their peaks for summary.json.
class WaterWatch {
 public:
  // direction: where the wave runs from the slide's bank (+1: toward +x, -1: toward -x, 0: no
  // slide known; see crest_beyond).
  WaterWatch(const io::Scenario& sc, const MovingWaterLayout& layout, const Model& model, int direction);

  // history.csv columns: <gauge>_eta, <bank>_runup, <crest>_overtopped, <curve>_force_x/_y,
  // <curve>_peak_pressure, water_energy_gain, water_boundary_work (sph::Fluid::boundary_work:
  // the modified boundary's wall pressure work since step 0).
  static std::vector<io::HistoryColumn> columns(const io::SphSpec& spec, const std::string& energy_unit,
                                                const std::string& force_unit);
  // Measures the water now; writes columns(...).size() values from `row`. slide_front: the x
  // of the slide's foremost point now (NaN: none); the wave's amplitude is sought beyond it,
  // above the still level. slide_entered: the slide has met the water; until then the still
  // level is measured anew at each row (the mean surface over the wave's columns: the
  // settled water's, a little below reservoir.level as the weakly compressible water is
  // squeezed by its weight, about g H^2 / (2 c0^2)).
  void observe(const sph::Fluid& fluid, double t, std::span<double> row, double slide_front, bool slide_entered,
               const Model& model);

  struct Peak {
    double value = 0.0, x = 0.0, t = 0.0;
    bool seen = false;
  };
  const Peak& max_amplitude() const { return amplitude_; }
  // Whether the wave column at x (within half a spacing) stands against a wall (wave_columns).
  bool against_wall(double x) const;
  struct Named {
    std::string name;
    Peak peak;             // run-up elevation (m), overtopped area (m^2/m) or force magnitude (N/m)
    double pressure = 0.0;  // Pa, the peak pressure on a pressure curve
    // A bank's run-up elevation (m) or a curve's force (N/m) at each row before the slide met
    // the water (all rows when it never does).
    std::vector<double> before_entry;
    // Their median: the water at rest against it, through the solid's own settling and an
    // earthquake's sloshing before the slide (NaN: no row).
    double at_rest() const;
  };
  const std::vector<Named>& runup() const { return runup_; }
  const std::vector<Named>& crests() const { return crests_; }
  const std::vector<Named>& forces() const { return forces_; }
  // The mean up-crossing period at each gauge (s; NaN with fewer than two crossings), from its
  // record before the slide's front reached it.
  std::vector<std::pair<std::string, double>> gauge_periods() const;
  // When the slide's rock first rose at each gauge to within two spacings of the water's surface
  // there, or the gauge went dry over it (s; NaN: never; moved_rock_tops): from then on the gauge
  // reads the debris and the water it displaces, not the wave. A slide running under the gauge
  // deeper down leaves its reading the wave's, as in Heller & Hager's flume.
  const std::vector<double>& gauge_overrun_times() const { return gauge_overrun_t_; }
  // The primary wave at each gauge from t_from on (the slide's entry) until the slide's front
  // reached it: its first crest and the trough after it, from the still level (turning points a
  // spacing apart).
  struct GaugeWave {
    std::string name;
    double x = 0.0;  // m
    sph::PrimaryWave wave;
    double overrun_t = std::numeric_limits<double>::quiet_NaN();  // s, gauge_overrun_times()
  };
  std::vector<GaugeWave> primary_waves(double t_from) const;
  // The largest gain of the water's energy over its energy at step 0 (J/m) and when.
  const Peak& energy_gain() const { return energy_gain_; }
  // The most fluid particles seen outside the model's box (grown by the kernel's support):
  // water that leaked out of the reservoir through a gap in the solid.
  long escaped_particles() const { return escaped_; }
  // The most fluid particles seen above the top of the coupled bedrock faces (the level plus
  // the freeboard): water that may have run through uncoupled rock.
  long above_freeboard_particles() const { return above_top_; }
  // The most fluid particles seen inside a triangle of the solid at a history row: water
  // that got through a wall (at corners of the wall layout, or squeezed into closing gaps).
  long particles_inside_solid() const { return inside_; }
  // The largest particle speed at a history row (m/s), where and when: often a few
  // particles thrown out of a squeeze, far faster than the flow.
  const Peak& max_speed() const { return speed_; }
  // The flow's speed: the largest at a history row of the speed that 1 % of the particles
  // exceed (m/s) and when. Beyond c0 / 10 the weakly compressible water's density errs by more
  // than about 1 % (docs/theory.md §11).
  const Peak& flow_speed() const { return flow_speed_; }
  // True when this peak came at the last row observed: the quantity may still have been
  // growing when the run ended.
  bool at_last_row(const Peak& p) const { return p.seen && p.t >= last_t_; }
  // Whether a row has been observed (restored from a checkpoint included).
  bool observed() const { return std::isfinite(last_t_); }
  double coupled_top() const { return top_; }
  double level() const { return level_; }
  // The still level the wave's amplitude is measured from (m): the water's mean surface at
  // the last row before the slide met it; reservoir.level before the first row.
  double still_level() const { return std::isnan(still_) ? level_ : still_; }

  // Everything observe() has gathered, as numbers for a checkpoint, and back. restore()
  // throws std::runtime_error when the numbers do not fit this scenario's water.
  std::vector<double> state() const;
  void restore(std::span<const double> s);

 private:
  void observe_curves(const sph::Fluid& fluid, double t, std::span<double> row, std::size_t& k, bool slide_entered);

  const io::SphSpec& spec_;
  double level_ = 0.0, dp_ = 0.0, h_ = 0.0;
  double still_ = std::numeric_limits<double>::quiet_NaN();
  double last_t_ = -std::numeric_limits<double>::infinity();  // s, the last row observed
  int direction_ = 0;
  Vec2 box_min_ = Vec2::Zero(), box_max_ = Vec2::Zero();  // the model's, grown by 2h
  long escaped_ = 0, above_top_ = 0, inside_ = 0;
  double top_ = 0.0;  // m: the top of the coupled bedrock faces
  std::vector<double> gauge_x_, wave_x_;  // the gauges; where the amplitude is sought
  std::vector<bool> wave_wall_;           // wave_x_'s columns against a wall
  std::vector<std::vector<double>> gauge_t_, gauge_eta_;
  std::vector<double> gauge_overrun_t_;  // s, NaN until the slide's front reaches the gauge
  // A gauge's record before the slide's front reached it.
  std::span<const double> before_overrun(std::size_t g, const std::vector<double>& series) const;
  std::vector<double> crest_start_;
  std::optional<double> energy_start_;
  Peak amplitude_, energy_gain_, speed_, flow_speed_;
  std::vector<double> speeds_;  // scratch of observe()
  std::vector<Named> runup_, crests_, forces_;
};

}  // namespace dsdem::run
