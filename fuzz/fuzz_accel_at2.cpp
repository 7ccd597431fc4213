// Fuzz target: the PEER NGA .AT2 accelerogram reader.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "seismic/accelerogram.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    (void)dsdem::seismic::read_accelerogram_at2(in, "fuzz.AT2");
  } catch (const std::runtime_error&) {
  }
  return 0;
}
