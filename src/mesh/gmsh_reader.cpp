#include "mesh/gmsh_reader.hpp"

#include <fmt/format.h>
#include <gmsh.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <map>
#include <mutex>
#include <stdexcept>

#include "io/input_file.hpp"

namespace dsdem::mesh {

namespace {

// The Gmsh API is a process-wide singleton: serialise its use.
std::mutex& gmsh_mutex() {
  static std::mutex m;
  return m;
}

// Gmsh sets the process's OpenMP thread count to its own General.NumThreads (1) when
// it starts: the session puts the caller's count back, or every later parallel loop of
// the solver would run on one thread.
struct GmshSession {
  GmshSession() : omp_threads(omp_get_max_threads()) {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 0);
  }
  ~GmshSession() {
    gmsh::finalize();
    omp_set_num_threads(omp_threads);
  }
  int omp_threads;
};

constexpr int kGmshLine2 = 1;
constexpr int kGmshTriangle3 = 2;
constexpr int kGmshPoint = 15;

// Gmsh's own parser trusts its input (a damaged file can make it read out of bounds or
// stop the process), so a file goes to it only after this structural check: an ASCII
// .msh 2.x or 4.x whose sections are all closed ($Name ... $EndName), without NUL bytes.
// Throws std::runtime_error naming the file and the line.
void check_msh_structure(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open the mesh file", path));
  std::string line;
  long line_no = 0;
  std::string open_section;
  bool saw_format = false, saw_nodes = false;
  auto fail = [&](const std::string& what) {
    throw std::runtime_error(fmt::format("{}:{}: not a Gmsh ASCII .msh file: {}", path, line_no, what));
  };
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find('\0') != std::string::npos) fail("NUL byte (binary data; save the mesh as ASCII, Mesh.Binary = 0)");
    if (line_no == 1 && line != "$MeshFormat") fail("the first line must be $MeshFormat");
    if (line_no == 2) {
      std::istringstream v(line);
      double version = 0.0;
      int file_type = -1, data_size = 0;
      if (!(v >> version >> file_type >> data_size)) fail("expected 'version file-type data-size' after $MeshFormat");
      if (!(version >= 2.0 && version < 5.0)) fail(fmt::format("unsupported .msh version {} (write 4.1 or 2.2)", version));
      if (file_type != 0) fail("binary .msh (save the mesh as ASCII, Mesh.Binary = 0)");
      if (data_size != sizeof(double)) fail(fmt::format("data size {} (expected {})", data_size, sizeof(double)));
      saw_format = true;
    }
    if (open_section == "PhysicalNames" && !line.empty() && line[0] != '$') {
      // Gmsh 4.8 dereferences a bad iterator (SEGV) for a physical name of dimension
      // outside 0..3 (a fuzz find): entries are "dim tag \"name\"", dim 0..3, tag > 0.
      std::istringstream e(line);
      long dim = -1, tag = 0;
      if (e >> dim >> tag) {
        if (dim < 0 || dim > 3 || tag <= 0)
          fail(fmt::format("physical name with dimension {} and tag {} (dimension 0..3, tag > 0)", dim, tag));
      }
    }
    if (line.empty() || line[0] != '$') continue;
    if (line.rfind("$End", 0) == 0) {
      if (open_section.empty() || line.substr(4) != open_section)
        fail(fmt::format("'{}' without a matching ${}", line, line.substr(4)));
      open_section.clear();
    } else {
      if (!open_section.empty()) fail(fmt::format("${} is not closed before '{}'", open_section, line));
      open_section = line.substr(1);
      if (open_section == "Nodes" || open_section == "NOD") saw_nodes = true;
    }
  }
  if (line_no == 0) fail("empty file");
  if (!saw_format) fail("no version line after $MeshFormat");
  if (!open_section.empty()) fail(fmt::format("${} is not closed (truncated file?)", open_section));
  if (!saw_nodes) fail("no $Nodes section (was it meshed?)");
}

}  // namespace

RawMesh read_msh(const std::string& path) {
  if (const std::string problem = io::input_file_problem(path); !problem.empty())
    throw std::runtime_error(fmt::format("mesh: {}", problem));
  check_msh_structure(path);
  std::lock_guard<std::mutex> lock(gmsh_mutex());
  GmshSession session;
  try {
    gmsh::open(path);
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("{}: Gmsh cannot read this mesh: {}", path, e.what()));
  } catch (...) {
    throw std::runtime_error(fmt::format("{}: Gmsh cannot read this mesh", path));
  }

  RawMesh mesh;
  mesh.source = path;
  mesh.msh_file = path;

  std::vector<std::size_t> node_tags;
  std::vector<double> coords, param;
  gmsh::model::mesh::getNodes(node_tags, coords, param, -1, -1, false, false);
  if (node_tags.empty()) throw std::runtime_error(fmt::format("{}: the mesh has no nodes (was it meshed?)", path));
  std::map<std::size_t, Index> node_index;
  mesh.nodes.reserve(node_tags.size());
  for (std::size_t i = 0; i < node_tags.size(); ++i) {
    if (std::abs(coords[3 * i + 2]) > 0.0)
      throw std::runtime_error(fmt::format("{}: node {} has z = {} ; dsdem is 2D (x, y only)", path,
                                           node_tags[i], coords[3 * i + 2]));
    node_index[node_tags[i]] = static_cast<Index>(mesh.nodes.size());
    mesh.nodes.emplace_back(coords[3 * i], coords[3 * i + 1]);
  }
  auto node_of = [&](std::size_t tag) {
    auto it = node_index.find(tag);
    if (it == node_index.end()) throw std::runtime_error(fmt::format("{}: element refers to unknown node {}", path, tag));
    return it->second;
  };

  // Every triangle of every surface entity, once; physical groups refer to entities.
  std::map<int, std::vector<Index>> entity_triangles;
  std::map<std::size_t, Index> triangle_of_tag;
  gmsh::vectorpair surfaces;
  gmsh::model::getEntities(surfaces, 2);
  for (const auto& [dim, tag] : surfaces) {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> elem_tags, elem_nodes;
    gmsh::model::mesh::getElements(types, elem_tags, elem_nodes, dim, tag);
    int n_ccw = 0, n_cw = 0;
    std::vector<std::size_t> cw_tags;
    for (std::size_t k = 0; k < types.size(); ++k) {
      if (types[k] != kGmshTriangle3) {
        std::string name;
        int d, order, nn, npn;
        std::vector<double> lc;
        gmsh::model::mesh::getElementProperties(types[k], name, d, order, nn, lc, npn);
        throw std::runtime_error(fmt::format(
            "{}: surface {} holds '{}' elements; dsdem needs linear 3-node triangles (Mesh.ElementOrder = 1, no recombination)",
            path, tag, name));
      }
      for (std::size_t e = 0; e < elem_tags[k].size(); ++e) {
        std::array<Index, 3> t{node_of(elem_nodes[k][3 * e]), node_of(elem_nodes[k][3 * e + 1]),
                               node_of(elem_nodes[k][3 * e + 2])};
        const Vec2 a = mesh.nodes[t[1]] - mesh.nodes[t[0]], b = mesh.nodes[t[2]] - mesh.nodes[t[0]];
        const double area2 = a.x() * b.y() - a.y() * b.x();
        const double scale = a.squaredNorm() + b.squaredNorm();
        if (!(std::abs(area2) > 1e-12 * scale))
          throw std::runtime_error(fmt::format("{}: triangle {} (surface {}) is degenerate (zero area) near ({:.6g}, {:.6g})",
                                               path, elem_tags[k][e], tag, mesh.nodes[t[0]].x(), mesh.nodes[t[0]].y()));
        if (area2 < 0) {
          ++n_cw;
          cw_tags.push_back(elem_tags[k][e]);
          std::swap(t[1], t[2]);
        } else {
          ++n_ccw;
        }
        triangle_of_tag[elem_tags[k][e]] = static_cast<Index>(mesh.triangles.size());
        entity_triangles[tag].push_back(static_cast<Index>(mesh.triangles.size()));
        mesh.triangles.push_back(t);
      }
    }
    // A surface whose triangles do not share one orientation is folded: some are inverted.
    if (n_ccw > 0 && n_cw > 0) {
      const bool few_cw = n_cw <= n_ccw;
      throw std::runtime_error(fmt::format(
          "{}: surface {} has inverted elements: {} of its {} triangles are {} (first: element {})", path, tag,
          few_cw ? n_cw : n_ccw, n_cw + n_ccw, few_cw ? "clockwise" : "counter-clockwise",
          few_cw ? cw_tags.front() : std::size_t(0)));
    }
  }
  if (mesh.triangles.empty()) throw std::runtime_error(fmt::format("{}: the mesh has no triangles", path));
  mesh.triangle_surface_group.assign(mesh.triangles.size(), kNoIndex);

  gmsh::vectorpair physicals;
  gmsh::model::getPhysicalGroups(physicals);
  for (const auto& [dim, tag] : physicals) {
    RawPhysicalGroup g;
    g.dim = dim;
    g.tag = tag;
    gmsh::model::getPhysicalName(dim, tag, g.name);
    if (g.name.empty()) g.name = fmt::format("physical_{}_{}", dim, tag);
    const Index gi = static_cast<Index>(mesh.groups.size());
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
    for (int ent : entities) {
      if (dim == 2) {
        for (Index t : entity_triangles[ent]) {
          g.triangles.push_back(t);
          if (mesh.triangle_surface_group[t] == kNoIndex) mesh.triangle_surface_group[t] = gi;
        }
      } else if (dim == 1 || dim == 0) {
        std::vector<int> types;
        std::vector<std::vector<std::size_t>> elem_tags, elem_nodes;
        gmsh::model::mesh::getElements(types, elem_tags, elem_nodes, dim, ent);
        for (std::size_t k = 0; k < types.size(); ++k) {
          if (types[k] == kGmshLine2) {
            for (std::size_t e = 0; e < elem_tags[k].size(); ++e)
              g.edges.push_back({node_of(elem_nodes[k][2 * e]), node_of(elem_nodes[k][2 * e + 1])});
          } else if (types[k] == kGmshPoint) {
            for (std::size_t n : elem_nodes[k]) g.nodes.push_back(node_of(n));
          } else {
            throw std::runtime_error(fmt::format("{}: physical group '{}' has unsupported elements of type {}", path,
                                                 g.name, types[k]));
          }
        }
      }
      // dim 3 cannot occur in a 2D model; ignore silently would hide errors.
      if (dim == 3) throw std::runtime_error(fmt::format("{}: 3D physical group '{}': dsdem is 2D", path, g.name));
    }
    if (dim == 1) {
      for (const auto& e : g.edges) {
        g.nodes.push_back(e[0]);
        g.nodes.push_back(e[1]);
      }
    }
    std::sort(g.nodes.begin(), g.nodes.end());
    g.nodes.erase(std::unique(g.nodes.begin(), g.nodes.end()), g.nodes.end());
    mesh.groups.push_back(std::move(g));
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (mesh.triangle_surface_group[t] == kNoIndex) {
      const Vec2 c = (mesh.nodes[mesh.triangles[t][0]] + mesh.nodes[mesh.triangles[t][1]] + mesh.nodes[mesh.triangles[t][2]]) / 3.0;
      throw std::runtime_error(fmt::format(
          "{}: triangle near ({:.6g}, {:.6g}) belongs to no physical surface group; give every surface a Physical Surface",
          path, c.x(), c.y()));
    }
  }
  return mesh;
}

void mesh_geo(const std::string& geo_path, double element_size, const std::string& out_msh) {
  if (const std::string problem = io::input_file_problem(geo_path); !problem.empty())
    throw std::runtime_error(fmt::format("geometry: {}", problem));
  std::string gmsh_exe = DSDEM_GMSH_EXECUTABLE;
  if (gmsh_exe.empty() || gmsh_exe.find("NOTFOUND") != std::string::npos) gmsh_exe = "gmsh";
  const std::string log = out_msh + ".gmsh.log";
  // -clmax caps the size; Mesh.MeshSizeFromPoints stays on so .geo-local sizes still refine.
  const std::string cmd = fmt::format("\"{}\" -2 -format msh41 -clmax {:.17g} -o \"{}\" \"{}\" > \"{}\" 2>&1",
                                      gmsh_exe, element_size, out_msh, geo_path, log);
  const int rc = std::system(cmd.c_str());
  if (rc != 0 || !io::input_file_problem(out_msh).empty()) {
    std::string tail;
    if (FILE* f = std::fopen(log.c_str(), "r")) {
      char buf[4096];
      std::size_t n;
      while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) tail.append(buf, n);
      std::fclose(f);
    }
    std::string errors;
    std::size_t pos = 0;
    while ((pos = tail.find("Error", pos)) != std::string::npos) {
      const auto end = tail.find('\n', pos);
      errors += "\n  " + tail.substr(pos, end - pos);
      pos = end;
    }
    throw std::runtime_error(fmt::format("{}: gmsh failed to mesh the geometry (exit {}){}", geo_path, rc,
                                         errors.empty() ? std::string(" ; see ") + log : errors));
  }
}

}  // namespace dsdem::mesh
