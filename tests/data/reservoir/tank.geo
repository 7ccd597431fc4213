// A closed rectangular tank: its inside 0.4 m long (x = 0 to 0.4 m) and 0.4 m high above its
// bed (y = 0), walls and bed 0.1 m thick (more than the wall particles' rows and the kernel's
// reach at a spacing of 0.01 m), one surface "tank".
L = 0.4; Hw = 0.4; t = 0.1; hs = 0.05;
Point(1) = {-t, -t, 0, hs}; Point(2) = {L + t, -t, 0, hs}; Point(3) = {L + t, Hw, 0, hs};
Point(4) = {L, Hw, 0, hs}; Point(5) = {L, 0, 0, hs}; Point(6) = {0, 0, 0, hs};
Point(7) = {0, Hw, 0, hs}; Point(8) = {-t, Hw, 0, hs};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 6};
Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8}; Plane Surface(1) = {1};
Physical Surface("tank") = {1};
