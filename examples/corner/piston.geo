// The caliper's piston: a steel cup (open towards the pad) sliding in the housing's bore. Its
// back, in the bore, is loaded by the brake-line pressure; its rim is glued to the inboard
// pad's shim by a [[ties]] entry between components; its skirt (the outer cylinder inside
// the bore, z_back .. z_top) bears on the bore through the seal (a [[contact]] pair that does
// not slide). The skirt's part above the bore (z_top .. z_rim) is a second volume fragmented
// with the first (one conforming mesh), so that the skirt face ends at the bore's mouth.
// SI units (m); inboard of the rotor's face z = 0.
//
// Physical groups: volume "piston"; surfaces "back" (z = z_back: the hydraulic face), "rim"
// (z = z_rim: the annulus on the shim), "seal" (r = r, z_top - w_seal .. z_top).
SetFactory("OpenCASCADE");
DefineConstant[
  h_piston = {0.006, Name "Parameters/h_piston"}
];
xc = 0.1265; r = 0.024; r_cup = 0.018;     // axis at (xc, 0), outer radius r, cup radius r_cup
z_rim = -0.0185; z_back = -0.0395; depth = 0.012;
z_top = -0.0195;                           // the bore's mouth (caliper.geo)
w_seal = 0.004;                            // the seal's width (its groove in the bore)
z_seal = z_top - w_seal;
eps = 1e-6;
Cylinder(1) = {xc, 0, z_back, 0, 0, z_seal - z_back, r};
Cylinder(2) = {xc, 0, z_seal, 0, 0, w_seal, r};
Cylinder(4) = {xc, 0, z_top, 0, 0, z_rim - z_top, r};
Cylinder(3) = {xc, 0, z_rim - depth, 0, 0, depth + 0.001, r_cup};
a[] = BooleanDifference{ Volume{1}; Delete; }{ Volume{3}; };
b[] = BooleanDifference{ Volume{2}; Delete; }{ Volume{3}; };
c[] = BooleanDifference{ Volume{4}; Delete; }{ Volume{3}; Delete; };
BooleanFragments{ Volume{a[], b[], c[]}; Delete; }{}
back[] = Surface In BoundingBox{xc - r - eps, -r - eps, z_back - eps, xc + r + eps, r + eps, z_back + eps};
rim[] = Surface In BoundingBox{xc - r - eps, -r - eps, z_rim - eps, xc + r + eps, r + eps, z_rim + eps};
band[] = Surface In BoundingBox{xc - r - eps, -r - eps, z_seal - eps, xc + r + eps, r + eps, z_top + eps};
inner[] = Surface In BoundingBox{xc - r_cup - eps, -r_cup - eps, z_seal - eps, xc + r_cup + eps, r_cup + eps, z_top + eps};
ends[] = Surface In BoundingBox{xc - r - eps, -r - eps, z_seal - eps, xc + r + eps, r + eps, z_seal + eps};
ends[] += Surface In BoundingBox{xc - r - eps, -r - eps, z_top - eps, xc + r + eps, r + eps, z_top + eps};
seal[] = band[];
seal[] -= inner[];
seal[] -= ends[];
Physical Volume("piston") = {Volume{:}};
Physical Surface("back") = {back[]};
Physical Surface("rim") = {rim[]};
Physical Surface("seal") = {seal[]};
MeshSize{ PointsOf{ Volume{:}; } } = h_piston;
