// A floating caliper housing of two meshed bodies: the inboard leg (with the piston's bore)
// and the bridge over the rotor's rim in one volume, the outboard leg (the fingers) in
// another, NOT fragmented (non-matching tet meshes where the fingers meet the bridge), glued
// by a [[ties]] entry inside the component. SI units (m); the rotor's faces are z = 0 and
// z = 0.026, its rim r = 0.160.
//
// Physical groups: volumes "housing", "fingers"; surfaces "bore_bottom" (the hydraulic face
// of the housing), "bore" (the bore's wall, where the piston's seal bears), "bridge_inner"
// (the bridge's face x = xb0 above the rotor), "fingers_end" (the fingers' face on it),
// "fingers_face" (z = z_f: where the outboard pad's shim bears), "pins" (the housing's ends
// y = +-w: where the guide pins hold it in plane).
SetFactory("OpenCASCADE");
DefineConstant[
  h_housing = {0.015, Name "Parameters/h_housing"},
  h_fingers = {0.010, Name "Parameters/h_fingers"},
  h_bore = {0.006, Name "Parameters/h_bore"}
];
w = 0.062;                                 // half width (y)
xl = 0.086; xb0 = 0.165; xb1 = 0.187;      // legs from xl; bridge xb0..xb1
zi0 = -0.052; zi1 = -0.0195;               // inboard leg (the piston's side), up to the bore's mouth
z_f = 0.0445; zo1 = 0.0665;                // fingers: z_f (on the outboard shim) .. zo1
xc = 0.1265; r_bore = 0.024; z_bore = -0.040;
eps = 1e-6;

Box(1) = {xl, -w, zi0, xb1 - xl, 2 * w, zi1 - zi0};
Box(2) = {xb0, -w, zi1, xb1 - xb0, 2 * w, zo1 - zi1};
u[] = BooleanUnion{ Volume{1}; Delete; }{ Volume{2}; Delete; };
Cylinder(4) = {xc, 0, z_bore, 0, 0, zi1 - z_bore + 0.001, r_bore};
hs[] = BooleanDifference{ Volume{u[0]}; Delete; }{ Volume{4}; Delete; };
Box(6) = {xl, -w, z_f, xb0 - xl, 2 * w, zo1 - z_f};

bore_bottom[] = Surface In BoundingBox{xc - r_bore - eps, -r_bore - eps, z_bore - eps, xc + r_bore + eps, r_bore + eps, z_bore + eps};
bore[] = Surface In BoundingBox{xc - r_bore - eps, -r_bore - eps, z_bore - eps, xc + r_bore + eps, r_bore + eps, zi1 + eps};
bore[] -= bore_bottom[];
bridge_inner[] = Surface In BoundingBox{xb0 - eps, -w - eps, zi1 - eps, xb0 + eps, w + eps, zo1 + eps};
fingers_end[] = Surface In BoundingBox{xb0 - eps, -w - eps, z_f - eps, xb0 + eps, w + eps, zo1 + eps};
bridge_inner[] -= fingers_end[];
fingers_face[] = Surface In BoundingBox{xl - eps, -w - eps, z_f - eps, xb0 + eps, w + eps, z_f + eps};
// The housing's ends y = +-w (the union may fuse the leg's and the bridge's into one face),
// the fingers' ends left out.
p1[] = Surface In BoundingBox{xl - eps, w - eps, zi0 - eps, xb1 + eps, w + eps, zo1 + eps};
p2[] = Surface In BoundingBox{xl - eps, -w - eps, zi0 - eps, xb1 + eps, -w + eps, zo1 + eps};
f1[] = Surface In BoundingBox{xl - eps, -w - eps, z_f - eps, xb0 + eps, w + eps, zo1 + eps};
p1[] -= f1[];
p2[] -= f1[];

Physical Volume("housing") = {hs[0]};
Physical Volume("fingers") = {6};
Physical Surface("bore_bottom") = {bore_bottom[]};
Physical Surface("bore") = {bore[]};
Physical Surface("bridge_inner") = {bridge_inner[]};
Physical Surface("fingers_end") = {fingers_end[]};
Physical Surface("fingers_face") = {fingers_face[]};
Physical Surface("pins") = {p1[], p2[]};

MeshSize{ PointsOf{ Volume{hs[0]}; } } = h_housing;
MeshSize{ PointsOf{ Volume{6}; } } = h_fingers;
MeshSize{ PointsOf{ Surface{bore[]}; } } = h_bore;
