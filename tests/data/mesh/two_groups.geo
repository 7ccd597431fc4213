// Entities in two physical groups each (gmsh 4.8.4 -2 -format msh22 -> two_groups_msh22.msh):
// msh 2.2 writes such elements once per group; the reader keeps them as Gmsh did.
Point(1) = {0, 0, 0, 0.5}; Point(2) = {1, 0, 0, 0.5}; Point(3) = {1, 1, 0, 0.5}; Point(4) = {0, 1, 0, 0.5};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Surface("a") = {1};
Physical Surface("b") = {1};
Physical Curve("c1") = {1, 2};
Physical Curve("c2") = {2, 3};
Physical Point("p") = {3};
