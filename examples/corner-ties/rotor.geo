// A solid rotor of two meshed bodies, as CAD hands them over: the friction disc and the hat
// (tube and mounting flange) are separate volumes, NOT fragmented, so gmsh meshes the hat's
// foot and the disc's top face independently (non-matching tet meshes at the joint). The
// scene glues them with a [[ties]] entry inside the component. SI units (m).
//
// Physical groups: volumes "disc", "hat"; surfaces "friction_in" (disc, z = 0),
// "disc_top" (disc, z = t: the outboard friction face and the hat's seat), "hat_foot" (hat,
// z = t), "hub" (the flange's bore: the fixed set).
SetFactory("OpenCASCADE");
DefineConstant[
  h_disc = {0.020, Name "Parameters/h_disc (mesh size of the disc)"},
  h_hat = {0.015, Name "Parameters/h_hat (mesh size of the hat)"}
];
r_in = 0.070;  r_out = 0.160;  t = 0.026;            // friction disc
r_hat = 0.090; t_wall = 0.016; hat_h = 0.040;         // hat tube r 0.074 .. 0.090
t_flange = 0.008; r_hub = 0.040;                      // flange at the top, bored at r_hub
eps = 1e-6;

Cylinder(1) = {0, 0, 0, 0, 0, t, r_out};
Cylinder(2) = {0, 0, 0, 0, 0, t, r_in};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Cylinder(4) = {0, 0, t, 0, 0, hat_h, r_hat};
Cylinder(5) = {0, 0, t, 0, 0, hat_h - t_flange, r_hat - t_wall};
BooleanDifference(6) = { Volume{4}; Delete; }{ Volume{5}; Delete; };
Cylinder(7) = {0, 0, t, 0, 0, hat_h, r_hub};
BooleanDifference(8) = { Volume{6}; Delete; }{ Volume{7}; Delete; };

friction_in[] = Surface In BoundingBox{-r_out - eps, -r_out - eps, -eps, r_out + eps, r_out + eps, eps};
foot[] = Surface In BoundingBox{-r_hat - eps, -r_hat - eps, t - eps, r_hat + eps, r_hat + eps, t + eps};
top[] = Surface In BoundingBox{-r_out - eps, -r_out - eps, t - eps, r_out + eps, r_out + eps, t + eps};
top[] -= foot[];
hub[] = Surface In BoundingBox{-r_hub - eps, -r_hub - eps, t + hat_h - t_flange - eps, r_hub + eps, r_hub + eps, t + hat_h + eps};

Physical Volume("disc") = {3};
Physical Volume("hat") = {8};
Physical Surface("friction_in") = {friction_in[]};
Physical Surface("disc_top") = {top[]};
Physical Surface("hat_foot") = {foot[]};
Physical Surface("hub") = {hub[]};

MeshSize{ PointsOf{ Volume{3}; } } = h_disc;
MeshSize{ PointsOf{ Volume{8}; } } = h_hat;
Mesh.MeshSizeMax = h_disc;
