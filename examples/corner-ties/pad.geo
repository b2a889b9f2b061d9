// A brake pad of three meshed bodies, as CAD hands them over: the friction lining, the steel
// backplate (with ears) and the shim, separate volumes NOT fragmented, so each is meshed
// on its own (non-matching tet meshes at both joints). The scene glues them with [[ties]]
// inside the component. One file for both pads: `side` = -1 (inboard: the pad below the
// rotor's face z = z_face) or +1 (outboard: above it). SI units (m).
//
// Physical groups: volumes "lining", "backplate", "shim"; surfaces "friction" (the lining's
// face on the rotor), "lining_back", "bp_front", "bp_back", "shim_front", "shim_back" (where
// the piston or the caliper's fingers bear), "abutment" (the ears' ends: the fixed set).
SetFactory("OpenCASCADE");
DefineConstant[
  side = {-1, Name "Parameters/side (-1 inboard, +1 outboard)"},
  z_face = {0.0, Name "Parameters/z_face (the rotor face)"},
  h_lining = {0.006, Name "Parameters/h_lining"},
  h_bp = {0.008, Name "Parameters/h_bp"},
  h_shim = {0.006, Name "Parameters/h_shim"}
];
x0 = 0.100; x1 = 0.153; w = 0.045;          // lining and shim: x0..x1, y -w..w
bx0 = 0.098; bx1 = 0.155; bw = 0.056;       // backplate with its ears: bx0..bx1, y -bw..bw
t_l = 0.011; t_b = 0.006; t_s = 0.0015;
z1 = z_face + side * t_l;  z2 = z1 + side * t_b;  z3 = z2 + side * t_s;
eps = 1e-6;

Box(1) = {x0, -w, Min(z_face, z1), x1 - x0, 2 * w, t_l};
Box(2) = {bx0, -bw, Min(z1, z2), bx1 - bx0, 2 * bw, t_b};
Box(3) = {x0, -w, Min(z2, z3), x1 - x0, 2 * w, t_s};

// The faces of one plane z = zz: the small one (lining or shim) and the backplate's.
friction[] = Surface In BoundingBox{x0 - eps, -w - eps, z_face - eps, x1 + eps, w + eps, z_face + eps};
lining_back[] = Surface In BoundingBox{x0 - eps, -w - eps, z1 - eps, x1 + eps, w + eps, z1 + eps};
bp_front[] = Surface In BoundingBox{bx0 - eps, -bw - eps, z1 - eps, bx1 + eps, bw + eps, z1 + eps};
bp_front[] -= lining_back[];
shim_front[] = Surface In BoundingBox{x0 - eps, -w - eps, z2 - eps, x1 + eps, w + eps, z2 + eps};
bp_back[] = Surface In BoundingBox{bx0 - eps, -bw - eps, z2 - eps, bx1 + eps, bw + eps, z2 + eps};
bp_back[] -= shim_front[];
shim_back[] = Surface In BoundingBox{x0 - eps, -w - eps, z3 - eps, x1 + eps, w + eps, z3 + eps};
ab1[] = Surface In BoundingBox{bx0 - eps, bw - eps, Min(z1, z2) - eps, bx1 + eps, bw + eps, Max(z1, z2) + eps};
ab2[] = Surface In BoundingBox{bx0 - eps, -bw - eps, Min(z1, z2) - eps, bx1 + eps, -bw + eps, Max(z1, z2) + eps};

Physical Volume("lining") = {1};
Physical Volume("backplate") = {2};
Physical Volume("shim") = {3};
Physical Surface("friction") = {friction[]};
Physical Surface("lining_back") = {lining_back[]};
Physical Surface("bp_front") = {bp_front[]};
Physical Surface("bp_back") = {bp_back[]};
Physical Surface("shim_front") = {shim_front[]};
Physical Surface("shim_back") = {shim_back[]};
Physical Surface("abutment") = {ab1[], ab2[]};

MeshSize{ PointsOf{ Volume{1}; } } = h_lining;
MeshSize{ PointsOf{ Volume{2}; } } = h_bp;
MeshSize{ PointsOf{ Volume{3}; } } = h_shim;
