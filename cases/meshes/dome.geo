// A solid dome: the lower half of a ball of radius 1 centred at (0, 0, 1.01),
// flat face up (z = 1.01, clamped), curved face down, 0.01 above the plane z = 0.
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 1.01, 1.0, -Pi/2, 0, 2*Pi};
eps = 1e-6;
top() = Surface In BoundingBox{-1.1, -1.1, 1.01 - eps, 1.1, 1.1, 1.01 + eps};
all() = Surface{:};
curved() = all();
curved() -= top();
Physical Surface("clamped") = top();
Physical Surface("contact") = curved();
Physical Volume("body") = {1};
// Finer near the lowest point, where the contact zone grows.
Field[1] = Ball;
Field[1].XCenter = 0; Field[1].YCenter = 0; Field[1].ZCenter = 0.01;
Field[1].Radius = 0.35; Field[1].Thickness = 0.3;
Field[1].VIn = 0.05; Field[1].VOut = 0.2;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
