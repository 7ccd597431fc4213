// Validation cases of docs/validation.md §1-2, fast coarse variants (§3) run through the CLI:
// the Brazilian disc and the four-point impact beam. The full runs are the examples
// (examples/brazilian_disc, examples/beam_impact; docs/validation.md); these variants
// use coarser meshes and, for the disc, a faster plate, and assert golden numbers of
// those variants with stated tolerances plus the acceptance checks that a coarse mesh
// can carry.
#include <gtest/gtest.h>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli_util.hpp"

using namespace dsdem::test;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

// OUT/history.csv by column name.
std::map<std::string, std::vector<double>> read_history(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream hs(line);
  for (std::string c; std::getline(hs, c, ',');) names.push_back(c);
  std::map<std::string, std::vector<double>> cols;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::size_t k = 0;
    for (std::string c; std::getline(ls, c, ',') && k < names.size(); ++k) cols[names[k]].push_back(std::stod(c));
  }
  return cols;
}

struct Crack {
  double t, x, y;
  std::string mode;
};

std::vector<Crack> read_cracks(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);  // joint,time_s,x_m,y_m,mode,property,curve
  std::vector<Crack> out;
  while (std::getline(in, line)) {
    std::vector<std::string> v;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) v.push_back(c);
    out.push_back({std::stod(v[1]), std::stod(v[2]), std::stod(v[3]), v[4]});
  }
  return out;
}

double json_number(const std::string& text, const std::string& key) {
  const std::regex re("\"" + key + "\": ([-0-9.eE+]+)");
  std::smatch m;
  if (!std::regex_search(text, m, re)) return std::nan("");
  return std::stod(m[1]);
}

// (time, file) of each frame of a .pvd series.
std::vector<std::pair<double, fs::path>> read_pvd(const fs::path& out, const std::string& name) {
  const std::string text = read_text(out / (name + ".pvd"));
  const std::regex re("timestep=\"([-0-9.eE+]+)\"[^>]*file=\"([^\"]+)\"");
  std::vector<std::pair<double, fs::path>> frames;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it)
    frames.emplace_back(std::stod((*it)[1]), out / (*it)[2].str());
  std::sort(frames.begin(), frames.end());
  return frames;
}

// One frame of the triangles: reference centroids, areas, stress, zone, fragment.
struct Frame {
  std::vector<std::array<double, 2>> centroid0;
  std::vector<std::array<std::array<double, 2>, 3>> vertex0;  // reference vertices
  std::vector<double> area0;
  std::vector<std::array<double, 3>> stress;
  std::vector<int> zone, fragment;
};

Frame read_frame(const fs::path& file) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkUnstructuredGrid* g = reader->GetOutput();
  vtkDataArray* u = g->GetPointData()->GetArray("displacement_m");
  vtkDataArray* s = g->GetCellData()->GetArray("stress_Pa");
  vtkDataArray* z = g->GetCellData()->GetArray("zone");
  vtkDataArray* fr = g->GetCellData()->GetArray("fragment");
  Frame f;
  if (!u || !s || !z) return f;
  const vtkIdType n = g->GetNumberOfCells();
  for (vtkIdType c = 0; c < n; ++c) {
    vtkIdType np;
    const vtkIdType* ids;
    g->GetCellPoints(c, np, ids);
    std::array<std::array<double, 2>, 3> X{};
    for (int k = 0; k < 3; ++k) {
      double p[3], d[3];
      g->GetPoint(ids[k], p);
      u->GetTuple(ids[k], d);
      X[k] = {p[0] - d[0], p[1] - d[1]};
    }
    f.centroid0.push_back({(X[0][0] + X[1][0] + X[2][0]) / 3, (X[0][1] + X[1][1] + X[2][1]) / 3});
    f.vertex0.push_back(X);
    f.area0.push_back(0.5 * std::abs((X[1][0] - X[0][0]) * (X[2][1] - X[0][1]) - (X[1][1] - X[0][1]) * (X[2][0] - X[0][0])));
    double t[3];
    s->GetTuple(c, t);
    f.stress.push_back({t[0], t[1], t[2]});
    f.zone.push_back(static_cast<int>(z->GetTuple1(c)));
    f.fragment.push_back(fr ? static_cast<int>(fr->GetTuple1(c)) : -1);
  }
  return f;
}

// Areas of the pieces of the zone-0 (discrete) triangles, largest first.
std::vector<double> pieces(const Frame& f) {
  std::map<int, double> area;
  for (std::size_t t = 0; t < f.zone.size(); ++t)
    if (f.zone[t] == 0) area[f.fragment[t]] += f.area0[t];
  std::vector<double> a;
  for (const auto& [k, v] : area) a.push_back(v);
  std::sort(a.rbegin(), a.rend());
  return a;
}

// Point-load elastic solution of the disc (Hondros with alpha -> 0) at (x, y), disc
// centre at the origin, loads at (0, +-R) (Timoshenko & Goodier): (sigma_xx, sigma_yy) /
// sigma_0, sigma_0 = 2P/(pi D t). On the diameters: loaded (x = 0) sigma_xx = 1,
// sigma_yy = -(3 + rho^2)/(1 - rho^2); unloaded (y = 0) sigma_xx = ((1 - rho^2)/(1 + rho^2))^2,
// sigma_yy = -(1 - rho^2)(3 + rho^2)/(1 + rho^2)^2.
std::array<double, 2> point_load(double x, double y, double R) {
  const double r1 = x * x + (R - y) * (R - y), r2 = x * x + (R + y) * (R + y);
  return {1 - 2 * R * (x * x * (R - y) / (r1 * r1) + x * x * (R + y) / (r2 * r2)),
          1 - 2 * R * (std::pow(R - y, 3) / (r1 * r1) + std::pow(R + y, 3) / (r2 * r2))};
}

// Band mean around a point, like with like (scripts/validate_brazilian.py): the
// area-weighted mean of the constant stresses of the discrete triangles whose centroid
// lies within radius of (x, y), and the same weighted mean of the analytic stress
// averaged over each of those triangles (edge-midpoint rule). A CST field's band mean is
// compared with the analytic field's band mean, not with its value at the point (which
// would count the curvature of the field across the band as an error).
struct BandMean {
  std::array<double, 2> num{0, 0}, analytic{0, 0};  // (sigma_xx, sigma_yy), analytic / sigma_0
};
BandMean band_mean(const Frame& f, double x, double y, double radius, double R) {
  BandMean b;
  double w = 0;
  for (std::size_t t = 0; t < f.zone.size(); ++t) {
    if (f.zone[t] != 0 || std::hypot(f.centroid0[t][0] - x, f.centroid0[t][1] - y) > radius) continue;
    const auto& v = f.vertex0[t];
    for (int k = 0; k < 2; ++k) b.num[k] += f.area0[t] * f.stress[t][k];
    for (int e = 0; e < 3; ++e) {
      const auto& p = v[e];
      const auto& q = v[(e + 1) % 3];
      const auto a = point_load(0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), R);
      for (int k = 0; k < 2; ++k) b.analytic[k] += f.area0[t] * a[k] / 3;
    }
    w += f.area0[t];
  }
  for (int k = 0; k < 2; ++k) {
    b.num[k] = w > 0 ? b.num[k] / w : std::nan("");
    b.analytic[k] = w > 0 ? b.analytic[k] / w : std::nan("");
  }
  return b;
}

double interp(const std::vector<double>& x, const std::vector<double>& y, double xi) {
  const auto it = std::lower_bound(x.begin(), x.end(), xi);
  if (it == x.begin()) return y.front();
  if (it == x.end()) return y.back();
  const std::size_t k = static_cast<std::size_t>(it - x.begin());
  return y[k - 1] + (y[k] - y[k - 1]) * (xi - x[k - 1]) / (x[k] - x[k - 1]);
}

double wall_seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

// Brazilian disc, coarse: element size 13 mm (5.5 mm on the loaded diameter, 1500
// triangles), top plate at 0.1 m/s (ramped over 0.5 ms) instead of 0.01 m/s; the
// paper's material, the example's mesh (loaded diameter in the mesh). Golden numbers are
// those of this variant (the faster plate adds about 3 % to the peak: docs/validation.md);
// the full case is the example.
TEST(Validation, BrazilianDiscCoarse) {
  const fs::path out = fresh_dir("brazilian");
  const auto t0 = std::chrono::steady_clock::now();
  const auto c = run_dsdem("run " + example("brazilian_disc/scenario.yaml") + " -o " + out.string() +
                           " --threads 1 -q --set mesh.element_size=0.013 --set stages.0.duration=0.0045"
                           " --set stages.0.boundaries.1.y=[[0,0],[0.0005,-0.1]]"
                           " --set output.field_interval=0.0001 --set output.history_interval=0.00001");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const double wall = wall_seconds(t0);
  RecordProperty("wall_time_s", std::to_string(wall));

  const double R = 0.1, D = 2 * R, t = 1.0, ft = 2.5e6;
  const double scale = kPi * D * t / 2;  // P = scale * sigma_t
  auto h = read_history(out / "history.csv");
  const auto& time = h["time_s"];
  // Load on the disc: mean of the two plates' reactions (cancels the inertia of the
  // disc rattling between the contacts).
  std::vector<double> P(time.size());
  for (std::size_t i = 0; i < P.size(); ++i)
    P[i] = 0.5 * (h["bottom_plate_reaction_y_N_per_m"][i] - h["top_plate_reaction_y_N_per_m"][i]);
  const std::size_t ipk = static_cast<std::size_t>(std::max_element(P.begin(), P.end()) - P.begin());
  const double P_peak = P[ipk];
  const double sigma_t = P_peak / scale;

  // Golden (this variant, penalty joints kn = 10 E / h_local): peak 0.8074 MN/m,
  // sigma_t = 2.570 MPa (+2.8 %; +2.2 % with the former disc-wide mean h). Tolerance
  // 1 %: mesh and loading are fixed, the number moves only with the physics. The
  // acceptance of the full case, |sigma_t - ft| <= 3 % ft, holds here too.
  RecordProperty("peak_load_N_per_m", std::to_string(P_peak));  // in --gtest_output=xml
  EXPECT_NEAR(P_peak, 807411.0, 0.01 * 807411.0) << "sigma_t = " << sigma_t;
  EXPECT_LE(std::abs(sigma_t - ft), 0.03 * ft) << "sigma_t = " << sigma_t;

  // Crack: the first joints break near the loaded diameter, away from the plates, and
  // the crack runs through along it (within 0.1 R) after the peak.
  const auto cracks = read_cracks(out / "cracks.csv");
  ASSERT_FALSE(cracks.empty());
  EXPECT_LT(std::abs(cracks.front().x), 0.1 * R);
  EXPECT_LT(std::abs(cracks.front().y), 0.5 * R);
  EXPECT_GE(cracks.front().t, time[ipk] - 1e-4);
  auto through_time = [&](double band) {
    std::vector<double> ys;
    for (const auto& k : cracks) {
      if (std::abs(k.x) > band * R) continue;
      if (std::abs(k.y) <= 0.8 * R) ys.push_back(k.y);
      std::vector<double> cover = ys;
      cover.push_back(-0.8 * R);
      cover.push_back(0.8 * R);
      std::sort(cover.begin(), cover.end());
      double gap = 0;
      for (std::size_t i = 1; i < cover.size(); ++i) gap = std::max(gap, cover[i] - cover[i - 1]);
      if (gap <= 0.1 * R) return k.t;
    }
    return std::nan("");
  };
  const double t_through = through_time(0.1);
  ASSERT_FALSE(std::isnan(t_through)) << "no crack through the disc within 0.1 R of the loaded diameter";
  RecordProperty("through_crack_s", std::to_string(t_through));
  EXPECT_NEAR(t_through, 0.00332, 1e-4);  // golden 3.32 ms (3.39 ms with the mean h)
  // Split: the load has dropped (the halves stay pressed between the plates through
  // the crushed wedges under them, which keep carrying some load).
  EXPECT_LT(P.back(), 0.6 * P_peak);

  // Stresses before cracking (frame nearest half the peak load): within 5 % of the
  // point-load solution for |r| <= 0.3 R on both diameters (error relative to
  // max(|analytic|, sigma_0); band means over 8 mm around each point, the analytic
  // field averaged over the same triangles: like with like, as the acceptance script
  // does; comparing the band mean with the point value instead adds up to 1.2 points,
  // 5.4 % instead of 4.2 % at p = 10). The coarse mesh does not resolve the gradients
  // nearer the plates (docs/validation.md).
  const auto frames = read_pvd(out, "fields");
  ASSERT_GT(frames.size(), 5u);
  std::size_t best = 0;
  for (std::size_t k = 0; k < frames.size(); ++k)
    if (frames[k].first <= time[ipk] &&
        std::abs(interp(time, P, frames[k].first) - 0.5 * P_peak) <
            std::abs(interp(time, P, frames[best].first) - 0.5 * P_peak))
      best = k;
  const Frame f = read_frame(frames[best].second);
  ASSERT_FALSE(f.zone.empty());
  const double sigma0 = interp(time, P, frames[best].first) / scale;
  double worst = 0;
  for (int diameter = 0; diameter < 2; ++diameter)
    for (double rho = -0.3; rho <= 0.3 + 1e-9; rho += 0.1) {
      const double x = diameter == 0 ? 0.0 : rho * R, y = diameter == 0 ? rho * R : 0.0;
      const BandMean b = band_mean(f, x, y, 0.008, R);
      for (int k = 0; k < 2; ++k) {
        const double num = b.num[k] / sigma0, a = b.analytic[k];
        const double err = std::abs(num - a) / std::max(std::abs(a), 1.0);
        worst = std::max(worst, err);
        EXPECT_LT(err, 0.05) << (diameter == 0 ? "loaded" : "unloaded") << " diameter, rho = " << rho
                             << (k == 0 ? ", sigma_xx" : ", sigma_yy") << ": " << num << " vs " << a;
      }
    }
  RecordProperty("stress_max_error", std::to_string(worst));

  // The frames carry the fragment of each triangle, numbered as the history counts
  // them. (The disc's halves stay bonded through the crushed wedges under the plates,
  // where the joints are in compression: topologically it is still one piece.)
  const Frame last = read_frame(frames.back().second);
  ASSERT_NE(last.fragment.front(), -1) << "no 'fragment' cell field in the frames";
  const int labels = *std::max_element(last.fragment.begin(), last.fragment.end()) + 1;
  EXPECT_EQ(labels, static_cast<int>(h["fragments"].back()));
  EXPECT_EQ(pieces(last).size(), 1u);

  const std::string summary = read_text(out / "summary.json");
  EXPECT_LT(json_number(summary, "energy_balance_error"), 0.02);
  fs::remove_all(out);
}

// Impact beam, coarse: element size 25 mm (6 elements over the depth), the example's
// 10 ms after the strike. Golden numbers of this variant; the full case is the example.
TEST(Validation, ImpactBeamCoarse) {
  const fs::path out = fresh_dir("beam");
  const auto t0 = std::chrono::steady_clock::now();
  const auto c = run_dsdem("run " + example("beam_impact/scenario.yaml") + " -o " + out.string() +
                           " --threads 1 -q --set mesh.element_size=0.025 --set output.field_interval=0.0005");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  RecordProperty("wall_time_s", std::to_string(wall_seconds(t0)));
  const double H = 0.152, heads = 0.203 / 2, head_radius = 0.025;

  auto h = read_history(out / "history.csv");
  const auto& uy = h["midspan_displacement_y_m"];
  // The mid-span piece is carried down by the impactor: the largest deflection is the
  // last one (golden 51.3 mm, 10 %; 48.3 mm with the former disc-wide mean element size
  // in the penalty rule, now kn = 10 E / h_local).
  const double max_defl = -*std::min_element(uy.begin(), uy.end());
  RecordProperty("max_deflection_m", std::to_string(max_defl));
  EXPECT_NEAR(max_defl, 0.0513, 0.1 * 0.0513);

  // First crack, apart from the crushing under the heads: bottom face, under the
  // impactor, at t = 0.44 ms.
  const auto all = read_cracks(out / "cracks.csv");
  std::vector<Crack> cracks;
  for (const auto& k : all)
    if (std::min(std::hypot(k.x - heads, k.y - H), std::hypot(k.x + heads, k.y - H)) > 2 * head_radius)
      cracks.push_back(k);
  ASSERT_FALSE(cracks.empty());
  EXPECT_LT(std::abs(cracks.front().x), heads + 0.05) << cracks.front().x;
  EXPECT_LT(cracks.front().y, 0.2 * H) << cracks.front().y;
  RecordProperty("first_crack_s", std::to_string(cracks.front().t));
  EXPECT_NEAR(cracks.front().t, 0.442e-3, 0.05e-3);
  // Cracks near the quarter points (0.25 m <= |x| <= 0.55 m) on both halves.
  bool left = false, right = false;
  for (const auto& k : cracks) {
    left = left || (k.x <= -0.25 && k.x >= -0.55);
    right = right || (k.x >= 0.25 && k.x <= 0.55);
  }
  EXPECT_TRUE(left && right);

  // Pieces of at least 1 % of the beam at the end: 8 on this mesh with kn = 10 E / h_local
  // (7 with the former mean h; 5 in the example).
  const auto frames = read_pvd(out, "fields");
  const Frame last = read_frame(frames.back().second);
  const auto a = pieces(last);
  const double beam_area = std::accumulate(a.begin(), a.end(), 0.0);
  int n = 0;
  for (double v : a) n += v >= 0.01 * beam_area ? 1 : 0;
  RecordProperty("pieces", std::to_string(n));
  EXPECT_NEAR(n, 8, 1);
  const std::string summary = read_text(out / "summary.json");
  EXPECT_LT(json_number(summary, "energy_balance_error"), 0.02);
  fs::remove_all(out);
}
