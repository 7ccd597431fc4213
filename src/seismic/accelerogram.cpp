#include "seismic/accelerogram.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <istream>
#include <stdexcept>

#include <fmt/format.h>

#include "model/types.hpp"

namespace dsdem::seismic {

namespace {

[[noreturn]] void fail(const std::string& name, int line, const std::string& what) {
  if (line > 0) throw std::runtime_error(fmt::format("{}:{}: {}", name, line, what));
  throw std::runtime_error(fmt::format("{}: {}", name, what));
}

std::string trim(const std::string& s) {
  std::size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// Locale-independent parse of a whole token as a finite double ('+' and Fortran 'D'
// exponents accepted). Returns false if the token is not entirely a number.
bool parse_double(std::string token, double& out) {
  if (!token.empty() && token[0] == '+') token.erase(0, 1);
  for (char& c : token)
    if (c == 'd' || c == 'D') c = 'E';
  if (token.empty()) return false;
  const char* first = token.data();
  const char* last = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(first, last, out);
  return ec == std::errc() && ptr == last && std::isfinite(out);
}

std::vector<std::string> split_whitespace(const std::string& line) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    std::size_t j = i;
    while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

// Fields of a CSV line: split on ',' or ';' when present (so an empty field is seen),
// otherwise on tabs/spaces.
std::vector<std::string> split_fields(const std::string& line) {
  char sep = 0;
  if (line.find(',') != std::string::npos) sep = ',';
  else if (line.find(';') != std::string::npos) sep = ';';
  if (sep == 0) return split_whitespace(line);
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    std::size_t pos = line.find(sep, start);
    out.push_back(trim(line.substr(start, pos == std::string::npos ? std::string::npos : pos - start)));
    if (pos == std::string::npos) break;
    start = pos + 1;
  }
  return out;
}

// Legendre polynomials P_0..P_m at s in [-1, 1]: a well-conditioned basis for the
// baseline polynomial.
void legendre(double s, int m, std::vector<double>& p) {
  p.assign(static_cast<std::size_t>(m) + 1, 0.0);
  p[0] = 1.0;
  if (m >= 1) p[1] = s;
  for (int k = 1; k < m; ++k)
    p[k + 1] = ((2.0 * k + 1.0) * s * p[k] - k * p[k - 1]) / (k + 1.0);
}

void trapezoid(const std::vector<double>& f, double dt, std::vector<double>& out) {
  out.assign(f.size(), 0.0);
  for (std::size_t i = 1; i < f.size(); ++i) out[i] = out[i - 1] + 0.5 * dt * (f[i - 1] + f[i]);
}

void baseline_correct(Accelerogram& r, int degree) {
  const std::size_t n = r.size();
  const int m = degree + 1;  // number of polynomial coefficients
  const double T = r.duration();
  // Basis functions of the acceleration correction and their trapezoidal integrals.
  Eigen::MatrixXd phi(n, m), V(n, m), D(n, m);
  std::vector<double> p;
  for (std::size_t i = 0; i < n; ++i) {
    legendre(2.0 * (r.dt * static_cast<double>(i)) / T - 1.0, degree, p);
    for (int k = 0; k < m; ++k) phi(i, k) = p[k];
  }
  std::vector<double> col(n), iv, id;
  for (int k = 0; k < m; ++k) {
    for (std::size_t i = 0; i < n; ++i) col[i] = phi(i, k);
    trapezoid(col, r.dt, iv);
    trapezoid(iv, r.dt, id);
    for (std::size_t i = 0; i < n; ++i) {
      V(i, k) = iv[i];
      D(i, k) = id[i];
    }
  }
  // Equality constraints G c = g: the corrected final velocity and displacement are 0.
  Eigen::MatrixXd G(2, m);
  G.row(0) = V.row(n - 1);
  G.row(1) = D.row(n - 1);
  Eigen::Vector2d g(r.v[n - 1], r.d[n - 1]);
  Eigen::Map<const Eigen::VectorXd> d(r.d.data(), static_cast<Eigen::Index>(n));
  // Null-space method: G^T = Q R; c = Q1 R^-T g + Q2 w, w from least squares on d.
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(G.transpose());
  Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(m, m);
  Eigen::Matrix2d R = qr.matrixQR().topLeftCorner(2, 2).triangularView<Eigen::Upper>();
  Eigen::VectorXd c = Q.leftCols(2) * R.transpose().triangularView<Eigen::Lower>().solve(g);
  if (m > 2) {
    Eigen::MatrixXd Z = Q.rightCols(m - 2);
    Eigen::MatrixXd DZ = D * Z;
    Eigen::VectorXd rhs = d - D * c;
    Eigen::VectorXd w = DZ.colPivHouseholderQr().solve(rhs);
    c += Z * w;
  }
  Eigen::VectorXd pa = phi * c, pv = V * c, pd = D * c;
  for (std::size_t i = 0; i < n; ++i) {
    r.a[i] -= pa[static_cast<Eigen::Index>(i)];
    r.v[i] -= pv[static_cast<Eigen::Index>(i)];
    r.d[i] -= pd[static_cast<Eigen::Index>(i)];
  }
}

std::vector<double> linear_resample(const std::vector<double>& t, const std::vector<double>& f,
                                    double dt) {
  const double T = t.back() - t.front();
  const std::size_t n = static_cast<std::size_t>(std::floor(T / dt * (1.0 + 1e-12))) + 1;
  std::vector<double> out(n);
  std::size_t j = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double ti = t.front() + dt * static_cast<double>(i);
    while (j + 2 < t.size() && t[j + 1] <= ti) ++j;
    const double s = std::clamp((ti - t[j]) / (t[j + 1] - t[j]), 0.0, 1.0);
    out[i] = f[j] + s * (f[j + 1] - f[j]);
  }
  return out;
}

}  // namespace

double Accelerogram::pga() const {
  double m = 0.0;
  for (double x : a) m = std::max(m, std::abs(x));
  return m;
}

MotionSample Accelerogram::at(double t) const {
  if (a.empty() || t <= 0.0) {
    if (a.empty() || t < 0.0) return {};
    return {a[0], v[0], d[0]};
  }
  const double T = duration();
  if (t > T) {
    const double vl = v.back();
    return {0.0, vl, d.back() + vl * (t - T)};
  }
  const double x = t / dt;
  std::size_t i = static_cast<std::size_t>(x);
  if (i + 1 >= a.size()) i = a.size() - 2;
  const double s = x - static_cast<double>(i);
  return {a[i] + s * (a[i + 1] - a[i]), v[i] + s * (v[i + 1] - v[i]), d[i] + s * (d[i + 1] - d[i])};
}

AccelUnits parse_accel_units(const std::string& text) {
  const std::string u = upper(trim(text));
  if (u == "G") return AccelUnits::G;
  if (u == "M/S2" || u == "M/S^2" || u == "MPS2" || u == "M/S**2") return AccelUnits::MetresPerSecondSquared;
  throw std::runtime_error(fmt::format("unknown acceleration units '{}' (valid: g, m/s2)", text));
}

double to_si_factor(AccelUnits units) {
  return units == AccelUnits::G ? kStandardGravity : 1.0;
}

Accelerogram integrate(double dt, std::vector<double> a, const BaselineOptions& baseline) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw std::runtime_error(fmt::format("accelerogram: time step must be positive, got {}", dt));
  if (a.size() < 2)
    throw std::runtime_error(fmt::format("accelerogram: need at least 2 samples, got {}", a.size()));
  if (baseline.enabled && baseline.degree < 1)
    throw std::runtime_error(fmt::format("accelerogram: baseline degree must be >= 1, got {}", baseline.degree));
  if (baseline.enabled && a.size() < static_cast<std::size_t>(baseline.degree) + 2)
    throw std::runtime_error(fmt::format("accelerogram: {} samples are too few for a degree-{} baseline correction",
                                         a.size(), baseline.degree));
  Accelerogram r;
  r.dt = dt;
  r.a = std::move(a);
  trapezoid(r.a, dt, r.v);
  trapezoid(r.v, dt, r.d);
  if (baseline.enabled) baseline_correct(r, baseline.degree);
  return r;
}

Accelerogram resample(const Accelerogram& record, double dt, const BaselineOptions& baseline) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw std::runtime_error(fmt::format("accelerogram: resampling time step must be positive, got {}", dt));
  if (record.size() < 2 || !(record.dt > 0.0))
    throw std::runtime_error("accelerogram: cannot resample an empty record");
  std::vector<double> t(record.size());
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = record.dt * static_cast<double>(i);
  return integrate(dt, linear_resample(t, record.a, dt), baseline);
}

void scale(Accelerogram& record, double factor) {
  for (double& x : record.a) x *= factor;
  for (double& x : record.v) x *= factor;
  for (double& x : record.d) x *= factor;
}

Accelerogram read_accelerogram_csv(std::istream& in, const std::string& name, AccelUnits units,
                                   const BaselineOptions& baseline) {
  std::vector<double> t, a;
  std::string raw;
  int line_no = 0;
  bool header_allowed = true;
  while (std::getline(in, raw)) {
    ++line_no;
    const std::string line = trim(raw);
    if (line.empty() || line[0] == '#') continue;
    const auto fields = split_fields(line);
    double tv = 0.0, av = 0.0;
    const bool t_ok = !fields.empty() && parse_double(fields[0], tv);
    const bool a_ok = fields.size() >= 2 && parse_double(fields[1], av);
    if (header_allowed && !t_ok) {  // a header line: column names
      header_allowed = false;
      if (fields.size() < 2)
        fail(name, line_no, fmt::format("header has {} column(s); need at least 2 (t, a)", fields.size()));
      continue;
    }
    header_allowed = false;
    if (fields.size() < 2)
      fail(name, line_no, fmt::format("expected 2 columns (t, a), found {}", fields.size()));
    if (!t_ok) fail(name, line_no, fmt::format("time '{}' is not a number", fields[0]));
    if (!a_ok) fail(name, line_no, fmt::format("acceleration '{}' is not a number", fields[1]));
    if (!t.empty() && !(tv > t.back()))
      fail(name, line_no, fmt::format("time {} does not increase (previous sample at {})", tv, t.back()));
    t.push_back(tv);
    a.push_back(av * to_si_factor(units));
  }
  if (t.size() < 2) fail(name, 0, fmt::format("need at least 2 samples, found {}", t.size()));
  // Uniform sampling within rounding of the printed times: use it as it is.
  const double mean_dt = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  double min_dt = mean_dt, max_dev = 0.0;
  for (std::size_t i = 1; i < t.size(); ++i) {
    min_dt = std::min(min_dt, t[i] - t[i - 1]);
    max_dev = std::max(max_dev, std::abs(t[i] - t[i - 1] - mean_dt));
  }
  if (max_dev <= 1e-4 * mean_dt) return integrate(mean_dt, std::move(a), baseline);
  // Irregular steps are resampled at the smallest one. A record whose smallest step is
  // tiny against its length would become hundreds of millions of samples (minutes of
  // work, gigabytes, with its baseline correction): refuse it with the numbers.
  constexpr double kMaxResampled = 1e6;  // e.g. 83 min at 0.005 s; real records are minutes long
  const double resampled = (t.back() - t.front()) / min_dt + 1.0;
  if (!(resampled <= kMaxResampled))
    fail(name, 0, fmt::format("irregular time steps from {:.6g} s over {:.6g} s would need {:.3g} samples once resampled "
                              "at the smallest step (limit {:.0g}): check the time column",
                              min_dt, t.back() - t.front(), resampled, kMaxResampled));
  return integrate(min_dt, linear_resample(t, a, min_dt), baseline);
}

Accelerogram read_accelerogram_csv(const std::string& path, AccelUnits units, const BaselineOptions& baseline) {
  std::ifstream in(path);
  if (!in) fail(path, 0, "cannot open file");
  return read_accelerogram_csv(in, path, units, baseline);
}

Accelerogram read_accelerogram_at2(std::istream& in, const std::string& name, const BaselineOptions& baseline) {
  std::string header[4];
  for (int i = 0; i < 4; ++i) {
    if (!std::getline(in, header[i]))
      fail(name, i + 1, "PEER .AT2 file ends inside its 4 header lines");
  }
  // Line 3 states the units; the values must be in g.
  const std::string l3 = upper(header[2]);
  const auto units_pos = l3.find("UNITS OF");
  if (units_pos != std::string::npos) {
    const std::string u = trim(l3.substr(units_pos + 8));
    if (u.empty() || u[0] != 'G')
      fail(name, 3, fmt::format("units '{}' are not supported; PEER .AT2 values must be in g", trim(header[2].substr(units_pos + 8))));
  }
  // Line 4: "NPTS=  5000, DT= .0050 SEC" or the older "5000 0.005 ...".
  const std::string l4 = upper(header[3]);
  double npts_d = 0.0, dt = 0.0;
  const auto np = l4.find("NPTS");
  if (np != std::string::npos && l4.find('=') != std::string::npos) {
    auto value_after = [&](std::size_t key_end, const char* key, double& out) {
      std::size_t eq = l4.find('=', key_end);
      if (eq == std::string::npos) fail(name, 4, fmt::format("no '=' after {}", key));
      std::size_t b = eq + 1;
      while (b < l4.size() && std::isspace(static_cast<unsigned char>(l4[b]))) ++b;
      std::size_t e = b;
      while (e < l4.size() && (std::isdigit(static_cast<unsigned char>(l4[e])) || l4[e] == '.' || l4[e] == '-' ||
                               l4[e] == '+' || l4[e] == 'E'))
        ++e;
      if (!parse_double(l4.substr(b, e - b), out))
        fail(name, 4, fmt::format("cannot read the value of {} in '{}'", key, trim(header[3])));
    };
    value_after(np + 4, "NPTS", npts_d);
    const auto dp = l4.find("DT", np + 4);
    if (dp == std::string::npos) fail(name, 4, fmt::format("no DT in '{}'", trim(header[3])));
    value_after(dp + 2, "DT", dt);
  } else {
    std::string l = header[3];
    for (char& ch : l)
      if (ch == ',') ch = ' ';
    auto tok = split_whitespace(l);
    if (tok.size() < 2 || !parse_double(tok[0], npts_d) || !parse_double(tok[1], dt))
      fail(name, 4, fmt::format("expected NPTS and DT, as 'NPTS= 5000, DT= .005 SEC' or '5000 0.005', got '{}'",
                                trim(header[3])));
  }
  if (npts_d < 2 || npts_d != std::floor(npts_d) || npts_d > 1e9)
    fail(name, 4, fmt::format("NPTS must be an integer >= 2, got {}", npts_d));
  if (!(dt > 0.0)) fail(name, 4, fmt::format("DT must be positive, got {}", dt));
  const std::size_t npts = static_cast<std::size_t>(npts_d);
  std::vector<double> a;
  // NPTS is only a claim until the values are read: do not let a damaged header reserve
  // gigabytes (found by fuzzing).
  a.reserve(std::min<std::size_t>(npts, 1u << 16));
  std::string raw;
  int line_no = 4;
  while (std::getline(in, raw)) {
    ++line_no;
    for (std::string& tok : split_whitespace(raw)) {
      double x = 0.0;
      if (!parse_double(tok, x)) fail(name, line_no, fmt::format("value '{}' is not a number", tok));
      if (a.size() == npts)
        fail(name, line_no, fmt::format("more values than NPTS = {}", npts));
      a.push_back(x * kStandardGravity);
    }
  }
  if (a.size() != npts)
    fail(name, line_no, fmt::format("file ends after {} values; NPTS = {}", a.size(), npts));
  return integrate(dt, std::move(a), baseline);
}

Accelerogram read_accelerogram_at2(const std::string& path, const BaselineOptions& baseline) {
  std::ifstream in(path);
  if (!in) fail(path, 0, "cannot open file");
  return read_accelerogram_at2(in, path, baseline);
}

Accelerogram read_accelerogram(const std::string& path, AccelUnits csv_units, const BaselineOptions& baseline) {
  const auto dot = path.rfind('.');
  if (dot != std::string::npos && upper(path.substr(dot)) == ".AT2") return read_accelerogram_at2(path, baseline);
  return read_accelerogram_csv(path, csv_units, baseline);
}

void write_accelerogram_csv(const std::string& path, const Accelerogram& record) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(fmt::format("{}: cannot open for writing", path));
  out << "t_s,a_mps2,v_mps,d_m\n";
  for (std::size_t i = 0; i < record.size(); ++i)
    out << fmt::format("{:.10g},{:.9e},{:.9e},{:.9e}\n", record.dt * static_cast<double>(i), record.a[i],
                       record.v[i], record.d[i]);
  if (!out) throw std::runtime_error(fmt::format("{}: write failed", path));
}

}  // namespace dsdem::seismic
