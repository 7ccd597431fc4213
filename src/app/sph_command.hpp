#pragma once
// `dsdem sph dam-break`: the standalone SPH water (docs/theory.md §11) on the dam break of
// Martin & Moyce (1952) and Koshizuka & Oka (1996): the surge front and the column height
// as CSV, and the water particles as a VTU/PVD series.
#include <CLI/CLI.hpp>

namespace dsdem::app {

void add_sph_commands(CLI::App& app);

}  // namespace dsdem::app
