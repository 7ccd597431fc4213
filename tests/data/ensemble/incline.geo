// A 0.2 m square block resting on a fixed 4 m slab (two separate meshes, no shared nodes);
// the scenario tilts gravity by 30 degrees, which stands in for a 30-degree incline exactly.
h = 0.1;
Point(1) = {-0.2, -0.2, 0, h}; Point(2) = {3.8, -0.2, 0, h}; Point(3) = {3.8, 0, 0, h}; Point(4) = {-0.2, 0, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Point(5) = {0, 0, 0, h}; Point(6) = {0.2, 0, 0, h}; Point(7) = {0.2, 0.2, 0, h}; Point(8) = {0, 0.2, 0, h};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Physical Surface("ground") = {1};
Physical Surface("block") = {2};
Physical Curve("ground_bottom") = {1};
