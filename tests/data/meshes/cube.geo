// Unit cube (0,1)^3 with the OpenCASCADE kernel, coarse tetrahedra.
// Physical groups: "clamped" (z = 1), "contact" (z = 0), "body" (the volume).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
MeshSize{ PointsOf{ Volume{1}; } } = 0.5;
// OpenCASCADE numbers the faces of a box x = 0, x = 1, y = 0, y = 1, z = 0, z = 1;
// select them by position rather than relying on that order.
eps = 1e-6;
Physical Surface("contact") = Surface In BoundingBox{-eps, -eps, -eps, 1 + eps, 1 + eps, eps};
Physical Surface("clamped") = Surface In BoundingBox{-eps, -eps, 1 - eps, 1 + eps, 1 + eps, 1 + eps};
Physical Volume("body") = {1};
