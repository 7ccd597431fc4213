#pragma once
// JSON files: OUT/summary.json, OUT/diagnosis.json (docs/user-guide.md), read back by the
// post-processing and by anything that compares runs. nlohmann-json does the encoding.
//
//   nlohmann::ordered_json s;                    // keys keep insertion order
//   s["scenario"] = "dr2_shear_sliding";
//   s["max_displacement_m"] = 163.2;             // keys carry units (io/atomic_file.hpp)
//   write_json_file(out / "summary.json", s);    // atomic
//   const auto back = read_json_file(out / "summary.json");
//
// Numbers as nlohmann writes them: each double in a form that parses back to the same
// bits, always with a '.' or an exponent (1.0, not 1), in exponent form from 1e15 up and
// below 1e-4; NaN and +-infinity, which JSON cannot represent, as null.
#include <filesystem>

#include <nlohmann/json_fwd.hpp>

namespace dsdem::io {

// `value` with `indent` spaces per level plus a final newline to `path`, atomically
// (io/atomic_file.hpp). Strings that are not valid UTF-8 are written with U+FFFD in place
// of the bad bytes rather than failing the run at its end.
void write_json_file(const std::filesystem::path& path, const nlohmann::ordered_json& value, int indent = 2);

// The JSON document in `path`, keys in file order. Throws std::runtime_error naming the
// file (and, for bad JSON, the line and column).
nlohmann::ordered_json read_json_file(const std::filesystem::path& path);

}  // namespace dsdem::io
