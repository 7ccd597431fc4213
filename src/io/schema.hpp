#pragma once
// The scenario schema: one table of every key (type, unit, default, range, meaning)
// used both to validate input and to generate docs/scenario-reference.md, so the
// reference never drifts from the code (docs/developer-guide.md §5).
#include <yaml-cpp/yaml.h>

#include "model/types.hpp"

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace dsdem::io {

// Range: two numbers [min, max] (a Vector2 read the same way, documented as a range).
enum class KeyType { Number, Integer, String, Boolean, Vector2, Vector, Map, List, Table, Choice, NumberOrTable, Polyline, Points, Range };

struct KeySpec {
  std::string pattern;  // e.g. "materials.*.E", "regions[].group"
  KeyType type = KeyType::Number;
  std::string unit;     // SI unit text, "" when dimensionless
  std::string default_text;  // "" = no default; "required" = must be given
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  bool max_exclusive = false;
  std::vector<std::string> choices;  // KeyType::Choice
  std::string doc;
  bool required() const { return default_text == "required"; }
};

// Every key the scenario accepts.
const std::vector<KeySpec>& scenario_schema();
const KeySpec* find_spec(const std::string& pattern);

// Markdown reference of the whole schema.
std::string schema_markdown();

// A location in the input: the actual key path (materials.rock.E) and the schema
// pattern it matches (materials.*.E).
struct KeyPath {
  std::string actual;
  std::string pattern;
  KeyPath child(const std::string& key) const;
  KeyPath item(const std::string& name) const;  // named entry of a map of maps
  KeyPath index(std::size_t i) const;           // entry of a list
};

// Reads values through the schema and collects every error with file, line and
// column, so one run reports all problems at once.
class SchemaReader {
 public:
  explicit SchemaReader(std::string file) : file_(std::move(file)) {}
  // Another file format's table of keys (e.g. an ensemble file); `schema` must outlive the reader.
  SchemaReader(std::string file, const std::vector<KeySpec>& schema) : file_(std::move(file)), schema_(&schema) {}

  std::optional<double> number(const YAML::Node& map, const KeyPath& parent, const std::string& key);
  std::optional<long long> integer(const YAML::Node& map, const KeyPath& parent, const std::string& key);
  std::optional<std::string> string(const YAML::Node& map, const KeyPath& parent, const std::string& key);
  std::optional<bool> boolean(const YAML::Node& map, const KeyPath& parent, const std::string& key);
  std::optional<std::array<double, 2>> vector2(const YAML::Node& map, const KeyPath& parent, const std::string& key);
  // Two or three numbers: a point or vector of a plane or a 3D model.
  std::optional<std::vector<double>> vector(const YAML::Node& map, const KeyPath& parent, const std::string& key);
  // A list of [t, value] rows, strictly increasing in t.
  std::optional<std::vector<std::array<double, 2>>> table(const YAML::Node& map, const KeyPath& parent,
                                                          const std::string& key);
  // A list of [x, z] points, strictly increasing in x (a polyline over x).
  std::optional<std::vector<std::array<double, 2>>> polyline(const YAML::Node& map, const KeyPath& parent,
                                                             const std::string& key);
  // A list of at least `at_least` [x, y] points in any order (a path or a polygon).
  std::optional<std::vector<Vec2>> points(const YAML::Node& map, const KeyPath& parent, const std::string& key,
                                          std::size_t at_least);
  // A map or list that must exist when required; returns an undefined node otherwise.
  YAML::Node section(const YAML::Node& map, const KeyPath& parent, const std::string& key, YAML::NodeType::value type);
  // Reports every key of `map` that the schema does not know under `path`, with the
  // nearest valid key suggested.
  void check_keys(const YAML::Node& map, const KeyPath& path);

  void error(const YAML::Node& at, const std::string& path, const std::string& message);
  void error_at(int line, int column, const std::string& path, const std::string& message);
  bool ok() const { return errors_.empty(); }
  const std::vector<std::string>& errors() const { return errors_; }
  const std::string& file() const { return file_; }
  // The --set assignments applied to the tree (key=value): an error on an overridden key
  // names the assignment instead of a line of the file (the value has no line there).
  void set_overrides(const std::vector<std::string>& assignments);
  // The assignment that set `path` or a section above it, or nullptr.
  const std::string* override_for(const std::string& path) const;

 private:
  std::optional<std::vector<std::array<double, 2>>> rows(const YAML::Node& map, const KeyPath& parent,
                                                         const std::string& key, bool polyline);
  const KeySpec& spec(const KeyPath& p) const;
  void check_range(const YAML::Node& at, const KeyPath& p, const KeySpec& s, double v);
  std::string file_;
  const std::vector<KeySpec>* schema_ = nullptr;  // nullptr: the scenario's
  std::vector<std::string> errors_;
  std::vector<std::string> overrides_;
};

// The nearest of `candidates` to `word` by edit distance, or "" when none is close.
std::string nearest(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace dsdem::io
