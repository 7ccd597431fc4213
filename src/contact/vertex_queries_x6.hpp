#pragma once
// The six vertex queries of a pair in one pass on CPUs with AVX-512: a's three
// core vertices on b's core and b's three on a's core, in the eight lanes of 512-bit
// registers (lanes 0-2 and 4-6), where closest_within_x3() runs each side in four AVX2
// lanes. The pairs examined touch or nearly, so both sides or at least one are near and
// the two four-lane calls cost well over one pass per pair; the eight-lane pass costs one
// (on CPUs that run 512-bit operations at the rate of 256-bit ones, square root and
// division included).
// The same IEEE operations in the same order per lane as closest_within(), no fused
// multiply-add (the file is compiled with -ffp-contract=off): each lane equals the scalar
// query bit for bit (test VertexQueries.*).
#include <array>

#include "contact/narrow_phase.hpp"

namespace dsdem::contact {

// True when vertex_queries_x6() may be called (the CPU has AVX-512F) and is not turned off.
bool vertex_queries_x6_enabled();
// Turns the one-pass queries off (or on again where the CPU has AVX-512F), for tests and
// comparisons; returns vertex_queries_x6_enabled(). Not thread-safe: call between runs.
bool set_vertex_queries_x6(bool on);
// out_a[v] = closest_within(a[v], b, eb, reach) and out_b[v] = closest_within(b[v], a, ea,
// reach) for v = 0, 1, 2, bit for bit. Only when vertex_queries_x6_enabled().
void vertex_queries_x6(const std::array<Vec2, 3>& a, const CoreEdges& ea, const std::array<Vec2, 3>& b,
                       const CoreEdges& eb, double reach, std::array<CoreClosest, 3>& out_a,
                       std::array<CoreClosest, 3>& out_b);

}  // namespace dsdem::contact
