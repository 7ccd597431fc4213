#pragma once
// The engineering estimate of a landslide-generated impulse wave (Heller & Hager 2010,
// VAW report 4257; docs/theory.md §12): the impulse product parameter of the slide where it
// meets the water and the 2D wave amplitude, height and their decay. Pure functions.
namespace dsdem::water {

// The slide where it enters the water, per unit width (2D: the channel width b is 1 m).
struct SlideImpact {
  double speed = 0.0;        // V_s, m/s: the slide's centroid speed at impact
  double thickness = 0.0;    // s, m: the slide's thickness normal to the slope
  double mass = 0.0;         // m_s, kg/m: the slide's mass per unit width
  double slope_deg = 0.0;    // alpha, deg: the slope angle where it enters the water
  double depth = 0.0;        // h, m: the still water depth
  double water_density = 1000.0;  // kg/m^3
  double gravity = 9.81;          // m/s^2
};

// One parameter against the range of the experiments behind the equations.
struct RangeCheck {
  const char* name = "";
  double value = 0.0;
  double min = 0.0, max = 0.0;
  bool inside() const { return value >= min && value <= max; }
};

struct ImpulseWave {
  double froude = 0.0;             // F = V_s / sqrt(g h)
  double relative_thickness = 0.0; // S = s / h
  double relative_mass = 0.0;      // M = m_s / (rho_w b h^2)
  double impulse_product = 0.0;    // P = F S^1/2 M^1/4 cos(6 alpha / 7)^1/2
  double amplitude_m = 0.0;        // a_M = 4/9 P^4/5 h: the largest crest above the still level
  double height_m = 0.0;           // H_M = 5/9 P^4/5 h: the largest crest-to-trough height
  double distance_m = 0.0;         // x_M = 11/2 P^1/2 h: where H_M is reached from the impact
  // F, S, M, P and alpha against the experiments' ranges; inside() of all: the equations apply.
  RangeCheck checks[5];
  bool inside_validity() const;
};

// Throws std::invalid_argument for a non-positive depth, speed, thickness or mass or a
// slope outside (0, 90] deg.
ImpulseWave heller_hager(const SlideImpact& s);

// The 2D wave height at distance x (m) from the impact: H(x) = 3/4 (P (x/h)^-1/3)^4/5 h.
double heller_hager_height_at(const ImpulseWave& w, double depth, double x);

// The 2D crest amplitude at distance x (m) from the impact: a(x) = 3/5 (P (x/h)^-1/3)^4/5 h
// (Heller & Hager 2010, the primary wave's crest). a(x) and H(x) reach a_M and H_M at the
// same x/h (heller_hager_decay_onset): nearer the impact the laws exceed their own maxima.
double heller_hager_amplitude_at(const ImpulseWave& w, double depth, double x);

// x/h at which the decay laws meet a_M and H_M: (27/20)^(15/4) = 3.08.
double heller_hager_decay_onset();

}  // namespace dsdem::water
