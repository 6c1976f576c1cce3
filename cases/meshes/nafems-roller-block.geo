// The NAFEMS cylinder-roller benchmark (Konter, NAFEMS R0094, 2006, benchmark 1; Code_Aster
// SSNP154): the aluminium block, half model x >= 0: [0, 100] x [-200, 0] mm, its top touching
// the roller at the origin. Graded towards the contact: h = 0.25 within 10 mm of the origin,
// growing to 10 (mesh.size_factor scales every size).
Point(1) = {0, 0, 0};
Point(2) = {100, 0, 0};
Point(3) = {100, -200, 0};
Point(4) = {0, -200, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("top") = {1};
Physical Curve("right") = {2};
Physical Curve("bottom") = {3};
Physical Curve("left") = {4};
Physical Surface("block") = {1};
Field[1] = Ball;
Field[1].XCenter = 0; Field[1].YCenter = 0; Field[1].ZCenter = 0;
Field[1].Radius = 10; Field[1].Thickness = 40;
Field[1].VIn = 0.25; Field[1].VOut = 10;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
