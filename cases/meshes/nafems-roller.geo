// The NAFEMS cylinder-roller benchmark (Konter, NAFEMS R0094, 2006, benchmark 1; Code_Aster
// SSNP154): the steel roller of radius 50 mm, centre (0, 50), half model x >= 0, touching the
// block at the origin. "arc" its lower quarter (the contact side), "side" the quarter above it to
// 5 degrees from the top, "load" the last 5 degrees (the benchmark's point load at (0, 100),
// here a prescribed displacement on a 4.4 mm arc), "axis" the symmetry line x = 0. Graded
// towards the contact: h = 0.25 within 10 mm of the origin, growing to 5.
Point(1) = {0, 50, 0};
Point(2) = {0, 0, 0};
Point(3) = {50, 50, 0};
Point(4) = {50*Sin(5*Pi/180), 50 + 50*Cos(5*Pi/180), 0};
Point(5) = {0, 100, 0};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Line(4) = {5, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("arc") = {1};
Physical Curve("side") = {2};
Physical Curve("load") = {3};
Physical Curve("axis") = {4};
Physical Surface("roller") = {1};
Field[1] = Ball;
Field[1].XCenter = 0; Field[1].YCenter = 0; Field[1].ZCenter = 0;
Field[1].Radius = 10; Field[1].Thickness = 40;
Field[1].VIn = 0.25; Field[1].VOut = 5;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
