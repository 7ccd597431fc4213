#pragma once
// Uniformly sampled ground-motion records (docs/theory.md §5): readers for CSV and PEER
// NGA .AT2 files, linear resampling to any dt, trapezoidal integration to velocity
// and displacement with a least-squares polynomial baseline correction.
#include <cstddef>
#include <iosfwd>
#include <span>
#include <string>
#include <vector>

namespace dsdem::seismic {

// Acceleration, velocity and displacement of the ground at one instant (SI).
struct MotionSample {
  double a = 0.0;  // m/s^2
  double v = 0.0;  // m/s
  double d = 0.0;  // m
};

// A record sampled at t_i = i*dt, i = 0..n-1 (the first sample is t = 0).
// Invariant after integrate()/resample(): a, v, d have the same length and v, d are
// the trapezoidal integrals of a starting from v = d = 0 at t = 0.
struct Accelerogram {
  double dt = 0.0;        // s
  std::vector<double> a;  // m/s^2
  std::vector<double> v;  // m/s
  std::vector<double> d;  // m

  std::size_t size() const { return a.size(); }
  double duration() const { return a.empty() ? 0.0 : dt * static_cast<double>(a.size() - 1); }
  double pga() const;  // max |a|, m/s^2

  // Linear interpolation of a, v, d at any t; no allocation, safe to call per node per
  // step. Before t = 0 the ground is at rest (all zero); after the last sample the
  // acceleration is zero and the motion continues with the final velocity.
  MotionSample at(double t) const;
};

enum class AccelUnits { MetresPerSecondSquared, G };

// "m/s2", "m/s^2", "mps2" or "g" (case-insensitive); anything else throws.
AccelUnits parse_accel_units(const std::string& text);
double to_si_factor(AccelUnits units);  // 1 or kStandardGravity

// Baseline correction (see integrate()).
struct BaselineOptions {
  bool enabled = true;
  int degree = 3;  // degree of the polynomial removed from the acceleration, >= 1
};

// Trapezoidal integration of a (sampled at dt) to v and d from rest. With the baseline
// correction on, a polynomial p(t) of the given degree (Legendre basis on [0, T]) is
// subtracted from a; its trapezoidal integrals are subtracted from v and d, so the
// three stay exactly consistent. p minimises sum_i d_i^2 (least squares on the
// displacement) subject to v(T) = 0 and d(T) = 0 exactly. Throws on dt <= 0 or fewer
// than 2 samples (the correction needs degree + 1 <= n).
Accelerogram integrate(double dt, std::vector<double> a, const BaselineOptions& baseline = {});

// Re-sample the acceleration linearly at the new dt over the same duration (the last
// new sample is at or before the old end), then integrate() again.
Accelerogram resample(const Accelerogram& record, double dt, const BaselineOptions& baseline = {});

// Multiply a, v, d by a factor (e.g. to scale to a PGA, or to take half the design
// motion as the incident wave).
void scale(Accelerogram& record, double factor);

// CSV with columns t, a (further columns ignored). Separators: comma, semicolon, tab
// or spaces. An optional non-numeric header line; blank lines and lines starting with
// '#' are skipped. t must increase strictly; it is shifted so that the first sample is
// t = 0. Non-uniform sampling is resampled linearly at the smallest spacing. Errors
// throw std::runtime_error naming the file (name) and line.
Accelerogram read_accelerogram_csv(const std::string& path, AccelUnits units,
                                   const BaselineOptions& baseline = {});
Accelerogram read_accelerogram_csv(std::istream& in, const std::string& name, AccelUnits units,
                                   const BaselineOptions& baseline = {});

// PEER NGA .AT2: 4 header lines, line 4 holds NPTS and DT either as
// "NPTS=  5000, DT= .0050 SEC" or in the older form "5000 0.005 ..."; then NPTS values
// in g, any number per line. Errors throw std::runtime_error naming file and line.
Accelerogram read_accelerogram_at2(const std::string& path, const BaselineOptions& baseline = {});
Accelerogram read_accelerogram_at2(std::istream& in, const std::string& name,
                                   const BaselineOptions& baseline = {});

// Pick the reader by extension: .AT2 (any case) is PEER, anything else CSV with units.
Accelerogram read_accelerogram(const std::string& path, AccelUnits csv_units,
                               const BaselineOptions& baseline = {});

// Write t_s,a_mps2,v_mps,d_m (header with units). Throws if the file cannot be written.
void write_accelerogram_csv(const std::string& path, const Accelerogram& record);

}  // namespace dsdem::seismic
