#pragma once
// Internal to src/io: the readers of the scenario's sections (scenario_sections.cpp).
#include <yaml-cpp/yaml.h>

#include "io/scenario.hpp"
#include "io/schema.hpp"

namespace dsdem::io::detail {

// Where a value stands: the file, line and column of node n, or the --set that gave it.
SourceLocation location(const SchemaReader& r, const YAML::Node& n, const std::string& key);

void read_mesh(SchemaReader& r, YAML::Node& root, Scenario& sc);
void read_materials(SchemaReader& r, YAML::Node& root, Scenario& sc);
void read_regions(SchemaReader& r, YAML::Node& root, Scenario& sc);
void read_time_and_stages(SchemaReader& r, YAML::Node& root, Scenario& sc);
void read_joints(SchemaReader& r, YAML::Node& root, Scenario& sc);
void read_contact(SchemaReader& r, YAML::Node& root, Scenario& sc);
void read_earthquake(SchemaReader& r, YAML::Node& root, Scenario& sc);
void read_output(SchemaReader& r, YAML::Node& root, Scenario& sc);
void read_stability(SchemaReader& r, YAML::Node& root, Scenario& sc);
void read_reservoir(SchemaReader& r, YAML::Node& root, Scenario& sc);  // scenario_reservoir.cpp

}  // namespace dsdem::io::detail
