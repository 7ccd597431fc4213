// Fuzz target: the scenario parser (YAML text -> Scenario, or io::ScenarioError).
// Any other exception, crash, hang or sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The first line, when it starts with "#set ", is used as a --set override: the
  // override syntax is fuzzed together with the document.
  std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> overrides;
  if (text.rfind("#set ", 0) == 0) {
    const auto eol = text.find('\n');
    overrides.push_back(text.substr(5, eol == std::string::npos ? std::string::npos : eol - 5));
  }
  try {
    (void)dsdem::io::parse_scenario(text, "fuzz.yaml", overrides);
  } catch (const dsdem::io::ScenarioError&) {
  }
  return 0;
}
