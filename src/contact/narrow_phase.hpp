#pragma once
// Narrow phase between two spheropolygons (docs/theory.md §4; paper eq. 1, Fig. 4): the
// vertex-edge, edge-vertex and vertex-vertex contacts of the two cores.
//
// Every core vertex of one body is measured against every core edge of the other
// (paper eq. 1), and each vertex keeps the edge or end point nearest to it: its
// closest feature on the other core. So a vertex near an acute corner is not counted
// against both edges of the corner, and the interaction of the vertex's disc with the
// other rounded body is exact. A vertex-vertex contact is kept only when it is mutual
// (each vertex is the other's closest feature) and then once; a one-sided one is
// dropped, because the other vertex then has a closer contact of its own (this makes
// edge-edge contact exactly two vertex-edge contacts, at the ends of the overlap).
#include <array>
#include <cstdint>

#include "contact/spheropolygon.hpp"

namespace dsdem::contact {

enum class ContactKind : std::uint8_t { VertexEdge = 0, VertexVertex = 1 };

// Closest point of a core triangle to a point p.
struct CoreClosest {
  double distance = 0.0;  // m; negative when p lies inside the core (its depth)
  Vec2 point = Vec2::Zero();   // closest point on the core's boundary
  Vec2 normal = Vec2::Zero();  // unit, from the core toward p (outward)
  int edge = 0;                // core edge k = core[k] -> core[(k+1)%3]
  double t = 0.0;              // parameter of `point` on that edge, in [0, 1]
  bool at_vertex = false;      // the closest point is an edge end: core[vertex]
  int vertex = 0;
};

// Per-core quantities shared by the six vertex queries of a pair: edge vectors, their
// inverse squared lengths and unit outward normals (either orientation), and the box.
struct CoreEdges {
  std::array<Vec2, 3> e;        // core[(k+1)%3] - core[k]
  std::array<double, 3> inv_len2;  // 0 for a zero-length edge
  std::array<Vec2, 3> n_out;    // zero for a zero-length edge
  bool proper = false;          // non-degenerate area (else nothing is "inside")
  Vec2 lo = Vec2::Zero(), hi = Vec2::Zero();
};
CoreEdges core_edges(const std::array<Vec2, 3>& core);

// What core_edges computes with a square root or a division, kept per triangle between
// the shape update and the pair loop (56 B instead of CoreEdges' 160: memory per triangle):
// expand() redoes the rest (edge vectors, normals from the scales, box) with the same
// operations, so expand(core, core_edge_scales(core)) equals core_edges(core) bit for bit.
struct CoreEdgeScales {
  std::array<double, 3> inv_len2;  // as CoreEdges::inv_len2
  std::array<double, 3> n_scale;   // n_out[k] = n_scale[k] * (e.y, -e.x); 0 for a zero-length edge
  bool proper = false;
};
CoreEdgeScales core_edge_scales(const std::array<Vec2, 3>& core);
// Unit outward edge normal k, as CoreEdges::n_out[k].
inline Vec2 edge_normal(const std::array<Vec2, 3>& core, const CoreEdgeScales& s, int k) {
  const Vec2 e = core[(k + 1) % 3] - core[k];
  return s.inv_len2[k] > 0.0 ? Vec2(s.n_scale[k] * Vec2(e.y(), -e.x())) : Vec2(Vec2::Zero());
}
// The normals when already computed (edge_normal of each edge).
inline CoreEdges expand(const std::array<Vec2, 3>& core, const CoreEdgeScales& s, const std::array<Vec2, 3>& normals) {
  CoreEdges ce;
  for (int k = 0; k < 3; ++k) {
    ce.e[k] = core[(k + 1) % 3] - core[k];
    ce.inv_len2[k] = s.inv_len2[k];
    ce.n_out[k] = normals[k];
  }
  ce.proper = s.proper;
  ce.lo = core[0].cwiseMin(core[1]).cwiseMin(core[2]);
  ce.hi = core[0].cwiseMax(core[1]).cwiseMax(core[2]);
  return ce;
}
// Each edge vector computed once (edge_normal() computes the same one again).
inline CoreEdges expand(const std::array<Vec2, 3>& core, const CoreEdgeScales& s) {
  CoreEdges ce;
  for (int k = 0; k < 3; ++k) {
    const Vec2 e = core[(k + 1) % 3] - core[k];
    ce.e[k] = e;
    ce.inv_len2[k] = s.inv_len2[k];
    ce.n_out[k] = s.inv_len2[k] > 0.0 ? Vec2(s.n_scale[k] * Vec2(e.y(), -e.x())) : Vec2(Vec2::Zero());
  }
  ce.proper = s.proper;
  ce.lo = core[0].cwiseMin(core[1]).cwiseMin(core[2]);
  ce.hi = core[0].cwiseMax(core[1]).cwiseMax(core[2]);
  return ce;
}

// Closest point on the core (either orientation) to p. Outside the core it is the
// nearest point of the three edges; inside (deep penetration) it is the foot on the
// nearest edge with the outward normal, so the contact pushes p out, not through.
CoreClosest closest_on_core(const Vec2& p, const std::array<Vec2, 3>& core, const CoreEdges& ce);
inline CoreClosest closest_on_core(const Vec2& p, const std::array<Vec2, 3>& core) {
  return closest_on_core(p, core, core_edges(core));
}

// closest_on_core() for a vertex of another body that may touch this core: p farther
// than `reach` from the core's box, or beyond an edge line by more than `reach` plus a
// margin far above rounding, gives distance = +inf and the other fields as
// CoreClosest{} (the computed distance would exceed reach too).
CoreClosest closest_within(const Vec2& p, const std::array<Vec2, 3>& core, const CoreEdges& ce, double reach);
// out[v] = closest_within(p[v], core, ce, reach) for v = 0, 1, 2, bit for bit. On an
// x86-64 CPU with AVX2 the three queries run in the lanes of 256-bit registers, with
// compares and blends for the scalar code's data-dependent branches, which are
// mispredicted often; elsewhere three scalar calls.
// narrow_phase() runs both sides of a pair in one AVX-512 pass instead where the CPU has
// it (vertex_queries_x6.hpp), and this one otherwise.
void closest_within_x3(const std::array<Vec2, 3>& p, const std::array<Vec2, 3>& core, const CoreEdges& ce,
                       double reach, std::array<CoreClosest, 3>& out);
// True when closest_within_x3() uses the vector lanes on this CPU.
bool closest_within_x3_vectorised();
// Turns the vector lanes off (or on again where the CPU has them), for tests comparing
// the two; returns closest_within_x3_vectorised(). Not thread-safe: call between runs.
bool set_closest_within_x3_vectorised(bool on);

constexpr int kMaxContactsPerPair = 6;

// True when an edge normal of either core separates the two cores by more than
// a.r + b.r (plus a margin far above rounding), so the rounded shapes cannot touch and
// narrow_phase() would find no contact. Most candidate pairs of a discrete mesh are
// triangles meeting at a vertex that never touch: this rejects them with dot products
// instead of six closest-point queries.
// cores_clearance() > 0 is that test, and says by how much more than the limit the cores
// are apart along the first separating normal found: while the two cores' vertices move
// less than that in all, the pair still has no contact (ContactForces skips it).
double cores_clearance(const Spheropolygon& a, const std::array<Vec2, 3>& a_normals, const Spheropolygon& b,
                       const std::array<Vec2, 3>& b_normals);
inline bool cores_apart(const Spheropolygon& a, const CoreEdges& ea, const Spheropolygon& b, const CoreEdges& eb) {
  return cores_clearance(a, ea.n_out, b, eb.n_out) > 0.0;
}

// One contact between spheropolygons i and j.
// No default values: narrow_phase() writes every field of the contacts it returns, and
// the contact phase declares a buffer of kMaxContactsPerPair of these per pair, which a
// zero-fill per pair would cost for nothing.
struct ContactGeometry {
  // Identifies the contact within the pair, stable while the same vertex stays in
  // contact: 3*side + vertex, side 0 = a vertex of i on the core of j, side 1 = a
  // vertex of j on the core of i.
  std::uint8_t feature;
  ContactKind kind;
  std::uint8_t other;  // edge (VertexEdge) or vertex (VertexVertex) of the other core
  double t;            // parameter of the closest point on that core edge
  double distance;     // vertex to other core, m (negative if inside it)
  double overlap;      // delta = r_i + r_j - distance > 0, m
  Vec2 normal;         // unit, from j toward i (force on i = +Fn * normal)
  Vec2 point;          // contact point shared by both bodies: mid-overlap
};

// All contacts of the pair (i = a, j = b), written to out[0..n), n returned (at most
// kMaxContactsPerPair), ordered by feature. Only contacts with overlap > 0.
int narrow_phase(const Spheropolygon& a, const Spheropolygon& b,
                 std::array<ContactGeometry, kMaxContactsPerPair>& out);
// Same, with the cores' edge data computed beforehand (once per triangle and step).
int narrow_phase(const Spheropolygon& a, const CoreEdges& ea, const Spheropolygon& b,
                 const CoreEdges& eb, std::array<ContactGeometry, kMaxContactsPerPair>& out);
// Same, from the cached scales: the edge data are expanded only for pairs that
// cores_apart() does not reject (the contact phase's per-pair call). clearance, if
// given, receives a clearance as cores_clearance() defines it whenever there is no
// contact: cores_clearance() itself, or for pairs it does not reject, the gap along the
// nearest vertex query's direction (or x, y) beyond the same limit; 0 when none is
// positive. check_apart = false skips cores_clearance() (a pair in contact at its last
// check: the test would only cost); the contacts are the same either way.
int narrow_phase(const Spheropolygon& a, const CoreEdgeScales& sa, const Spheropolygon& b,
                 const CoreEdgeScales& sb, std::array<ContactGeometry, kMaxContactsPerPair>& out,
                 double* clearance = nullptr, bool check_apart = true);

}  // namespace dsdem::contact
