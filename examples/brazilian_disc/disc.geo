// Brazilian disc test (docs/validation.md §1, paper §1.3.1): a disc of radius 0.1 m between two
// steel loading plates.
//
// The loaded diameter is a line of the mesh. Cracks in dsdem can only run along element
// edges (joints); by symmetry the Brazilian crack runs along the loaded diameter, and
// this mesh lets it do so. On a mesh without that line (disc_unaligned.geo) the crack
// has to zigzag along inclined edges, in mixed mode against c = 20 MPa and
// GII = 1500 N/m, and the peak load comes out 8 % to over 60 % higher depending on
// the mesh: a discretisation effect measured and discussed in docs/validation.md §1.5.
//
// Units: metres. The disc centre is the origin; the loaded
// diameter is the y axis.
//
// Mesh size: the scenario's mesh.element_size (gmsh -clmax) is the largest size h, used
// at the sides of the disc; it falls linearly to hf = h * 3.7/8.7 on the loaded
// diameter (|x| <= 0), so element_size = 8.7 mm gives the paper's 3.7-8.7 mm mesh and
// other element sizes scale the whole mesh (mesh convergence).
R = 0.1;
h = Mesh.MeshSizeMax;
If (h > 1)            // no -clmax given (gmsh GUI): the paper's mesh
  h = 0.0087;
EndIf
hf = h * 3.7 / 8.7;
W = 0.03;             // half width of a plate
T = 0.015;            // plate thickness

// Disc: four arcs, with nodes forced at the two loading points (0, +-R).
Point(1) = {0, 0, 0, h};
Point(2) = {R, 0, 0, h};
Point(3) = {0, R, 0, hf};
Point(4) = {-R, 0, 0, h};
Point(5) = {0, -R, 0, hf};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Line(5) = {3, 5};                 // the loaded diameter, embedded in the disc
Line{5} In Surface{1};

// Top plate, touching the disc at (0, R).
Point(11) = {-W, R, 0, h};
Point(12) = { W, R, 0, h};
Point(13) = { W, R + T, 0, h};
Point(14) = {-W, R + T, 0, h};
Line(11) = {11, 12};
Line(12) = {12, 13};
Line(13) = {13, 14};
Line(14) = {14, 11};
Curve Loop(11) = {11, 12, 13, 14};
Plane Surface(11) = {11};

// Bottom plate, touching the disc at (0, -R).
Point(21) = {-W, -R - T, 0, h};
Point(22) = { W, -R - T, 0, h};
Point(23) = { W, -R, 0, h};
Point(24) = {-W, -R, 0, h};
Line(21) = {21, 22};
Line(22) = {22, 23};
Line(23) = {23, 24};
Line(24) = {24, 21};
Curve Loop(21) = {21, 22, 23, 24};
Plane Surface(21) = {21};

// Refinement toward the loaded diameter, in the disc only.
Field[1] = MathEval;
Field[1].F = Sprintf("%.17g + %.17g * Fabs(x) / %.17g", hf, h - hf, 0.5 * R);
Field[2] = Restrict;
Field[2].InField = 1;
Field[2].SurfacesList = {1};
Background Field = 2;

Physical Surface("disc") = {1};
Physical Surface("top_plate") = {11};
Physical Surface("bottom_plate") = {21};
Physical Curve("rim") = {1, 2, 3, 4};
