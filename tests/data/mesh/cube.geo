// 2 x 1 x 1 m box of two volumes (rock below z = 0.5, soil above) with its base named and a
// gauge at the top centre, for the volume-mesh reader.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 2, 1, 0.5};
Box(2) = {0, 0, 0.5, 2, 1, 0.5};
Coherence;
top() = Surface In BoundingBox{-1, -1, 0.99, 3, 2, 1.01};
Point(100) = {1, 0.5, 1, 0.2};
Point{100} In Surface{top(0)};
Physical Volume("rock") = {1};
Physical Volume("soil") = {2};
Physical Surface("base") = Surface In BoundingBox{-1, -1, -0.01, 3, 2, 0.01};
Physical Point("gauge") = {100};
