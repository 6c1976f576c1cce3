// A valid script on which Gmsh 4.8.4 itself segfaults (frontal-delaunay for quads with RecombineAll).
Point(1) = {0, 0, 0, 0.25}; Point(2) = {1, 0, 0, 0.25};
Point(3) = {1, 1, 0, 0.25}; Point(4) = {0, 1, 0, 0.25};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Curve("contact") = {1};
Physical Curve("clamped") = {3};
Mesh.Algorithm = 8; Mesh.RecombineAll = 1;
Physical Surface("body") = {1};
