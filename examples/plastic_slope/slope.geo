// A soil slope on a rock base, 120 m wide: a Mohr-Coulomb soil layer (plastic) over
// elastic rock, settling under gravity. Units: metres.
lc = 2.5;
Point(1) = {0, 0, 0, lc};
Point(2) = {120, 0, 0, lc};
Point(3) = {120, 10, 0, lc};
Point(4) = {80, 10, 0, lc};   // toe
Point(5) = {50, 30, 0, lc};   // crest
Point(6) = {0, 30, 0, lc};
Point(7) = {0, 10, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 7};
Line(7) = {7, 1};
Line(8) = {7, 4};             // soil on rock
Curve Loop(1) = {1, 2, 3, -8, 7};
Plane Surface(1) = {1};
Curve Loop(2) = {8, 4, 5, 6};
Plane Surface(2) = {2};
Physical Surface("rock") = {1};
Physical Surface("soil") = {2};
Physical Curve("base") = {1};
Physical Curve("right") = {2};
Physical Curve("left") = {6, 7};
Physical Curve("ground") = {3, 4, 5};
