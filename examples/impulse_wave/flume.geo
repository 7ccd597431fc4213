// A 45-degree plane from (0, 2) down to a flat bed at its toe (2, 0), the bed on to x = 7.5 m
// and a wall 0.2 m thick up to z = 1.2 m closing the flume. A granular slide (the group
// "slide": every triangle a grain once its joints start broken) lies on the plane, 0.6 m
// long and 0.15 m thick, its lower front corner at z = 1.4 m. The still water depth is set in
// the scenario (reservoir.level), below 1.4 m: the slide runs down before it enters.
hb = 0.1; hf = 0.4; hs = 0.05;
zf = 1.4; l = 0.6; s = 0.15; r = Sqrt(0.5);
Point(1) = {-0.3, -0.3, 0, hf}; Point(2) = {7.7, -0.3, 0, hf}; Point(3) = {7.7, 1.2, 0, hb};
Point(4) = {7.5, 1.2, 0, hb}; Point(5) = {7.5, 0, 0, hb}; Point(6) = {2, 0, 0, hb};
Point(7) = {0, 2, 0, hb}; Point(8) = {-0.3, 2, 0, hb};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 6};
Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8}; Plane Surface(1) = {1};
// The slide: front bottom corner A on the plane, up the plane by l, out of it by s.
ax = 2 - zf; az = zf;
Point(11) = {ax, az, 0, hs}; Point(12) = {ax - l*r, az + l*r, 0, hs};
Point(13) = {ax - l*r + s*r, az + l*r + s*r, 0, hs}; Point(14) = {ax + s*r, az + s*r, 0, hs};
Line(11) = {11, 12}; Line(12) = {12, 13}; Line(13) = {13, 14}; Line(14) = {14, 11};
Curve Loop(2) = {11, 12, 13, 14}; Plane Surface(2) = {2};
Physical Surface("bedrock") = {1};
Physical Surface("slide") = {2};
Physical Curve("bedrock_bottom") = {1};
