// Interval [0, 1] in 1D, 8 segments.
// Physical groups: "left" (x = 0), "right" (x = 1), "rod" (the line).
Point(1) = {0, 0, 0, 0.125};
Point(2) = {1, 0, 0, 0.125};
Line(1) = {1, 2};
Physical Point("left") = {1};
Physical Point("right") = {2};
Physical Line("rod") = {1};
