// A homogeneous Mohr-Coulomb soil slope (code_aster validation test SSNP006, README.md):
// H = 4.5 m, 1:2 (26.57 deg), facing +x, on 2 m of the same soil down to the fixed base
// (the reference model is 6.5 m high), 2H = 9 m of ground behind the crest and 2H in front
// of the toe (the reference model is 18 m wide; the critical Bishop circle runs from 1.35 m
// behind the crest to the toe). Units: metres.
lc = Mesh.CharacteristicLengthMax;     // = mesh.element_size of the scenario (gmsh -clmax)
If (lc > 1e3)
  lc = 0.5;                            // gmsh run by hand
EndIf
H = 4.5;          // slope height
D = 2.0;          // foundation below the toe
n = 2.0;          // 1 vertical : n horizontal
B = 2 * H;        // ground behind the crest
F = 2 * H;        // ground in front of the toe
xc = B;           // crest
xt = B + n * H;   // toe
W = xt + F;       // model width (27 m)
Point(1) = {0, 0, 0, lc};
Point(2) = {W, 0, 0, lc};
Point(3) = {W, D, 0, lc};
Point(4) = {xt, D, 0, lc};        // toe
Point(5) = {xc, D + H, 0, lc};    // crest
Point(6) = {0, D + H, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};   // the slope face
Line(5) = {5, 6};
Line(6) = {6, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
Physical Surface("soil") = {1};
Physical Curve("base") = {1};
Physical Curve("right") = {2};
Physical Curve("left") = {6};
Physical Curve("ground") = {3, 4, 5};
