// A cantilever beam written by hand for squeal's `kind = "geo"` tests: eight points, twelve
// lines, six ruled surfaces and one transfinite volume (not an extrusion), all-hex.
// Physical groups: volume "steel"; surfaces "root" (x = 0, the fixed set), "tip" (x = L),
// "top" (z = H, the friction face), "bottom" (z = 0, the load face); curve "root_edges".
SetFactory("Built-in");
DefineConstant[ L = 0.2, W = 0.04, H = 0.02, nl = 10, nw = 2, nh = 2 ];
Point(1) = {0, 0, 0}; Point(2) = {L, 0, 0}; Point(3) = {L, W, 0}; Point(4) = {0, W, 0};
Point(5) = {0, 0, H}; Point(6) = {L, 0, H}; Point(7) = {L, W, H}; Point(8) = {0, W, H};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Line(9) = {1, 5}; Line(10) = {2, 6}; Line(11) = {3, 7}; Line(12) = {4, 8};
Transfinite Curve{1, 3, 5, 7} = nl + 1;
Transfinite Curve{2, 4, 6, 8} = nw + 1;
Transfinite Curve{9, 10, 11, 12} = nh + 1;
Curve Loop(1) = {1, 2, 3, 4};      Surface(1) = {1};   // z = 0
Curve Loop(2) = {5, 6, 7, 8};      Surface(2) = {2};   // z = H
Curve Loop(3) = {1, 10, -5, -9};   Surface(3) = {3};   // y = 0
Curve Loop(4) = {2, 11, -6, -10};  Surface(4) = {4};   // x = L
Curve Loop(5) = {3, 12, -7, -11};  Surface(5) = {5};   // y = W
Curve Loop(6) = {4, 9, -8, -12};   Surface(6) = {6};   // x = 0
Transfinite Surface{1:6};
Recombine Surface{1:6};
Surface Loop(1) = {1:6};
Volume(1) = {1};
Transfinite Volume{1};
Physical Volume("steel") = {1};
Physical Surface("root") = {6};
Physical Surface("tip") = {4};
Physical Surface("top") = {2};
Physical Surface("bottom") = {1};
Physical Curve("root_edges") = {4, 9, 8, 12};
