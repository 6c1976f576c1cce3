// An elastic half-disc of radius 1, centre (0, -1), its arc up (touching y = 0 at x = 0) and
// its flat side on y = -1: the lower cylinder of a two-body Hertz line contact
// (cases/hertz-cylinders-2d.toml). Graded towards the top: h = 0.0042 within 0.4 of
// (0, 0), growing to 0.2 (mesh.size_factor scales every size).
Point(1) = {0, -1, 0};
Point(2) = {-1, -1, 0};
Point(3) = {0, 0, 0};
Point(4) = {1, -1, 0};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Line(3) = {4, 2};
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};
Physical Curve("arc") = {1, 2};
Physical Curve("flat") = {3};
Physical Surface("disc") = {1};
Field[1] = Ball;
Field[1].XCenter = 0; Field[1].YCenter = 0; Field[1].ZCenter = 0;
Field[1].Radius = 0.4; Field[1].Thickness = 0.6;
Field[1].VIn = 0.0042; Field[1].VOut = 0.2;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
