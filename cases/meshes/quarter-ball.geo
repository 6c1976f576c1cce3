// A quarter of the lower half of an elastic ball of radius 1, centre (0, 0, 1): x >= 0, y >= 0,
// 0 <= z <= 1, touching z = 0 at the origin; the upper body of a two-body Hertz sphere contact
// (cases/hertz-spheres-3d.toml) above
// hertz-quarter.geo's block. Graded as that block: h = 0.005 within 0.13 of the origin, 0.2
// beyond 0.63 (mesh.size_factor scales every size).
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 1, 1};
Box(2) = {0, 0, 0, 1, 1, 1};
BooleanIntersection(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
eps = 1e-6;
sx() = Surface In BoundingBox{-eps, -eps, -eps, eps, 1 + eps, 1 + eps};
sy() = Surface In BoundingBox{-eps, -eps, -eps, 1 + eps, eps, 1 + eps};
st() = Surface In BoundingBox{-eps, -eps, 1 - eps, 1 + eps, 1 + eps, 1 + eps};
curved() = Boundary{ Volume{3}; };
curved() -= {sx(), sy(), st()};
Physical Surface("symmetry_x") = {sx()};
Physical Surface("symmetry_y") = {sy()};
Physical Surface("top") = {st()};
Physical Surface("surface") = {curved()};
Physical Volume("ball") = {3};
Field[1] = Ball;
Field[1].XCenter = 0; Field[1].YCenter = 0; Field[1].ZCenter = 0;
Field[1].Radius = 0.13; Field[1].Thickness = 0.5;
Field[1].VIn = 0.005; Field[1].VOut = 0.2;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
