// Four-point bending beam under impact (docs/validation.md §2, paper §1.3.2; the 1/3-scale
// drop-tower rig of Murray et al. 2007, FHWA-HRT-05-063). Units: metres.
// Beam 1.60 m x 0.152 m (x = -0.8 .. 0.8, y = 0 .. 0.152), two fixed steel supports
// with round tops 1.422 m apart, a steel impactor with two round heads 0.203 m apart
// whose heads start a small gap above the beam's top face.
//
// Mesh size: the scenario's mesh.element_size (gmsh -clmax) is the size in the beam;
// the steel parts get sizes of their own (coarser where they may, so that they do
// not set the time step).
h = Mesh.MeshSizeMax;
If (h > 1)
  h = 0.01;
EndIf
L = 1.60;  H = 0.152;
S = 1.422;            // support spacing
rs = 0.025;           // support radius (half-disc on a block)
hs = 0.03;            // support block height below the half-disc
a = 0.203;            // head spacing
rh = 0.025;           // head radius
gap = 0.001;          // initial gap between the heads and the beam
wb = 0.30;            // length of the cross bar
tb = 0.04;            // height of the cross bar
// Impactor area: Pi rh^2 + 4 rh hp + wb tb = 0.0179635 m^2; with the thickness 0.152 m
// its 75 kg need a density of 75 / (0.0179635 * 0.152) = 27468 kg/m^3 (scenario.yaml).
hp = 0.04;            // height of the posts carrying the heads
hst = h;              // size in the steel parts
// Delaunay meshing: an irregular mesh, so that cracks (which follow element edges)
// have no preferred directions (the default frontal mesher gives a regular pattern
// of equilateral triangles in the rectangle).
Mesh.Algorithm = 5;

// Beam.
Point(1) = {-L/2, 0, 0, h};
Point(2) = { L/2, 0, 0, h};
Point(3) = { L/2, H, 0, h};
Point(4) = {-L/2, H, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

// Supports: a half-disc of radius rs touching the beam's bottom at (+-S/2, 0), on a
// block of height hs.
For k In {0:1}
  xs = (2*k - 1) * S/2;
  p = 100 + 10*k;
  Point(p)   = {xs, -rs, 0, hst};          // centre
  Point(p+1) = {xs + rs, -rs, 0, hst};
  Point(p+2) = {xs, 0, 0, hst};          // top: touches the beam
  Point(p+3) = {xs - rs, -rs, 0, hst};
  Point(p+4) = {xs - rs, -rs - hs, 0, hst};
  Point(p+5) = {xs + rs, -rs - hs, 0, hst};
  Circle(p)   = {p+1, p, p+2};
  Circle(p+1) = {p+2, p, p+3};
  Line(p+2) = {p+3, p+4};
  Line(p+3) = {p+4, p+5};
  Line(p+4) = {p+5, p+1};
  Curve Loop(p) = {p, p+1, p+2, p+3, p+4};
  Plane Surface(p) = {p};
EndFor

// Impactor: two half-disc heads (bottom at y = H + gap) on posts under a cross bar.
y0 = H + gap + rh;    // centres of the heads
For k In {0:1}
  xh = (2*k - 1) * a/2;
  p = 200 + 10*k;
  Point(p)   = {xh, y0, 0, hst};
  Point(p+1) = {xh + rh, y0, 0, hst};
  Point(p+2) = {xh, H + gap, 0, hst};    // bottom: strikes the beam
  Point(p+3) = {xh - rh, y0, 0, hst};
EndFor
yb0 = y0 + hp;        // bottom of the cross bar
yb1 = yb0 + tb;
Point(300) = {-a/2 - rh, yb0, 0, hst};
Point(301) = {-wb/2, yb0, 0, hst};
Point(302) = {-wb/2, yb1, 0, hst};
Point(303) = { wb/2, yb1, 0, hst};
Point(304) = { wb/2, yb0, 0, hst};
Point(305) = { a/2 + rh, yb0, 0, hst};
Point(306) = { a/2 - rh, yb0, 0, hst};
Point(307) = {-a/2 + rh, yb0, 0, hst};
// Outline, counter-clockwise: left head, left post, bar, right post, right head, gap.
Circle(200) = {203, 200, 202};             // left head: from its left to its bottom
Circle(201) = {202, 200, 201};             // ... to its right
Line(202) = {201, 307};                    // left post, inner side
Line(203) = {307, 306};                    // underside of the bar between the posts
Line(204) = {306, 213};                    // right post, inner side
Circle(205) = {213, 210, 212};             // right head
Circle(206) = {212, 210, 211};
Line(207) = {211, 305};                    // right post, outer side
Line(208) = {305, 304};
Line(209) = {304, 303};
Line(210) = {303, 302};
Line(211) = {302, 301};
Line(212) = {301, 300};
Line(213) = {300, 203};                    // left post, outer side
Curve Loop(200) = {200, 201, 202, 203, 204, 205, 206, 207, 208, 209, 210, 211, 212, 213};
Plane Surface(200) = {200};

Physical Surface("beam") = {1};
Physical Surface("left_support") = {100};
Physical Surface("right_support") = {110};
Physical Surface("impactor") = {200};
Physical Curve("beam_bottom") = {1};
Physical Curve("beam_top") = {3};
