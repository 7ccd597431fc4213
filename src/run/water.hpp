#pragma once
// The scenario's water at rest (docs/theory.md §8) checked against the model and handed to
// the solver.
#include <vector>

#include "io/scenario.hpp"
#include "model/model.hpp"
#include "solver/water_loads.hpp"

namespace dsdem::run {

// Some stage has water.
bool has_water(const io::Scenario& sc);

// Every stage's water against the model: the line spans the model's x range, each crack
// is a named curve with joints. Throws io::ScenarioError with file, line and key.
void check_water(const io::Scenario& sc, const Model& model);

// The ground surface z_s(x): the top of the model in its reference configuration,
// sampled half the smallest element size apart (the line of a pore-pressure ratio ru);
// with without_discrete, the top of the triangles outside the discrete zone (the bedrock
// a slide runs on).
std::vector<Vec2> ground_surface(const Model& model, bool without_discrete = false);

// The solver's form of a stage's water (spec.present), for gravity g.
solver::WaterSetup water_setup(const io::WaterSpec& spec, const Model& model, Vec2 gravity);

}  // namespace dsdem::run
