// A closed rectangular tank in the vertical plane: its inside 1 m long (x = 0 to 1 m) and
// 1 m high above its bed (y = 0), its walls and bed 0.2 m thick, one surface "tank". The
// walls are thicker than twice the wall particles' rows plus the kernel's reach (docs/theory.md
// §11): the rows laid behind the outer faces stay out of the water's reach.
L = 1.0; Hw = 1.0; t = 0.2; hs = 0.1;
Point(1) = {-t, -t, 0, hs}; Point(2) = {L + t, -t, 0, hs}; Point(3) = {L + t, Hw, 0, hs};
Point(4) = {L, Hw, 0, hs}; Point(5) = {L, 0, 0, hs}; Point(6) = {0, 0, 0, hs};
Point(7) = {0, Hw, 0, hs}; Point(8) = {-t, Hw, 0, hs};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 6};
Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8}; Plane Surface(1) = {1};
Physical Surface("tank") = {1};
Physical Curve("bed") = {5};
