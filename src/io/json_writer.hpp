#pragma once
// A small JSON value and writer for OUT/summary.json (DESIGN.md §10) and other small
// machine-readable outputs. No third-party JSON library.
//
//   Json s = Json::object();
//   s["scenario"] = "dr2_shear_sliding";
//   s["max_displacement_m"] = 163.2;            // keys carry units (io/atomic_file.hpp)
//   s["gauges"] = Json::array();
//   s["gauges"].push_back(Json::object({{"name", "G1"}, {"peak_velocity_m_per_s", 21.7}}));
//   write_json_file(out / "summary.json", s);   // atomic
//
// Output rules:
//   - objects keep insertion order (a summary reads in the order it was built);
//   - doubles are written in the shortest form that parses back to the same double,
//     always with a '.' or an exponent so readers keep them floating point (1.0, not 1);
//   - NaN and +-infinity, which JSON cannot represent, are written as null;
//   - strings are UTF-8 passed through; '"', '\\' and control characters are escaped.
#include <concepts>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace dsdem::io {

class Json {
 public:
  using Array = std::vector<Json>;
  using Object = std::vector<std::pair<std::string, Json>>;

  Json() = default;  // null
  Json(std::nullptr_t) {}
  Json(bool b) : value_(b) {}
  template <std::integral T>
    requires(!std::same_as<T, bool>)
  Json(T i) : value_(static_cast<std::int64_t>(i)) {}
  template <std::floating_point T>
  Json(T d) : value_(static_cast<double>(d)) {}
  Json(const char* s) : value_(std::string(s)) {}
  Json(std::string_view s) : value_(std::string(s)) {}
  Json(std::string s) : value_(std::move(s)) {}
  Json(Array a) : value_(std::move(a)) {}
  Json(Object o) : value_(std::move(o)) {}

  static Json array(std::initializer_list<Json> items = {}) { return Json(Array(items)); }
  static Json object(std::initializer_list<std::pair<std::string, Json>> members = {}) {
    return Json(Object(members));
  }

  bool is_null() const { return std::holds_alternative<std::nullptr_t>(value_); }
  bool is_array() const { return std::holds_alternative<Array>(value_); }
  bool is_object() const { return std::holds_alternative<Object>(value_); }

  // Object member access: returns the member, appending a null one if absent. A null
  // value becomes an empty object first. Throws std::logic_error on any other type.
  Json& operator[](std::string_view key);
  // Array append. A null value becomes an empty array first; std::logic_error otherwise.
  void push_back(Json item);

  // Serialises. indent < 0: one line, no spaces; otherwise one member or item per line,
  // indented by `indent` spaces per level. No trailing newline.
  std::string dump(int indent = 2) const;

 private:
  void dump_to(std::string& out, int indent, int depth) const;

  std::variant<std::nullptr_t, bool, std::int64_t, double, std::string, Array, Object> value_ =
      nullptr;
};

// The JSON text of a double per the rules above ("null" if not finite).
std::string json_number(double d);
// `s` as a quoted, escaped JSON string.
std::string json_string(std::string_view s);

// `value.dump(indent)` plus a final newline to `path`, atomically (io/atomic_file.hpp).
void write_json_file(const std::filesystem::path& path, const Json& value, int indent = 2);

}  // namespace dsdem::io
