#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <sstream>
#include <string>

#include "model/types.hpp"
#include "seismic/accelerogram.hpp"

using namespace dsdem;
using namespace dsdem::seismic;

namespace {

const BaselineOptions kRaw{false, 3};
const std::string kData = std::string(DSDEM_TEST_DATA_DIR) + "/seismic/";

// d(t) = D sin^2(pi t/T) sin(w t): starts and ends at rest, so the exact v and d end at 0.
struct Wavelet {
  double D = 0.05, T = 10.0, w = 2 * kPi * 1.5;
  double s(double t) const { return 0.5 * (1 - std::cos(2 * kPi * t / T)); }
  double s1(double t) const { return kPi / T * std::sin(2 * kPi * t / T); }
  double s2(double t) const { return 2 * (kPi / T) * (kPi / T) * std::cos(2 * kPi * t / T); }
  double d(double t) const { return D * s(t) * std::sin(w * t); }
  double v(double t) const { return D * (s1(t) * std::sin(w * t) + s(t) * w * std::cos(w * t)); }
  double a(double t) const {
    return D * (s2(t) * std::sin(w * t) + 2 * s1(t) * w * std::cos(w * t) - s(t) * w * w * std::sin(w * t));
  }
};

std::vector<double> sample(const Wavelet& f, double dt, double extra_a0 = 0.0, double extra_a1 = 0.0) {
  const int n = static_cast<int>(std::round(f.T / dt)) + 1;
  std::vector<double> a(n);
  for (int i = 0; i < n; ++i) a[i] = f.a(i * dt) + extra_a0 + extra_a1 * i * dt;
  return a;
}

double max_abs(const std::vector<double>& x) {
  double m = 0;
  for (double v : x) m = std::max(m, std::abs(v));
  return m;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

Accelerogram csv(const std::string& text, AccelUnits u = AccelUnits::MetresPerSecondSquared) {
  std::istringstream in(text);
  return read_accelerogram_csv(in, "rec.csv", u, kRaw);
}

Accelerogram at2(const std::string& text) {
  std::istringstream in(text);
  return read_accelerogram_at2(in, "rec.AT2", kRaw);
}

const char* kAt2Head = "PEER NGA STRONG MOTION DATABASE RECORD\nTEST\nACCELERATION TIME SERIES IN UNITS OF G\n";

}  // namespace

// Trapezoidal integration is second order: halving dt divides the error by 4.
TEST(Accelerogram, TrapezoidalIntegrationIsSecondOrder) {
  const Wavelet f;
  double err[2];
  for (int k = 0; k < 2; ++k) {
    const double dt = 0.01 / (1 << k);
    const Accelerogram r = integrate(dt, sample(f, dt), kRaw);
    double e = 0;
    for (std::size_t i = 0; i < r.size(); ++i) e = std::max(e, std::abs(r.d[i] - f.d(i * dt)));
    err[k] = e;
  }
  EXPECT_LT(err[1], 1e-3 * f.D);
  EXPECT_NEAR(err[0] / err[1], 4.0, 0.2);
}

// A constant + linear error in the acceleration (a drifting baseline) is removed
// exactly: the corrected record equals the corrected clean record to rounding.
TEST(Accelerogram, BaselineCorrectionRemovesPolynomialDrift) {
  const Wavelet f;
  const double dt = 0.005;
  const Accelerogram clean = integrate(dt, sample(f, dt));
  const Accelerogram raw = integrate(dt, sample(f, dt, 0.02, 0.003), kRaw);
  EXPECT_GT(std::abs(raw.d.back()), 1.0);  // the drift is large: 0.02*T^2/2 + ... metres
  const Accelerogram fixed = integrate(dt, sample(f, dt, 0.02, 0.003));
  for (std::size_t i = 0; i < clean.size(); ++i) {
    ASSERT_NEAR(fixed.a[i], clean.a[i], 1e-11);
    ASSERT_NEAR(fixed.v[i], clean.v[i], 1e-11);
    ASSERT_NEAR(fixed.d[i], clean.d[i], 1e-11);
  }
  // Final velocity and displacement are zero (equality constraints of the fit).
  EXPECT_LT(std::abs(fixed.v.back()), 1e-12);
  EXPECT_LT(std::abs(fixed.d.back()), 1e-12);
  // The clean signal is barely touched: its projection on the low-order polynomials
  // is small for a signal of 15 cycles; 0.5% of the peak displacement asserted.
  double e = 0;
  for (std::size_t i = 0; i < clean.size(); ++i) e = std::max(e, std::abs(clean.d[i] - f.d(i * dt)));
  EXPECT_LT(e, 5e-3 * f.D);
}

TEST(Accelerogram, BaselineOfPurePolynomialIsZero) {
  std::vector<double> a(1001);
  for (int i = 0; i <= 1000; ++i) {
    const double t = i * 0.01;
    a[i] = 0.3 - 0.05 * t + 0.004 * t * t - 0.0002 * t * t * t;
  }
  const Accelerogram r = integrate(0.01, a);
  EXPECT_LT(max_abs(r.a), 1e-12);
  EXPECT_LT(max_abs(r.v), 1e-12);
  EXPECT_LT(max_abs(r.d), 1e-12);
}

TEST(Accelerogram, InterpolationZeroBeforeStartAndHeldAfterEnd) {
  const Accelerogram r = integrate(0.1, {0.0, 1.0, 3.0, 2.0}, kRaw);
  EXPECT_EQ(r.at(-1e-9).a, 0.0);
  EXPECT_EQ(r.at(-1.0).d, 0.0);
  EXPECT_DOUBLE_EQ(r.at(0.1).a, 1.0);
  EXPECT_DOUBLE_EQ(r.at(0.15).a, 2.0);
  EXPECT_DOUBLE_EQ(r.at(0.15).v, 0.5 * (r.v[1] + r.v[2]));
  const double T = r.duration();
  EXPECT_NEAR(T, 0.3, 1e-15);
  const MotionSample after = r.at(T + 0.5);
  EXPECT_EQ(after.a, 0.0);
  EXPECT_DOUBLE_EQ(after.v, r.v.back());
  EXPECT_DOUBLE_EQ(after.d, r.d.back() + 0.5 * r.v.back());
}

TEST(Accelerogram, ResampleIsLinearInterpolation) {
  std::vector<double> a;
  for (int i = 0; i <= 100; ++i) a.push_back(std::sin(0.2 * i));
  const Accelerogram r = integrate(0.01, a, kRaw);
  const Accelerogram fine = resample(r, 0.0025, kRaw);
  ASSERT_EQ(fine.size(), 401u);
  EXPECT_NEAR(fine.dt, 0.0025, 1e-18);
  for (std::size_t i = 0; i < fine.size(); ++i) {
    const double t = 0.0025 * i;
    ASSERT_NEAR(fine.a[i], r.at(t).a, 1e-14);
    // Linear interpolation of sin(20 t): error <= dt^2/8 * max|a''| = 1e-4/8 * 400.
    ASSERT_NEAR(fine.a[i], std::sin(20 * t), 0.005 + 1e-12);
  }
  // Coarsening keeps the samples that coincide.
  const Accelerogram coarse = resample(r, 0.02, kRaw);
  ASSERT_EQ(coarse.size(), 51u);
  for (std::size_t i = 0; i < coarse.size(); ++i) ASSERT_NEAR(coarse.a[i], a[2 * i], 1e-14);
  EXPECT_THROW(resample(r, -0.01), std::runtime_error);
  EXPECT_THROW(resample(r, 0.0), std::runtime_error);
}

TEST(AccelerogramCsv, ReadsHeaderUnitsAndSeparators) {
  const Accelerogram g = csv("t,a\n0,0.1\n0.01,0.2\n0.02,-0.1\n", AccelUnits::G);
  ASSERT_EQ(g.size(), 3u);
  EXPECT_NEAR(g.dt, 0.01, 1e-15);
  EXPECT_DOUBLE_EQ(g.a[1], 0.2 * kStandardGravity);
  const Accelerogram w = csv("# comment\n\n0 1.5\n0.5\t2.5 9 9\n1.0 3.5\n");
  ASSERT_EQ(w.size(), 3u);
  EXPECT_NEAR(w.dt, 0.5, 1e-15);
  EXPECT_DOUBLE_EQ(w.a[2], 3.5);
  const Accelerogram s = csv("time;acc\n1.0;4\n1.1;5\n");  // shifted so that t starts at 0
  EXPECT_NEAR(s.dt, 0.1, 1e-14);
  EXPECT_DOUBLE_EQ(s.a[0], 4.0);
  // Non-uniform times: resampled at the smallest spacing, linearly.
  const Accelerogram u = csv("0,0\n0.01,1\n0.03,3\n0.04,4\n");
  ASSERT_EQ(u.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(u.a[i], i, 1e-12);
}

TEST(AccelerogramCsv, ErrorsNameFileAndLine) {
  EXPECT_NE(error_of([] { csv("t,a\n0,1\n0.01,abc\n"); }).find("rec.csv:3: acceleration 'abc' is not a number"),
            std::string::npos);
  EXPECT_NE(error_of([] { csv("0,1\n0.01\n"); }).find("rec.csv:2: expected 2 columns"), std::string::npos);
  EXPECT_NE(error_of([] { csv("0,1\n0.01,2\n0.01,3\n"); }).find("rec.csv:3: time 0.01 does not increase"),
            std::string::npos);
  EXPECT_NE(error_of([] { csv("0,1\n0.02,2\n0.01,3\n"); }).find("rec.csv:3"), std::string::npos);
  EXPECT_NE(error_of([] { csv("0,1\n0.01,\n"); }).find("rec.csv:2: acceleration '' is not a number"),
            std::string::npos);
  EXPECT_NE(error_of([] { csv("t,a\n0,1\n"); }).find("rec.csv: need at least 2 samples"), std::string::npos);
  EXPECT_NE(error_of([] { csv("t,a\n0,1\nx,2\n"); }).find("rec.csv:3: time 'x' is not a number"),
            std::string::npos);
  EXPECT_NE(error_of([] { read_accelerogram_csv("/nonexistent/x.csv", AccelUnits::G); }).find("/nonexistent/x.csv"),
            std::string::npos);
}

TEST(AccelerogramCsv, ReadsFileInG) {
  const Accelerogram r = read_accelerogram_csv(kData + "sine_2hz_g.csv", AccelUnits::G, kRaw);
  ASSERT_EQ(r.size(), 200u);
  EXPECT_NEAR(r.dt, 0.01, 1e-12);
  for (std::size_t i = 0; i < r.size(); ++i)
    ASSERT_NEAR(r.a[i], 0.1 * kStandardGravity * std::sin(2 * kPi * 2 * 0.01 * i), 1e-8);
}

TEST(AccelerogramAt2, ReadsBothHeaderForms) {
  for (const char* name : {"sine_2hz.AT2", "sine_2hz_old.at2"}) {
    const Accelerogram r = read_accelerogram(kData + name, AccelUnits::MetresPerSecondSquared, kRaw);
    ASSERT_EQ(r.size(), 200u) << name;
    EXPECT_DOUBLE_EQ(r.dt, 0.01) << name;
    for (std::size_t i = 0; i < r.size(); ++i)
      ASSERT_NEAR(r.a[i], 0.1 * kStandardGravity * std::sin(2 * kPi * 2 * 0.01 * i), 1e-7) << name;
  }
  const Accelerogram s = at2(std::string(kAt2Head) + "NPTS=    3, DT=   .0050 SEC\n .1 -.2\n 3.0E-01\n");
  ASSERT_EQ(s.size(), 3u);
  EXPECT_DOUBLE_EQ(s.dt, 0.005);
  EXPECT_DOUBLE_EQ(s.a[1], -0.2 * kStandardGravity);
}

TEST(AccelerogramAt2, ErrorsNameFileAndLine) {
  const std::string h = kAt2Head;
  EXPECT_NE(error_of([&] { at2(h + "NPTS= 3, DT= -.01 SEC\n1 2 3\n"); }).find("rec.AT2:4: DT must be positive"),
            std::string::npos);
  EXPECT_NE(error_of([&] { at2(h + "NPTS= 3\n1 2 3\n"); }).find("rec.AT2:4: no DT"), std::string::npos);
  EXPECT_NE(error_of([&] { at2(h + "3.5 0.01\n1 2 3\n"); }).find("rec.AT2:4: NPTS must be an integer"),
            std::string::npos);
  EXPECT_NE(error_of([&] { at2(h + "garbage here\n1 2 3\n"); }).find("rec.AT2:4: expected NPTS and DT"),
            std::string::npos);
  EXPECT_NE(error_of([&] { at2(h + "NPTS= 4, DT= .01 SEC\n1 2\n3\n"); }).find("rec.AT2:6: file ends after 3 values; NPTS = 4"),
            std::string::npos);
  EXPECT_NE(error_of([&] { at2(h + "NPTS= 2, DT= .01 SEC\n1 2\n3\n"); }).find("rec.AT2:6: more values than NPTS = 2"),
            std::string::npos);
  EXPECT_NE(error_of([&] { at2(h + "NPTS= 3, DT= .01 SEC\n1 2\n3.0x\n"); }).find("rec.AT2:6: value '3.0x' is not a number"),
            std::string::npos);
  EXPECT_NE(error_of([&] { at2("A\nB\n"); }).find("rec.AT2:3: PEER .AT2 file ends inside its 4 header lines"),
            std::string::npos);
  EXPECT_NE(error_of([&] { at2("A\nB\nACCELERATION IN UNITS OF CM/S/S\nNPTS= 2, DT= .01\n1 2\n"); })
                .find("rec.AT2:3: units 'CM/S/S' are not supported"),
            std::string::npos);
}

TEST(Accelerogram, CsvRoundTrip) {
  const Wavelet f;
  const Accelerogram r = integrate(0.01, sample(f, 0.01));
  const std::string path = ::testing::TempDir() + "dsdem_roundtrip.csv";
  write_accelerogram_csv(path, r);
  const Accelerogram back = read_accelerogram_csv(path, AccelUnits::MetresPerSecondSquared, kRaw);
  ASSERT_EQ(back.size(), r.size());
  EXPECT_NEAR(back.dt, r.dt, 1e-12);
  for (std::size_t i = 0; i < r.size(); ++i) ASSERT_NEAR(back.a[i], r.a[i], 1e-8 * max_abs(r.a));
  std::remove(path.c_str());
}

TEST(Accelerogram, UnitsParsingAndBadInput) {
  EXPECT_EQ(parse_accel_units("g"), AccelUnits::G);
  EXPECT_EQ(parse_accel_units("m/s2"), AccelUnits::MetresPerSecondSquared);
  EXPECT_EQ(parse_accel_units("M/S^2"), AccelUnits::MetresPerSecondSquared);
  EXPECT_THROW(parse_accel_units("gal"), std::runtime_error);
  EXPECT_THROW(integrate(-0.01, {1.0, 2.0}), std::runtime_error);
  EXPECT_THROW(integrate(0.01, {1.0}), std::runtime_error);
  EXPECT_THROW(integrate(0.01, {1.0, 2.0, 3.0}, BaselineOptions{true, 0}), std::runtime_error);
}
