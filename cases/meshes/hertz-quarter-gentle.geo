// hertz-quarter.geo graded more gently (docs/verification.md §8j, the 3D Hertz reference): h = 0.005
// within 0.13 of the origin growing to 0.1 at 1.08 (slope 0.1, against 0.39 for hertz-quarter.geo),
// so that the far field's error falls with size_factor at the contact zone's rate. Use it with
// `vpcontact run hertz-3d --set 'mesh.file="meshes/hertz-quarter-gentle.geo"' --set mesh.size_factor=F`.
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
Field[1].Radius = 0.13; Field[1].Thickness = 0.95;
Field[1].VIn = 0.005; Field[1].VOut = 0.1;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
