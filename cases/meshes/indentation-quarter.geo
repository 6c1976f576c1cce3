// A quarter of an elastic half-space for a spherical punch (cases/indentation-3d.toml):
// the box [0, 1] x [0, 1] x [-1, 0], its top z = 0 under the indenter at the origin,
// symmetry planes x = 0 and y = 0. The elements are graded from h = 0.012 within 0.25
// of the origin (the contact radius grows to about 0.15) to 0.2 at 0.85 and beyond.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, -1, 1, 1, 1};
eps = 1e-6;
Physical Surface("symmetry_x") = Surface In BoundingBox{-eps, -eps, -1 - eps, eps, 1 + eps, eps};
Physical Surface("symmetry_y") = Surface In BoundingBox{-eps, -eps, -1 - eps, 1 + eps, eps, eps};
Physical Surface("base") = Surface In BoundingBox{-eps, -eps, -1 - eps, 1 + eps, 1 + eps, -1 + eps};
Physical Surface("top") = Surface In BoundingBox{-eps, -eps, -eps, 1 + eps, 1 + eps, eps};
Physical Volume("body") = {1};
Field[1] = Ball;
Field[1].XCenter = 0; Field[1].YCenter = 0; Field[1].ZCenter = 0;
Field[1].Radius = 0.25; Field[1].Thickness = 0.6;
Field[1].VIn = 0.012; Field[1].VOut = 0.2;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
