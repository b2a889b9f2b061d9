// A vented hat rotor of two meshed bodies, as CAD hands them over. The friction ring is one
// volume: the inboard and outboard friction plates joined by radial vanes (the vents between
// them open at the inner and outer rims), fused by OpenCASCADE and meshed in tets (it cannot
// be swept). The hat (tube and mounting flange) is a separate volume, NOT fragmented with the
// ring, so gmsh meshes the hat's foot and the ring's face independently (non-matching tet
// meshes at the joint): the scene glues them with a [[ties]] entry inside the component.
// SI units (m); the axis is z, the inboard friction face z = 0, the outboard z = t.
//
// Physical groups: volumes "ring", "hat"; surfaces "friction_in" (z = 0), "disc_top" (z = t:
// the outboard friction face and the hat's seat), "hat_foot" (the hat, z = t), "hub" (the
// flange's bore: the fixed set).
SetFactory("OpenCASCADE");
DefineConstant[
  h_ring = {0.020, Name "Parameters/h_ring (mesh size of the friction plates)"},
  h_vane = {0.012, Name "Parameters/h_vane (mesh size of the vanes)"},
  h_hat = {0.020, Name "Parameters/h_hat (mesh size of the hat)"},
  n_vanes = {30, Name "Parameters/n_vanes"}
];
r_in = 0.070;  r_out = 0.160;  t = 0.026;           // friction ring
t_plate = 0.0085; t_vent = t - 2 * t_plate;          // two plates, the vent between them
r_vane0 = 0.074; w_vane = 0.006;                     // straight radial vanes r_vane0 .. r_out
r_hat = 0.090; t_wall = 0.016; hat_h = 0.040;        // hat tube r 0.074 .. 0.090
t_flange = 0.008; r_hub = 0.040;                     // flange at the top, bored at r_hub
eps = 1e-6;

Cylinder(1) = {0, 0, 0, 0, 0, t_plate, r_out};
Cylinder(2) = {0, 0, 0, 0, 0, t_plate, r_in};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Cylinder(4) = {0, 0, t - t_plate, 0, 0, t_plate, r_out};
Cylinder(5) = {0, 0, t - t_plate, 0, 0, t_plate, r_in};
BooleanDifference(6) = { Volume{4}; Delete; }{ Volume{5}; Delete; };
vanes[] = {};
For k In {0 : n_vanes - 1}
  v = 100 + k;
  // A vane's outer end is cut by the rim below, so it ends flush with the plates.
  Box(v) = {r_vane0, -w_vane / 2, t_plate, r_out + 0.01 - r_vane0, w_vane, t_vent};
  Rotate{ {0, 0, 1}, {0, 0, 0}, 2 * Pi * k / n_vanes } { Volume{v}; }
  vanes[] += {v};
EndFor
BooleanUnion(7) = { Volume{3}; Delete; }{ Volume{6}; Volume{vanes[]}; Delete; };
// The vanes' outer ends cut flush with the rim.
Cylinder(8) = {0, 0, -0.01, 0, 0, t + 0.02, r_out};
BooleanIntersection(9) = { Volume{7}; Delete; }{ Volume{8}; Delete; };
Cylinder(10) = {0, 0, t, 0, 0, hat_h, r_hat};
Cylinder(11) = {0, 0, t, 0, 0, hat_h - t_flange, r_hat - t_wall};
BooleanDifference(12) = { Volume{10}; Delete; }{ Volume{11}; Delete; };
Cylinder(13) = {0, 0, t, 0, 0, hat_h, r_hub};
BooleanDifference(14) = { Volume{12}; Delete; }{ Volume{13}; Delete; };

friction_in[] = Surface In BoundingBox{-r_out - eps, -r_out - eps, -eps, r_out + eps, r_out + eps, eps};
foot[] = Surface In BoundingBox{-r_hat - eps, -r_hat - eps, t - eps, r_hat + eps, r_hat + eps, t + eps};
top[] = Surface In BoundingBox{-r_out - eps, -r_out - eps, t - eps, r_out + eps, r_out + eps, t + eps};
top[] -= foot[];
hub[] = Surface In BoundingBox{-r_hub - eps, -r_hub - eps, t + hat_h - t_flange - eps, r_hub + eps, r_hub + eps, t + hat_h + eps};

Physical Volume("ring") = {9};
Physical Volume("hat") = {14};
Physical Surface("friction_in") = {friction_in[]};
Physical Surface("disc_top") = {top[]};
Physical Surface("hat_foot") = {foot[]};
Physical Surface("hub") = {hub[]};

Mesh.MeshSizeMax = h_ring;
MeshSize{ PointsOf{ Volume{9}; } } = h_ring;
MeshSize{ PointsOf{ Volume{14}; } } = h_hat;
// The vanes' faces (inside the vent) get the finer size.
vent[] = Surface In BoundingBox{-r_out - eps, -r_out - eps, t_plate + eps, r_out + eps, r_out + eps, t - t_plate - eps};
MeshSize{ PointsOf{ Surface{vent[]}; } } = h_vane;
