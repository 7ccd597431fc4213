// A 45-degree bank into a reservoir: bedrock from (0, 10) down to (10, 0), a flat bed to
// x = 20 m; a 2 x 1 m block (discrete) resting on the bank with its lower corner at
// z = 8 - sqrt(2) m. The reservoir (level 4 m) spans x = 6-20 m.
hb = 1.0; hs = 0.5; s2 = Sqrt(2);
Point(1) = {0, -2, 0, 2*hb}; Point(2) = {20, -2, 0, 2*hb}; Point(3) = {20, 0, 0, hb};
Point(4) = {10, 0, 0, hb}; Point(5) = {0, 10, 0, hb};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4, 5}; Plane Surface(1) = {1};
Point(6) = {2, 8, 0, hs}; Point(7) = {2 + s2, 8 - s2, 0, hs};
Point(8) = {2 + s2 + s2/2, 8 - s2 + s2/2, 0, hs}; Point(9) = {2 + s2/2, 8 + s2/2, 0, hs};
Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 9}; Line(9) = {9, 6};
Curve Loop(2) = {6, 7, 8, 9}; Plane Surface(2) = {2};
Physical Surface("bedrock") = {1};
Physical Surface("block") = {2};
Physical Curve("bedrock_bottom") = {1};
