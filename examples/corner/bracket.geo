// The anchor bracket (carrier): two abutments per pad, on which the backplates' ears bear,
// joined by bridges that pass over the rotor's rim outside the caliper, and bolted to the
// knuckle at the inboard mounting faces. One volume (boxes fused by OpenCASCADE), meshed in
// tets. SI units (m); the rotor's faces z = 0 and z = 0.026, its rim r = 0.160. `pad_angle`
// must be the pads' (pad.geo): the abutments' faces are at the ears' ends y = +-bw.
//
// Physical groups: volume "bracket"; surfaces "abut_in_trail", "abut_in_lead" (the inboard
// pad's abutment faces y = +bw and y = -bw), "abut_out_trail", "abut_out_lead" (the outboard
// pad's), "mount" (the two mounting faces z = z_mount: the fixed set).
SetFactory("OpenCASCADE");
DefineConstant[
  pad_angle = {40, Name "Parameters/pad_angle (degrees: the pads' arc, pad.geo)"},
  h_bracket = {0.012, Name "Parameters/h_bracket"}
];
a = pad_angle * Pi / 180;
r_i = 0.100; r_o = 0.153;
bx0 = r_i * Cos(a / 2) - 0.004;            // the backplate's x range (pad.geo)
bw = r_o * Sin(a / 2) + 0.004;             // its ears' ends y = +-bw
ax0 = bx0 - 0.004; ax1 = 0.161;            // abutments x ax0 .. ax1
yo = 0.080;                                // the bracket's outer sides y = +-yo
yb = 0.066;                                // the bridges y = +-(yb .. yo), clear of the caliper (|y| <= 0.062)
xb0 = 0.158; xb1 = 0.180;                  // the bridges' x, outside the rim: r >= 0.171 at |y| >= yb
zi0 = -0.019; zi1 = -0.007;                // inboard abutments (the inboard backplate z -0.017 .. -0.011)
zo0 = 0.033; zo1 = 0.044;                  // outboard abutments (the outboard backplate z 0.037 .. 0.043)
z_mount = -0.036;                          // the mounting faces (the bridges' inboard ends)
eps = 1e-6;

v[] = {};
For s In {-1 : 1 : 2}
  // The abutment blocks: y from bw to yo on side s, at the two backplates' heights.
  b1 = newv; Box(b1) = {ax0, (s > 0) ? bw : -yo, zi0, ax1 - ax0, yo - bw, zi1 - zi0};
  b2 = newv; Box(b2) = {ax0, (s > 0) ? bw : -yo, zo0, ax1 - ax0, yo - bw, zo1 - zo0};
  // The bridge over the rim, down to the mounting face.
  b3 = newv; Box(b3) = {xb0, (s > 0) ? yb : -yo, z_mount, xb1 - xb0, yo - yb, zo1 - z_mount};
  v[] += {b1, b2, b3};
EndFor
u[] = BooleanUnion{ Volume{v[0]}; Delete; }{ Volume{v[{1 : 5}]}; Delete; };

abut_in_trail[] = Surface In BoundingBox{ax0 - eps, bw - eps, zi0 - eps, ax1 + eps, bw + eps, zi1 + eps};
abut_in_lead[] = Surface In BoundingBox{ax0 - eps, -bw - eps, zi0 - eps, ax1 + eps, -bw + eps, zi1 + eps};
abut_out_trail[] = Surface In BoundingBox{ax0 - eps, bw - eps, zo0 - eps, ax1 + eps, bw + eps, zo1 + eps};
abut_out_lead[] = Surface In BoundingBox{ax0 - eps, -bw - eps, zo0 - eps, ax1 + eps, -bw + eps, zo1 + eps};
mount[] = Surface In BoundingBox{xb0 - eps, -yo - eps, z_mount - eps, xb1 + eps, yo + eps, z_mount + eps};

Physical Volume("bracket") = {u[]};
Physical Surface("abut_in_trail") = {abut_in_trail[]};
Physical Surface("abut_in_lead") = {abut_in_lead[]};
Physical Surface("abut_out_trail") = {abut_out_trail[]};
Physical Surface("abut_out_lead") = {abut_out_lead[]};
Physical Surface("mount") = {mount[]};
MeshSize{ PointsOf{ Volume{:}; } } = h_bracket;
