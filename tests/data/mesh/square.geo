// 1 m square with named groups, for reader and scenario tests.
lc = 0.25;
Point(1) = {0, 0, 0, lc};
Point(2) = {1, 0, 0, lc};
Point(3) = {1, 1, 0, lc};
Point(4) = {0, 1, 0, lc};
Point(5) = {0.5, 0.5, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Point{5} In Surface{1};
Physical Surface("block") = {1};
Physical Curve("bottom") = {1};
Physical Curve("top") = {3};
Physical Curve("sides") = {2, 4};
Physical Point("centre") = {5};
