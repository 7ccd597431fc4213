// Hoek & Bray plane failure with a vertical tension crack of depth z = 8 m in the upper
// surface, behind the crest, reaching the sliding plane (README.md). Units: metres.
// H = 20 m, psi_f = 60 deg, psi_p = 35 deg, toe 10 m above the base; the plane daylights
// in the face 5 m above the toe, so the block can slide out freely.
lc = Mesh.CharacteristicLengthMax;     // = mesh.element_size of the scenario (gmsh -clmax)
If (lc > 1e3)
  lc = 1.5;                            // gmsh run by hand
EndIf
Mesh.CharacteristicLengthMax = 1e22;   // the local sizes below govern
lf = 3 * lc;                           // far from the block
H = 20; h0 = 10; xt = 60; hd = 5; z = 8;
cf = 1 / Tan(60 * Pi / 180);
cp = 1 / Tan(35 * Pi / 180);
Point(1) = {0, 0, 0, lf};
Point(2) = {xt + 20, 0, 0, lf};
Point(3) = {xt + 20, h0, 0, lf};
Point(4) = {xt, h0, 0, lc};                        // toe
Point(9) = {xt - hd * cf, h0 + hd, 0, lc};         // the plane daylights here, in the face
Point(5) = {xt - (hd + H) * cf, h0 + hd + H, 0, lc};           // crest
Point(6) = {xt - hd * cf - (H - z) * cp, h0 + hd + H, 0, lc};     // top of the crack
Point(8) = {xt - hd * cf - (H - z) * cp, h0 + hd + H - z, 0, lc}; // foot of the crack, on the plane
Point(7) = {0, h0 + hd + H, 0, lf};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(10) = {4, 9};  // face below the daylight point
Line(4) = {9, 5};   // face of the block
Line(5) = {5, 6};   // top of the block
Line(6) = {6, 8};   // tension crack
Line(9) = {8, 9};   // sliding plane
Line(7) = {6, 7};
Line(8) = {7, 1};
Curve Loop(1) = {4, 5, 6, 9};
Plane Surface(1) = {1};
Curve Loop(2) = {1, 2, 3, 10, -9, -6, 7, 8};
Plane Surface(2) = {2};
Physical Surface("block") = {1};
Physical Surface("ground") = {2};
Physical Curve("plane") = {9};
Physical Curve("crack") = {6};
Physical Curve("base") = {1};
Physical Curve("left") = {8};
Physical Curve("right") = {2};
