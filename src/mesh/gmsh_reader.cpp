#include "mesh/gmsh_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "io/input_file.hpp"
#include "mesh/msh_format.hpp"

namespace dsdem::mesh {

namespace {
MshFile parse_msh_file(const std::string& path) {
  if (const std::string problem = io::input_file_problem(path); !problem.empty())  // only regular files
    throw std::runtime_error(fmt::format("mesh: {}", problem));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open the mesh file", path));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw std::runtime_error(fmt::format("{}: cannot read the mesh file", path));
  return parse_msh(text, path);
}
}  // namespace

RawMesh read_msh(const std::string& path, bool crossed) { return to_raw_mesh(parse_msh_file(path), crossed); }

std::variant<RawMesh, RawMesh3> read_msh_any(const std::string& path, bool crossed) {
  const MshFile file = parse_msh_file(path);
  if (is_volume_mesh(file)) return to_raw_mesh_3d(file);
  return to_raw_mesh(file, crossed);
}

void mesh_geo(const std::string& geo_path, double element_size, const std::string& out_msh, bool crossed,
              int dimension) {
  if (const std::string problem = io::input_file_problem(geo_path); !problem.empty())
    throw std::runtime_error(fmt::format("geometry: {}", problem));
  std::string gmsh_exe = DSDEM_GMSH_EXECUTABLE;
  if (gmsh_exe.empty() || gmsh_exe.find("NOTFOUND") != std::string::npos) gmsh_exe = "gmsh";
  const std::string log = out_msh + ".gmsh.log";
  // -clmax caps the size; Mesh.MeshSizeFromPoints stays on so .geo-local sizes still refine.
  // Crossed (docs/theory.md §2): triangles at twice every size (the factor applies after
  // -clmax and to the .geo's own sizes), each split into three quadrilaterals of about the size.
  const std::string crossed_options =
      crossed ? " -setnumber Mesh.MeshSizeFactor 2 -setnumber Mesh.SubdivisionAlgorithm 1" : "";
  const std::string cmd = fmt::format("\"{}\" -{} -format msh41 -clmax {:.17g}{} -o \"{}\" \"{}\" > \"{}\" 2>&1",
                                      gmsh_exe, std::clamp(dimension, 1, 3), element_size, crossed_options, out_msh,
                                      geo_path, log);
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
