// A brake pad of three meshed bodies, as CAD hands them over: the friction lining, the steel
// backplate with its ears, and the damping shim, separate volumes NOT fragmented, so each is
// meshed on its own (non-matching tet meshes at both joints). The scene glues them with
// [[ties]] inside the component. One file for both pads: `side` = -1 (inboard: below the
// rotor's face z = z_face) or +1 (outboard: above it). SI units (m).
//
// The lining and the shim are annular sectors r_i .. r_o of `pad_angle` degrees about the
// x axis (the design parameter: the pad's arc); the backplate is a plate over them whose ends
// y = +-bw are the ears that bear on the anchor bracket's abutments (bracket.geo takes the
// same pad_angle).
//
// Physical groups: volumes "lining", "backplate", "shim"; surfaces "friction" (the lining's
// face on the rotor), "lining_back", "bp_front", "bp_back", "shim_front", "shim_back" (where
// the piston or the caliper's fingers bear), "ear_lead" (y = -bw), "ear_trail" (y = +bw: the
// ear the rotor's drag pushes onto its abutment at the [rotor] rotation +z).
SetFactory("OpenCASCADE");
DefineConstant[
  side = {-1, Name "Parameters/side (-1 inboard, +1 outboard)"},
  z_face = {0.0, Name "Parameters/z_face (the rotor face)"},
  pad_angle = {40, Name "Parameters/pad_angle (degrees: the lining's arc)"},
  h_lining = {0.012, Name "Parameters/h_lining"},
  h_bp = {0.015, Name "Parameters/h_bp"},
  h_shim = {0.009, Name "Parameters/h_shim"}
];
a = pad_angle * Pi / 180;
r_i = 0.100; r_o = 0.153;                          // the lining's and the shim's radii
bx0 = r_i * Cos(a / 2) - 0.004; bx1 = r_o + 0.003; // the backplate x bx0 .. bx1
bw = r_o * Sin(a / 2) + 0.004;                     // .. and y -bw .. bw (its ears' ends)
t_l = 0.011; t_b = 0.006; t_s = 0.0015;
z1 = z_face + side * t_l;  z2 = z1 + side * t_b;  z3 = z2 + side * t_s;
eps = 1e-6;

// The lining and the shim: annular sectors r_i .. r_o of angle a about +x.
Cylinder(11) = {0, 0, Min(z_face, z1), 0, 0, t_l, r_o, a};
Cylinder(12) = {0, 0, Min(z_face, z1) - 0.001, 0, 0, t_l + 0.002, r_i};
vd[] = BooleanDifference{ Volume{11}; Delete; }{ Volume{12}; Delete; };
v_lining = vd[0];
Cylinder(13) = {0, 0, Min(z2, z3), 0, 0, t_s, r_o, a};
Cylinder(14) = {0, 0, Min(z2, z3) - 0.001, 0, 0, t_s + 0.002, r_i};
vd[] = BooleanDifference{ Volume{13}; Delete; }{ Volume{14}; Delete; };
v_shim = vd[0];
Rotate{ {0, 0, 1}, {0, 0, 0}, -a / 2 } { Volume{v_lining, v_shim}; }
Box(15) = {bx0, -bw, Min(z1, z2), bx1 - bx0, 2 * bw, t_b};
v_bp = 15;

// Each body's faces in the plane z = zz (the bodies touch there: both sides' faces lie in it).
// InPlane: sel[] = the faces of volume vol in the plane z = zz
Macro InPlane
  inplane[] = Surface In BoundingBox{bx0 - eps, -bw - eps, zz - eps, bx1 + eps, bw + eps, zz + eps};
  own[] = Abs(Boundary{ Volume{vol}; });
  sel[] = {-1};
  For q In {0 : #inplane[] - 1}
    For r In {0 : #own[] - 1}
      If (inplane[q] == own[r])
        sel[] += {inplane[q]};
      EndIf
    EndFor
  EndFor
  sel[] -= {-1};
Return
vol = v_lining; zz = z_face;
Call InPlane;
friction[] = sel[];
vol = v_lining; zz = z1;
Call InPlane;
lining_back[] = sel[];
vol = v_bp; zz = z1;
Call InPlane;
bp_front[] = sel[];
vol = v_bp; zz = z2;
Call InPlane;
bp_back[] = sel[];
vol = v_shim; zz = z2;
Call InPlane;
shim_front[] = sel[];
vol = v_shim; zz = z3;
Call InPlane;
shim_back[] = sel[];
ear_trail[] = Surface In BoundingBox{bx0 - eps, bw - eps, Min(z1, z2) - eps, bx1 + eps, bw + eps, Max(z1, z2) + eps};
ear_lead[] = Surface In BoundingBox{bx0 - eps, -bw - eps, Min(z1, z2) - eps, bx1 + eps, -bw + eps, Max(z1, z2) + eps};

Physical Volume("lining") = {v_lining};
Physical Volume("backplate") = {v_bp};
Physical Volume("shim") = {v_shim};
Physical Surface("friction") = {friction[]};
Physical Surface("lining_back") = {lining_back[]};
Physical Surface("bp_front") = {bp_front[]};
Physical Surface("bp_back") = {bp_back[]};
Physical Surface("shim_front") = {shim_front[]};
Physical Surface("shim_back") = {shim_back[]};
Physical Surface("ear_trail") = {ear_trail[]};
Physical Surface("ear_lead") = {ear_lead[]};

MeshSize{ PointsOf{ Volume{v_lining}; } } = h_lining;
MeshSize{ PointsOf{ Volume{v_bp}; } } = h_bp;
MeshSize{ PointsOf{ Volume{v_shim}; } } = h_shim;
