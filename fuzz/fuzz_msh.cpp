// Fuzz target: the Gmsh .msh reader of both dimensions (plane and volume meshes). The bytes go to a temporary .msh file (the reader
// takes a path); every bad file must end in std::runtime_error naming the file.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "mesh/gmsh_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // One file per process; the pid padded to a fixed width, so the name's length (which
  // the error messages carry) is the same in every run of the CI smoke.
  static const std::string path = [] {
    char name[64];
    std::snprintf(name, sizeof name, "/tmp/dsdem_fuzz_msh_%010d.msh", static_cast<int>(::getpid()));
    return std::string(name);
  }();
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    (void)dsdem::mesh::read_msh_any(path);
  } catch (const std::runtime_error&) {
  }
  std::remove(path.c_str());
  return 0;
}
