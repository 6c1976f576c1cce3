// Unit square (0,1)^2, coarse triangles (h ~ 0.25).
// Physical groups: "clamped" (top, y = 1), "contact" (bottom, y = 0),
// "free" (left and right), "body" (the surface).
h = 0.25;
Point(1) = {0, 0, 0, h};
Point(2) = {1, 0, 0, h};
Point(3) = {1, 1, 0, h};
Point(4) = {0, 1, 0, h};
Line(1) = {1, 2};  // bottom
Line(2) = {2, 3};  // right
Line(3) = {3, 4};  // top
Line(4) = {4, 1};  // left
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("contact") = {1};
Physical Curve("clamped") = {3};
Physical Curve("free") = {2, 4};
Physical Surface("body") = {1};
