#pragma once
// Cracks for ParaView: every joint as a line cell between the mid-points of its two end
// pairs, with its state, damage, opening, slip, break mode and time (docs/user-guide.md).
#include <filesystem>
#include <string>

#include "model/model.hpp"

namespace dsdem::io {

void write_cracks_vtu(const std::filesystem::path& path, const Model& model, double time_s);

// One line per broken joint, in order of breaking: time, position, mode, curve.
void write_crack_log_csv(const std::filesystem::path& path, const Model& model);

}  // namespace dsdem::io
