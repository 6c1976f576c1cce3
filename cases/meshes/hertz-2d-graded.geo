// The hertz-2d block [-4, 4] x [0, 4] (bottom "bottom" on the rigid cylinder, "top"
// clamped, "sides" free) graded towards the contact zone: h = 0.0042 within 0.4 of the
// origin (the contact half-width is about 0.21: a/h ≈ 50), growing to 0.25 beyond 1.4.
// mesh.size_factor scales every size: 2 gives a/h ≈ 25, 5 gives a/h ≈ 10
// (docs/verification.md §8a).
Point(1) = {-4, 0, 0};
Point(2) = {4, 0, 0};
Point(3) = {4, 4, 0};
Point(4) = {-4, 4, 0};
Point(5) = {0, 0, 0};
Line(1) = {1, 5};
Line(2) = {5, 2};
Line(3) = {2, 3};
Line(4) = {3, 4};
Line(5) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Physical Curve("bottom") = {1, 2};
Physical Curve("top") = {4};
Physical Curve("sides") = {3, 5};
Physical Surface("body") = {1};
Field[1] = Ball;
Field[1].XCenter = 0; Field[1].YCenter = 0; Field[1].ZCenter = 0;
Field[1].Radius = 0.4; Field[1].Thickness = 1.0;
Field[1].VIn = 0.0042; Field[1].VOut = 0.25;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
