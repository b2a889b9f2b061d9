// The caliper's piston: a steel cup (open towards the pad), its back in the bore loaded by
// the brake-line pressure, its rim glued to the inboard pad's shim by a [[ties]] entry
// between components. SI units (m); inboard of the rotor's face z = 0.
//
// Physical groups: volume "piston"; surfaces "back" (z = z_back: the hydraulic face), "rim"
// (z = z_rim: the annulus on the shim).
SetFactory("OpenCASCADE");
DefineConstant[
  h_piston = {0.006, Name "Parameters/h_piston"}
];
xc = 0.1265; r = 0.024; r_cup = 0.018;     // axis at (xc, 0), outer radius r, cup radius r_cup
z_rim = -0.0185; z_back = -0.0395; depth = 0.012;
eps = 1e-6;
Cylinder(1) = {xc, 0, z_back, 0, 0, z_rim - z_back, r};
Cylinder(2) = {xc, 0, z_rim - depth, 0, 0, depth, r_cup};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
back[] = Surface In BoundingBox{xc - r - eps, -r - eps, z_back - eps, xc + r + eps, r + eps, z_back + eps};
rim[] = Surface In BoundingBox{xc - r - eps, -r - eps, z_rim - eps, xc + r + eps, r + eps, z_rim + eps};
Physical Volume("piston") = {3};
Physical Surface("back") = {back[]};
Physical Surface("rim") = {rim[]};
MeshSize{ PointsOf{ Volume{3}; } } = h_piston;
