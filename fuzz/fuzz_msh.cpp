// Fuzz target: the Gmsh .msh reader. The bytes go to a temporary .msh file (the reader
// takes a path); every bad file must end in std::runtime_error naming the file.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "mesh/gmsh_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/dsdem_fuzz_msh_" + std::to_string(::getpid()) + ".msh";
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    (void)dsdem::mesh::read_msh(path);
  } catch (const std::runtime_error&) {
  }
  std::remove(path.c_str());
  return 0;
}
