// TEMPORARY: the strict .msh reader against the Gmsh-API reader on every mesh the project uses.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "mesh/gmsh_reader.hpp"
#include "mesh/msh_format.hpp"

using namespace dsdem;
namespace fs = std::filesystem;

namespace {

std::string slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string diff(const RawMesh& a, const RawMesh& b) {
  if (a.nodes.size() != b.nodes.size()) return "node count";
  for (size_t i = 0; i < a.nodes.size(); ++i)
    if (a.nodes[i] != b.nodes[i]) return "node " + std::to_string(i);
  if (a.triangles != b.triangles) return "triangles";
  if (a.triangle_surface_group != b.triangle_surface_group) return "triangle_surface_group";
  if (a.groups.size() != b.groups.size()) return "group count";
  for (size_t i = 0; i < a.groups.size(); ++i) {
    const auto &g = a.groups[i], &h = b.groups[i];
    if (g.name != h.name || g.dim != h.dim || g.tag != h.tag) return "group head " + g.name + " vs " + h.name;
    if (g.triangles != h.triangles) return "group triangles " + g.name;
    if (g.edges != h.edges) return "group edges " + g.name;
    if (g.nodes != h.nodes) return "group nodes " + g.name;
  }
  return "";
}

std::string run_old(const std::string& p, RawMesh& m) {
  try {
    m = mesh::read_msh(p);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}
std::string run_new(const std::string& p, RawMesh& m) {
  try {
    m = mesh::to_raw_mesh(mesh::parse_msh(slurp(p), p));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

void compare(const std::string& p) {
  RawMesh a, b;
  const std::string ea = run_old(p, a), eb = run_new(p, b);
  std::cout << p << ": nodes " << a.nodes.size() << " tris " << a.triangles.size() << " groups " << a.groups.size()
            << "\n   old err: " << ea << "\n   new err: " << eb << "\n";
  EXPECT_EQ(ea.empty(), eb.empty()) << p;
  if (ea.empty() && eb.empty()) EXPECT_EQ(diff(a, b), "") << p;
}

}  // namespace

TEST(MshCompare, AllProjectMeshes) {
  const std::string src = DSDEM_SOURCE_DIR;
  const fs::path dir = fs::temp_directory_path() / ("dsdem_msh_compare_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::vector<std::pair<std::string, double>> geos = {
      {"tests/data/mesh/square.geo", 0.2},         {"tests/data/mesh/square.geo", 0.07},
      {"tests/data/mesh/quad.geo", 0.5},           {"tests/data/mesh/orphan.geo", 0.5},
      {"examples/beam_impact/beam.geo", 0.01},     {"examples/brazilian_disc/disc.geo", 0.0087},
      {"examples/brazilian_disc/disc_refined.geo", 0.0087}, {"examples/brazilian_disc/disc_unaligned.geo", 0.0087},
      {"examples/elastic_slope/slope.geo", 2.5},   {"examples/dr2/dr2.geo", 4.0},
      {"examples/dr2/dr2.geo", 12.0},              {"examples/dr2/sensitivity/dr2_gentle.geo", 4.0},
      {"examples/dr2/sensitivity/dr2_gentle.geo", 8.0}};
  int k = 0;
  for (const auto& [geo, h] : geos) {
    for (const std::string fmt : {"msh41", "msh22"}) {
      const std::string out = (dir / (std::to_string(k++) + "." + fmt + ".msh")).string();
      const std::string cmd = std::string(DSDEM_GMSH_EXECUTABLE) + " -2 -format " + fmt + " -clmax " + std::to_string(h) +
                              " -o " + out + " " + src + "/" + geo + " > /dev/null 2>&1";
      ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
      std::cout << geo << " h=" << h << " ";
      compare(out);
    }
  }
  // Extra files given by hand (hand-made orderings, duplicated physicals).
  if (const char* extra = std::getenv("DSDEM_MSH_COMPARE_EXTRA")) {
    std::istringstream ss(extra);
    std::string p;
    while (ss >> p) compare(p);
  }
}

TEST(MshCompare, ReadTime) {
  const char* p = std::getenv("DSDEM_MSH_TIME");
  if (!p) GTEST_SKIP();
  for (int rep = 0; rep < 3; ++rep) {
    auto t0 = std::chrono::steady_clock::now();
    RawMesh a = mesh::read_msh(p);
    auto t1 = std::chrono::steady_clock::now();
    RawMesh b = mesh::to_raw_mesh(mesh::parse_msh(slurp(p), p));
    auto t2 = std::chrono::steady_clock::now();
    std::cout << "old " << std::chrono::duration<double>(t1 - t0).count() << " s, new "
              << std::chrono::duration<double>(t2 - t1).count() << " s\n";
  }
}
