// A solid brake rotor with a hat, written by hand in gmsh's language (SI units: m).
// The cross-section in the (r, z) plane is five structured quadrilateral patches — the friction
// ring, the hat wall beside the ring, the hat wall above it, its corner and the mounting
// flange — revolved about the z axis in four quarters: all hexahedra, hex20 at `-order 2`.
//
//   z
//   ^  L+--------------+I--+J            flange (r_hub .. r_wall_in), top at z_hat
//   |  K+--------------+G--+H
//   |                  |   |             hat wall (r_wall_in .. r_ring_in)
//   |                 F+---+D-----------+C
//   |                  |   |   ring     |   friction ring (r_ring_in .. r_out, z 0 .. t_ring)
//   |                 E+---+A-----------+B
//   +------------------------------------------> r
//
// Physical groups: volume "rotor"; surfaces "friction_in" (z = 0 face of the ring, the
// inboard pad's side), "friction_out" (z = t_ring face of the ring), "rim" (r = r_out),
// "hub" (r = r_hub, the bolt circle's bore: the fixed set), "flange_top" (z = z_hat).
SetFactory("Built-in");
DefineConstant[
  r_hub = {0.035, Name "Parameters/r_hub"},
  r_wall_in = {0.086, Name "Parameters/r_wall_in"},
  r_ring_in = {0.094, Name "Parameters/r_ring_in"},
  r_out = {0.160, Name "Parameters/r_out"},
  t_ring = {0.026, Name "Parameters/t_ring"},
  hat_height = {0.042, Name "Parameters/hat_height"},
  t_flange = {0.008, Name "Parameters/t_flange"},
  n_ring = {11, Name "Parameters/n_ring (elements across the ring)"},
  n_ring_z = {4, Name "Parameters/n_ring_z (elements through the ring)"},
  n_wall = {2, Name "Parameters/n_wall (elements through the hat wall)"},
  n_hat = {5, Name "Parameters/n_hat (elements up the hat wall)"},
  n_flange = {7, Name "Parameters/n_flange (elements across the flange)"},
  n_flange_z = {2, Name "Parameters/n_flange_z (elements through the flange)"},
  n_quarter = {58, Name "Parameters/n_quarter (elements per quarter turn)"}
];
z_top = t_ring;
z_hat = t_ring + hat_height;
z_fl = z_hat - t_flange;

pA = newp; Point(pA) = {r_ring_in, 0, 0};
pB = newp; Point(pB) = {r_out, 0, 0};
pC = newp; Point(pC) = {r_out, 0, z_top};
pD = newp; Point(pD) = {r_ring_in, 0, z_top};
pE = newp; Point(pE) = {r_wall_in, 0, 0};
pF = newp; Point(pF) = {r_wall_in, 0, z_top};
pG = newp; Point(pG) = {r_wall_in, 0, z_fl};
pH = newp; Point(pH) = {r_ring_in, 0, z_fl};
pI = newp; Point(pI) = {r_wall_in, 0, z_hat};
pJ = newp; Point(pJ) = {r_ring_in, 0, z_hat};
pK = newp; Point(pK) = {r_hub, 0, z_fl};
pL = newp; Point(pL) = {r_hub, 0, z_hat};

lAB = newc; Line(lAB) = {pA, pB};
lBC = newc; Line(lBC) = {pB, pC};
lCD = newc; Line(lCD) = {pC, pD};
lDA = newc; Line(lDA) = {pD, pA};
lEA = newc; Line(lEA) = {pE, pA};
lFD = newc; Line(lFD) = {pF, pD};
lEF = newc; Line(lEF) = {pE, pF};
lDH = newc; Line(lDH) = {pD, pH};
lFG = newc; Line(lFG) = {pF, pG};
lGH = newc; Line(lGH) = {pG, pH};
lHJ = newc; Line(lHJ) = {pH, pJ};
lGI = newc; Line(lGI) = {pG, pI};
lIJ = newc; Line(lIJ) = {pI, pJ};
lKG = newc; Line(lKG) = {pK, pG};
lKL = newc; Line(lKL) = {pK, pL};
lLI = newc; Line(lLI) = {pL, pI};
Transfinite Curve{lAB, lCD} = n_ring + 1;
Transfinite Curve{lBC, lDA, lEF} = n_ring_z + 1;
Transfinite Curve{lEA, lFD, lGH, lIJ} = n_wall + 1;
Transfinite Curve{lDH, lFG} = n_hat + 1;
Transfinite Curve{lHJ, lGI, lKL} = n_flange_z + 1;
Transfinite Curve{lKG, lLI} = n_flange + 1;

// Each loop starts with the curve whose revolution matters: the laterals of Extrude come in
// loop order.
cl = newcl; Curve Loop(cl) = {lAB, lBC, lCD, lDA};    s_ring = news; Plane Surface(s_ring) = {cl};
cl = newcl; Curve Loop(cl) = {lEA, -lDA, -lFD, -lEF}; s_wall_low = news; Plane Surface(s_wall_low) = {cl};
cl = newcl; Curve Loop(cl) = {lFD, lDH, -lGH, -lFG};  s_wall = news; Plane Surface(s_wall) = {cl};
cl = newcl; Curve Loop(cl) = {lGH, lHJ, -lIJ, -lGI};  s_corner = news; Plane Surface(s_corner) = {cl};
cl = newcl; Curve Loop(cl) = {lKG, lGI, -lLI, -lKL};  s_flange = news; Plane Surface(s_flange) = {cl};
src[] = {s_ring, s_wall_low, s_wall, s_corner, s_flange};
Transfinite Surface{src[]};
Recombine Surface{src[]};

// Revolve by quarter turns (gmsh revolves less than pi at once); the last quarter closes on
// the first section's entities (the built-in kernel's coherence merges them).
For q In {0:3}
  ex[] = Extrude {{0, 0, 1}, {0, 0, 0}, Pi / 2} { Surface{src[]}; Layers{n_quarter}; Recombine; };
  For i In {0:4}
    body[] += ex[6 * i + 1];
    next[i] = ex[6 * i];
  EndFor
  fr_in[] += ex[2];        // ring: AB
  rim[] += ex[3];          // ring: BC
  fr_out[] += ex[4];       // ring: CD
  fl_top[] += ex[6 * 3 + 4];  // corner: IJ
  fl_top[] += ex[6 * 4 + 4];  // flange: LI
  hub[] += ex[6 * 4 + 5];     // flange: KL
  src[] = next[];
EndFor
Coherence;

Physical Volume("rotor") = {body[]};
Physical Surface("friction_in") = {fr_in[]};
Physical Surface("friction_out") = {fr_out[]};
Physical Surface("rim") = {rim[]};
Physical Surface("hub") = {hub[]};
Physical Surface("flange_top") = {fl_top[]};
