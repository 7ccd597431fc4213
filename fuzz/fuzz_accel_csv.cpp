// Fuzz target: the CSV accelerogram reader (time, acceleration columns).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "seismic/accelerogram.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  // The first byte picks the units, so both paths are explored.
  const auto units = (data[0] & 1) ? dsdem::seismic::AccelUnits::G : dsdem::seismic::AccelUnits::MetresPerSecondSquared;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  try {
    (void)dsdem::seismic::read_accelerogram_csv(in, "fuzz.csv", units);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
