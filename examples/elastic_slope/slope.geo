// An elastic rock slope, 100 m wide: settles under gravity (the quick demo of dsdem).
// Units: metres. Physical groups name what the scenario refers to.
lc = 5;
Point(1) = {0, 0, 0, lc};
Point(2) = {100, 0, 0, lc};
Point(3) = {100, 40, 0, lc};
Point(4) = {60, 40, 0, lc};   // crest
Point(5) = {35, 15, 0, lc};   // toe
Point(6) = {0, 15, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
Physical Surface("rock") = {1};
Physical Curve("base") = {1};
Physical Curve("right") = {2};
Physical Curve("left") = {6};
Physical Curve("ground") = {3, 4, 5};
