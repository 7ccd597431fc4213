// A closed flume: a 45-degree bank from (0, 6) down to (6, 0), a flat bed to x = 13 and a
// wall 1 m thick up to z = 5 on the right; a 1 x 0.5 m block (discrete) on the bank with its
// lower back corner at (1, 5), meshed as two triangles (the scenario's element size 1 m) so
// that particles 0.2 m apart fit behind each of its faces. The water (level 2 m) fills x = 2-13 m between bank and wall.
hb = 0.5; hs = 1; r = Sqrt(0.5);
Point(1) = {0, -1, 0, 2*hb}; Point(2) = {14, -1, 0, 2*hb}; Point(3) = {14, 5, 0, hb}; Point(4) = {13, 5, 0, hb};
Point(5) = {13, 0, 0, hb}; Point(6) = {6, 0, 0, hb}; Point(7) = {0, 6, 0, hb};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 6}; Line(6) = {6, 7};
Line(7) = {7, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7}; Plane Surface(1) = {1};
Point(8) = {1, 5, 0, hs}; Point(9) = {1 + r, 5 - r, 0, hs};
Point(10) = {1 + r + 0.5*r, 5 - r + 0.5*r, 0, hs}; Point(11) = {1 + 0.5*r, 5 + 0.5*r, 0, hs};
Line(8) = {8, 9}; Line(9) = {9, 10}; Line(10) = {10, 11}; Line(11) = {11, 8};
Curve Loop(2) = {8, 9, 10, 11}; Plane Surface(2) = {2};
Physical Surface("bedrock") = {1};
Physical Surface("block") = {2};
Physical Curve("bedrock_bottom") = {1};
