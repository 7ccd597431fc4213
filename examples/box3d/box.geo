// A 40 x 20 x 20 m block of ground: 12 m of rock under 8 m of soil, meshed into
// tetrahedra (the volumes make it a 3D model). Faces named for the boundaries.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 40, 20, 12};
Box(2) = {0, 0, 12, 40, 20, 8};
Coherence;
Physical Volume("rock") = {1};
Physical Volume("soil") = {2};
eps = 1e-3;
Physical Surface("base") = Surface In BoundingBox{-eps, -eps, -eps, 40 + eps, 20 + eps, eps};
Physical Surface("west") = Surface In BoundingBox{-eps, -eps, -eps, eps, 20 + eps, 20 + eps};
Physical Surface("east") = Surface In BoundingBox{40 - eps, -eps, -eps, 40 + eps, 20 + eps, 20 + eps};
Physical Surface("south") = Surface In BoundingBox{-eps, -eps, -eps, 40 + eps, eps, 20 + eps};
Physical Surface("north") = Surface In BoundingBox{-eps, 20 - eps, -eps, 40 + eps, 20 + eps, 20 + eps};
