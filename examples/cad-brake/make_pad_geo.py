"""Writes pad.geo: a brake pad as structured hexahedral blocks in gmsh's built-in language.

Run `python make_pad_geo.py > pad.geo` (the committed pad.geo is its output). The blocks'
corner coordinates stay gmsh expressions of the `DefineConstant`s at the top of pad.geo, so a
scene changes the pad with `set_numbers` (gmsh's `-setnumber`) without this script.

Plan view (angles about the rotor axis, radii r0 < r1 < r2 < r3 split the pad in 3 strips):

    angle:  -th_e  -th_p  -th_b -th_f   th_f th_b   th_p   th_e
    strip 2         +------+------------------+------+              backplate beyond the lining
    strip 1  +------+------+     lining       +------+------+       ears (abutments) on strip 1
    strip 0         +------+------------------+------+

Through the thickness (z measured from the friction face, away from the rotor):
level 0 (friction face, lining spans +-th_f) -> level 1 (chamfer top, +-th_b) -> level 2
(lining back = backplate front) -> level 3 (backplate back).
"""

LEVELS = 4
# Global angle list: index -> gmsh expression.
ANGLES = ["-th_e", "-th_p", "-th_b", "-th_f", "th_f", "th_b", "th_p", "th_e"]
RADII = ["r0", "r1", "r2", "r3"]
Z = ["z_face", "z_face + side * c_h", "z_face + side * t_l", "z_face + side * (t_l + t_b)"]

# Blocks: (level below, angle index lo/hi at the lower level, at the upper level, strip).
BLOCKS = []
for k in range(3):
    BLOCKS.append(("lining_chamfer", 0, (3, 4), (2, 5), k))
    BLOCKS.append(("lining", 1, (2, 5), (2, 5), k))
    for lo, hi in [(1, 2), (2, 5), (5, 6)]:
        BLOCKS.append(("backplate", 2, (lo, hi), (lo, hi), k))
BLOCKS.append(("backplate", 2, (0, 1), (0, 1), 1))
BLOCKS.append(("backplate", 2, (6, 7), (6, 7), 1))

# Element counts along each kind of edge.
def n_arc(a0, a1):
    pair = tuple(sorted((a0, a1)))
    return {(3, 4): "n_t", (2, 5): "n_t", (1, 2): "n_p", (5, 6): "n_p", (0, 1): "n_e", (6, 7): "n_e"}[pair]


N_RAD = ["n_r0", "n_r1", "n_r2"]
N_LEV = ["n_ch", "n_l", "n_b"]

out = []
w = out.append
points, lines, surfaces = {}, {}, {}
counter = {"p": 0, "l": 0, "s": 0, "v": 0}


def point(lev, a, k):
    key = (lev, a, k)
    if key not in points:
        counter["p"] += 1
        i = counter["p"]
        points[key] = i
        w(f"Point({i}) = {{{RADII[k]} * Cos({ANGLES[a]}), {RADII[k]} * Sin({ANGLES[a]}), {Z[lev]}}};")
    return points[key]


def centre(lev):
    key = ("c", lev)
    if key not in points:
        counter["p"] += 1
        points[key] = counter["p"]
        w(f"Point({counter['p']}) = {{0, 0, {Z[lev]}}};")
    return points[key]


def line(p, q, kind, n):
    """Oriented curve p -> q; returns a signed id."""
    if (q, p) in lines:
        return -lines[(q, p)]
    if (p, q) not in lines:
        counter["l"] += 1
        i = counter["l"]
        lines[(p, q)] = i
        if kind[0] == "arc":
            w(f"Circle({i}) = {{{p}, {centre(kind[1])}, {q}}}; Transfinite Curve{{{i}}} = {n} + 1;")
        else:
            w(f"Line({i}) = {{{p}, {q}}}; Transfinite Curve{{{i}}} = {n} + 1;")
    return lines[(p, q)]


def surface(loop):
    key = tuple(sorted(abs(c) for c in loop))
    if key not in surfaces:
        counter["s"] += 1
        i = counter["s"]
        surfaces[key] = i
        w(f"Curve Loop({i}) = {{{', '.join(str(c) for c in loop)}}}; Surface({i}) = {{{i}}};")
        w(f"Transfinite Surface{{{i}}}; Recombine Surface{{{i}}};")
    return surfaces[key]


def quad(lev_a, lev_b, corners, kinds):
    """Surface through 4 corner points (lev, a, k) in order, with edge kinds."""
    ps = [point(*c) for c in corners]
    loop = []
    for j in range(4):
        c0, c1 = corners[j], corners[(j + 1) % 4]
        loop.append(line(ps[j], ps[(j + 1) % 4], *kinds[j]))
    return surface(loop)


def edge_kind(c0, c1):
    (l0, a0, k0), (l1, a1, k1) = c0, c1
    if l0 != l1:
        return (("line",), N_LEV[min(l0, l1)])
    if k0 != k1:
        return (("line",), N_RAD[min(k0, k1)])
    return (("arc", l0), n_arc(a0, a1))


def face(corners):
    kinds = [edge_kind(corners[j], corners[(j + 1) % 4]) for j in range(4)]
    return quad(None, None, corners, kinds)


volumes = {"lining_chamfer": [], "lining": [], "backplate": []}
faces = {"friction": [], "back": [], "ears": [], "abutment": []}
for name, lev, (a0, a1), (b0, b1), k in BLOCKS:
    up = lev + 1
    bottom = face([(lev, a0, k), (lev, a1, k), (lev, a1, k + 1), (lev, a0, k + 1)])
    top = face([(up, b0, k), (up, b1, k), (up, b1, k + 1), (up, b0, k + 1)])
    inner = face([(lev, a0, k), (lev, a1, k), (up, b1, k), (up, b0, k)])
    outer = face([(lev, a0, k + 1), (lev, a1, k + 1), (up, b1, k + 1), (up, b0, k + 1)])
    end0 = face([(lev, a0, k), (lev, a0, k + 1), (up, b0, k + 1), (up, b0, k)])
    end1 = face([(lev, a1, k), (lev, a1, k + 1), (up, b1, k + 1), (up, b1, k)])
    counter["v"] += 1
    v = counter["v"]
    w(f"Surface Loop({v}) = {{{bottom}, {top}, {inner}, {outer}, {end0}, {end1}}}; Volume({v}) = {{{v}}};")
    w(f"Transfinite Volume{{{v}}};")
    volumes[name].append(v)
    if lev == 0:
        faces["friction"].append(bottom)
    if up == 3:
        faces["back"].append(top)
    if (a0, a1) in [(0, 1), (6, 7)]:
        faces["abutment"].append(end0 if a0 == 0 else end1)

body = "\n".join(out)
header = '''// A disc-brake pad in gmsh's built-in language, written by make_pad_geo.py (SI units: m).
// Realistic outline: the lining's inner and outer edges are arcs about the rotor axis, its
// leading and trailing ends are chamfered (the friction face spans +-th_f, the lining above
// the chamfer +-th_b), and the steel backplate reaches beyond the lining with two ears
// (abutment tabs) on its middle strip. 23 structured hexahedral blocks, each a transfinite
// volume: all-hex, hex20 at `-order 2`. The pad is centred on angle 0 about the z axis; a
// scene turns it with `rotate_deg`.
//
// side = -1: the pad lies below its friction face z = z_face (the inboard pad under the
// rotor's z = 0 face); side = +1: above it (the outboard pad on the z = t_ring face).
//
// Physical groups: volumes "lining" (chamfer layer and the rest) and "backplate"; surfaces
// "friction" (the friction face, level 0), "back" (the backplate's back: the piston or the
// caliper fingers push here, the load face), "abutment" (the ears' end faces, the fixed
// set: the bracket's abutments).
SetFactory("Built-in");
DefineConstant[
  side = {-1, Name "Parameters/side (-1 below the friction face, +1 above)"},
  z_face = {0.0, Name "Parameters/z_face (z of the friction face)"},
  r0 = {0.101, Name "Parameters/r0 (inner edge radius)"},
  r1 = {0.114, Name "Parameters/r1"},
  r2 = {0.1385, Name "Parameters/r2"},
  r3 = {0.153, Name "Parameters/r3 (outer edge radius)"},
  th_f = {27 * Pi / 180, Name "Parameters/th_f (half angle of the friction face)"},
  th_b = {29 * Pi / 180, Name "Parameters/th_b (half angle above the chamfer)"},
  th_p = {32 * Pi / 180, Name "Parameters/th_p (half angle of the backplate)"},
  th_e = {37 * Pi / 180, Name "Parameters/th_e (half angle at the ears' ends)"},
  c_h = {0.003, Name "Parameters/c_h (chamfer height)"},
  t_l = {0.011, Name "Parameters/t_l (lining thickness)"},
  t_b = {0.006, Name "Parameters/t_b (backplate thickness)"},
  n_t = {16, Name "Parameters/n_t (elements along the lining)"},
  n_p = {1, Name "Parameters/n_p (elements from the lining end to the backplate end)"},
  n_e = {2, Name "Parameters/n_e (elements along an ear)"},
  n_r0 = {2, Name "Parameters/n_r0 (elements across strip 0)"},
  n_r1 = {3, Name "Parameters/n_r1 (elements across strip 1)"},
  n_r2 = {2, Name "Parameters/n_r2 (elements across strip 2)"},
  n_ch = {1, Name "Parameters/n_ch (elements through the chamfer layer)"},
  n_l = {3, Name "Parameters/n_l (elements through the rest of the lining)"},
  n_b = {2, Name "Parameters/n_b (elements through the backplate)"}
];
'''
footer = f'''
Physical Volume("lining") = {{{", ".join(str(v) for v in volumes["lining_chamfer"] + volumes["lining"])}}};
Physical Volume("backplate") = {{{", ".join(str(v) for v in volumes["backplate"])}}};
Physical Surface("friction") = {{{", ".join(str(s) for s in faces["friction"])}}};
Physical Surface("back") = {{{", ".join(str(s) for s in faces["back"])}}};
Physical Surface("abutment") = {{{", ".join(str(s) for s in faces["abutment"])}}};
'''
print(header + body + footer)
