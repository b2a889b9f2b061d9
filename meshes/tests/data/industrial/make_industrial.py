"""Test data for the Nastran and Abaqus readers, written by other tools.

Run from the repository root with the project's virtual environment:

    .venv/bin/python meshes/tests/data/industrial/make_industrial.py

It writes, beside this script:

- `bracket.geo` → `bracket_hex20.msh` (gmsh 4.15, a twisted and tapered hex20 body with
  graded spacing), and from that mesh `bracket_hex20.bdf` (pyNastran: GRID in large field,
  CHEXA 20-node in Nastran's order from meshio's VTK→Nastran permutation, PSOLID, MAT1, SPC1)
  and `bracket_hex20.inp` (meshio's Abaqus writer: *NODE, *ELEMENT, *NSET, *ELSET). The three
  files hold the same mesh: `squeal modes` must give the same frequencies on all three.
- `bracket_ortho.bdf`, `bracket_ortho.inp`, `bracket_ortho.json`: the same bracket in an
  orthotropic lining on turned axes (MAT9 from numpy's inverse of the compliance on a CORD2R
  CORDM; ENGINEERING CONSTANTS on an *ORIENTATION); the JSON gives the constants and axes the
  scene gives the `.msh` route.
- `anchor.geo` → `anchor_tet10.msh` (gmsh, OpenCASCADE block + boss − bolt hole, unstructured
  tet10 with mid-edge nodes on the curved surfaces) and from it `anchor_tet10.bdf` (pyNastran:
  CTETRA 10-node, PSOLID, MAT1, SPC1) and `anchor_tet10.inp` (meshio: C3D10, *NSET);
  `anchor_tet10.json`: sizes and distortion (largest mid-edge offset from the chord over the
  edge length, smallest dihedral angle).
- `mixed.bdf` + `mixed_grids.bdf` (large field, included) + `mixed_free.bdf` (free field,
  written here as text): every solid shape linear and quadratic, some mirrored, grids in
  chained CORD2R/CORD2C/CORD2S and CORD1R systems, CD systems, MAT1, MAT9, PSOLID with CORDM,
  SPC1 (THRU), SPC, SPCADD, SET1, CQUAD4 skin faces, unsupported cards (CONM2, PARAM, EIGRL).
  `mixed.json` holds pyNastran's reading of it: every grid's basic position, the element
  connectivity (Nastran order), MAT9's matrix, the CORDM axes.
- `assembly.inp` + `assembly_materials.inp` (included): hand-written Abaqus input with two
  instances of a part (translation and rotation), C3D20R/C3D10/C3D15/C3D8I elements (element
  lines continued), *NSET/*ELSET with GENERATE, *SURFACE S-faces, *MATERIAL with ENGINEERING
  CONSTANTS and ORTHOTROPIC, *ORIENTATION (rectangular, cylindrical), *BOUNDARY, a *STEP.
  `assembly.json` holds the placed node positions computed here with numpy (Rodrigues).
"""

import json
import os
import subprocess
import sys

import meshio
import numpy as np
from meshio.nastran._nastran import _convert_to_nastran_ordering
from pyNastran.bdf.bdf import BDF, read_bdf

HERE = os.path.dirname(os.path.abspath(__file__))


def path(name):
    return os.path.join(HERE, name)


# ----------------------------------------------------------------------------- bracket

BRACKET_GEO = """// A twisted, tapered bracket meshed in hex20 (transfinite, graded): squeal's reader tests.
// Corners of a general hexahedron (no two faces parallel); lengths in metres.
Point(1) = {0.000, 0.000, 0.000};
Point(2) = {0.060, -0.003, 0.002};
Point(3) = {0.058, 0.022, -0.001};
Point(4) = {-0.002, 0.018, 0.001};
Point(5) = {0.001, 0.001, 0.010};
Point(6) = {0.061, -0.001, 0.014};
Point(7) = {0.057, 0.021, 0.012};
Point(8) = {0.000, 0.020, 0.009};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Line(9) = {1, 5}; Line(10) = {2, 6}; Line(11) = {3, 7}; Line(12) = {4, 8};
Curve Loop(1) = {1, 2, 3, 4}; Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Surface(2) = {2};
Curve Loop(3) = {1, 10, -5, -9}; Surface(3) = {3};
Curve Loop(4) = {2, 11, -6, -10}; Surface(4) = {4};
Curve Loop(5) = {3, 12, -7, -11}; Surface(5) = {5};
Curve Loop(6) = {4, 9, -8, -12}; Surface(6) = {6};
Surface Loop(1) = {1, 2, 3, 4, 5, 6};
Volume(1) = {1};
Transfinite Curve{1, 5} = 7 Using Progression 1.15;
Transfinite Curve{-3, -7} = 7 Using Progression 1.15;
Transfinite Curve{2, 4, 6, 8} = 4;
Transfinite Curve{9, 10, 11, 12} = 3;
Transfinite Surface{1, 2, 3, 4, 5, 6};
Recombine Surface{1, 2, 3, 4, 5, 6};
Transfinite Volume{1};
Physical Volume("body") = {1};
Physical Surface("clamp") = {6};
Physical Surface("top") = {2};
"""

E, NU, RHO = 210e9, 0.3, 7850.0


def bracket():
    with open(path("bracket.geo"), "w") as f:
        f.write(BRACKET_GEO)
    gmsh = [sys.executable, os.path.join(os.path.dirname(sys.executable), "gmsh")]
    subprocess.run(
        gmsh
        + ["-3", "-order", "2", "-string", "Mesh.SecondOrderIncomplete=1;", path("bracket.geo"),
           "-format", "msh41", "-o", path("bracket_hex20.msh")],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    m = meshio.read(path("bracket_hex20.msh"))
    hexes = np.vstack([c.data for c in m.cells if c.type == "hexahedron20"])
    # Node sets of the physical surfaces (from their quad8 faces).
    sets = {}
    for name in ("clamp", "top"):
        nodes = set()
        for c, ids in zip(m.cells, m.cell_sets[name]):
            if len(ids):
                nodes.update(np.asarray(c.data)[ids].ravel().tolist())
        sets[name] = sorted(nodes)
    used = np.unique(hexes)
    assert len(used) == len(m.points), "every node is a hex20 node"

    # Abaqus, by meshio (its names: C3D20RH for hexahedron20).
    out = meshio.Mesh(
        m.points,
        [("hexahedron20", hexes)],
        point_sets={k: np.array(v) for k, v in sets.items()},
        cell_sets={"body": [np.arange(len(hexes))]},
    )
    meshio.write(path("bracket_hex20.inp"), out, file_format="abaqus")

    # Nastran, by pyNastran: ids from 1; meshio's permutation to Nastran's CHEXA order.
    bdf = BDF(debug=False)
    for i, x in enumerate(m.points):
        bdf.add_grid(i + 1, x.tolist())
    for e, cell in enumerate(hexes):
        nids = [int(n) + 1 for n in _convert_to_nastran_ordering(cell.tolist(), "CHEXA_")]
        bdf.add_chexa(e + 1, 1, nids)
    bdf.add_psolid(1, 1)
    bdf.add_mat1(1, E, None, NU, rho=RHO)
    bdf.add_spc1(1, "123", [n + 1 for n in sets["clamp"]])
    bdf.write_bdf(path("bracket_hex20.bdf"), size=16, is_double=True)


# Orthotropic lining constants (a transversely isotropic organic pad: stiff in its plane 1-2,
# soft through its thickness 3), on material axes turned away from the global ones.
ORTHO = dict(e1=8.0e9, e2=6.5e9, e3=2.0e9, nu12=0.25, nu13=0.12, nu23=0.15,
             g12=3.0e9, g13=1.1e9, g23=0.9e9)
ORTHO_RHO = 2500.0


def ortho_axes():
    """Unit material axes 1, 2 (rows), turned 30 deg about z then 20 deg about the new 1."""
    c, s = np.cos(np.radians(30.0)), np.sin(np.radians(30.0))
    e1 = np.array([c, s, 0.0])
    e2 = np.array([-s, c, 0.0])
    z = np.array([0.0, 0.0, 1.0])
    ca, sa = np.cos(np.radians(20.0)), np.sin(np.radians(20.0))
    e2, e3 = ca * e2 + sa * z, -sa * e2 + ca * z
    return e1, e2, e3


def ortho_stiffness_nastran():
    """The 6x6 stiffness from the engineering constants, in Nastran's MAT9 strain order
    (xx, yy, zz, xy, yz, zx), by inverting the compliance with numpy."""
    o = ORTHO
    S = np.zeros((6, 6))
    S[0, 0], S[1, 1], S[2, 2] = 1 / o["e1"], 1 / o["e2"], 1 / o["e3"]
    S[0, 1] = S[1, 0] = -o["nu12"] / o["e1"]
    S[0, 2] = S[2, 0] = -o["nu13"] / o["e1"]
    S[1, 2] = S[2, 1] = -o["nu23"] / o["e2"]
    S[3, 3], S[4, 4], S[5, 5] = 1 / o["g12"], 1 / o["g23"], 1 / o["g13"]
    return np.linalg.inv(S)


def bracket_ortho():
    """The bracket in the orthotropic lining on turned axes: a .bdf (MAT9 from numpy's inverse
    of the compliance, PSOLID CORDM = a CORD2R on the axes) and an .inp (ENGINEERING
    CONSTANTS, *ORIENTATION on the axes); the scene gives the msh route the same material."""
    e1, e2, e3 = ortho_axes()
    m = meshio.read(path("bracket_hex20.msh"))
    hexes = np.vstack([c.data for c in m.cells if c.type == "hexahedron20"])
    clamp = set()
    for c, ids in zip(m.cells, m.cell_sets["clamp"]):
        if len(ids):
            clamp.update(np.asarray(c.data)[ids].ravel().tolist())
    bdf = BDF(debug=False)
    for i, x in enumerate(m.points):
        bdf.add_grid(i + 1, x.tolist())
    for e, cell in enumerate(hexes):
        nids = [int(n) + 1 for n in _convert_to_nastran_ordering(cell.tolist(), "CHEXA_")]
        bdf.add_chexa(e + 1, 1, nids)
    bdf.add_cord2r(5, [0.0, 0.0, 0.0], e3.tolist(), e1.tolist())
    bdf.add_psolid(1, 9, cordm=5)
    D = ortho_stiffness_nastran()
    iu = np.triu_indices(6)
    bdf.add_mat9(9, rho=ORTHO_RHO, **{f"G{i+1}{j+1}": float(D[i, j]) for i, j in zip(*iu)})
    bdf.add_spc1(1, "123", sorted(n + 1 for n in clamp))
    bdf.write_bdf(path("bracket_ortho.bdf"), size=16, is_double=True)
    out = meshio.Mesh(m.points, [("hexahedron20", hexes)],
                      point_sets={"clamp": np.array(sorted(clamp))},
                      cell_sets={"body": [np.arange(len(hexes))]})
    meshio.write(path("bracket_ortho.inp"), out, file_format="abaqus")
    o = ORTHO
    with open(path("bracket_ortho.inp"), "a") as f:
        f.write("** the lining material (make_industrial.py)\n")
        f.write("*ORIENTATION, NAME=LINING_AXES\n")
        f.write(", ".join(f"{v:.17g}" for v in list(e1) + list(e2)) + ", 0., 0., 0.\n")
        f.write("*SOLID SECTION, ELSET=body, MATERIAL=LINING, ORIENTATION=LINING_AXES\n,\n")
        f.write("*MATERIAL, NAME=LINING\n*ELASTIC, TYPE=ENGINEERING CONSTANTS\n")
        f.write(f"{o['e1']}, {o['e2']}, {o['e3']}, {o['nu12']}, {o['nu13']}, {o['nu23']}, "
                f"{o['g12']}, {o['g13']},\n{o['g23']}\n")
        f.write(f"*DENSITY\n{ORTHO_RHO}\n*BOUNDARY\nclamp, 1, 3\n")
    json.dump({"source": "make_industrial.py: the lining's constants and axes",
               "orthotropic": ORTHO, "density": ORTHO_RHO,
               "e1": e1.tolist(), "e2": e2.tolist()},
              open(path("bracket_ortho.json"), "w"), indent=1)


# ----------------------------------------------------------------------------- anchor (tet10)

ANCHOR_GEO = """// An anchor-bracket arm as CAD gives it: a block with a bolt hole and a round boss,
// OpenCASCADE booleans, meshed by gmsh in unstructured tet10 with its mid-edge nodes on the
// curved surfaces (squeal's reader tests; lengths in metres).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.06, 0.02, 0.012};
Cylinder(2) = {0.06, 0.01, 0, 0, 0, 0.012, 0.01};
BooleanUnion{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Cylinder(3) = {0.06, 0.01, -0.001, 0, 0, 0.014, 0.0045};
BooleanDifference{ Volume{1}; Delete; }{ Volume{3}; Delete; }
Mesh.MeshSizeMax = 0.006;
Mesh.MeshSizeFromCurvature = 8;
Physical Volume("body") = {1};
Physical Surface("clamp") = Surface In BoundingBox{-1e-6, -1, -1, 1e-6, 1, 1};
"""


def anchor():
    """The anchor arm in tet10 (gmsh, curved mid-edge nodes), and from its mesh a .bdf
    (pyNastran: CTETRA 10-node, PSOLID, MAT1, SPC1) and an .inp (meshio: C3D10, *NSET); the
    JSON gives how far from straight and how far from regular the cells are."""
    with open(path("anchor.geo"), "w") as f:
        f.write(ANCHOR_GEO)
    gmsh = [sys.executable, os.path.join(os.path.dirname(sys.executable), "gmsh")]
    subprocess.run(
        gmsh + ["-3", "-order", "2", path("anchor.geo"), "-format", "msh41",
                "-o", path("anchor_tet10.msh")],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    m = meshio.read(path("anchor_tet10.msh"))
    tets = np.vstack([c.data for c in m.cells if c.type == "tetra10"])
    clamp = set()
    for c, ids in zip(m.cells, m.cell_sets["clamp"]):
        if len(ids):
            clamp.update(np.asarray(c.data)[ids].ravel().tolist())
    used = np.unique(tets)
    assert len(used) == len(m.points), "every node is a tet10 node"
    # Distortion: mid-edge offset from the chord's midpoint over the edge length (curved
    # edges), and the smallest dihedral angle of the corner tetrahedra.
    x = m.points
    edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
    bow = 0.0
    for k, (a, b) in enumerate(edges):
        mid = (x[tets[:, a]] + x[tets[:, b]]) / 2
        length = np.linalg.norm(x[tets[:, a]] - x[tets[:, b]], axis=1)
        bow = max(bow, float(np.max(np.linalg.norm(x[tets[:, 4 + k]] - mid, axis=1) / length)))
    min_dihedral = 180.0
    faces = [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)]
    for t in tets[:, :4]:
        p = x[t]
        normals = []
        for i, f in enumerate(faces):
            n = np.cross(p[f[1]] - p[f[0]], p[f[2]] - p[f[0]])
            if np.dot(n, p[i] - p[f[0]]) > 0:
                n = -n
            normals.append(n / np.linalg.norm(n))
        for i in range(4):
            for j in range(i + 1, 4):
                ang = 180.0 - np.degrees(np.arccos(np.clip(np.dot(normals[i], normals[j]), -1, 1)))
                min_dihedral = min(min_dihedral, ang)

    out = meshio.Mesh(m.points, [("tetra10", tets)],
                      point_sets={"clamp": np.array(sorted(clamp))},
                      cell_sets={"body": [np.arange(len(tets))]})
    meshio.write(path("anchor_tet10.inp"), out, file_format="abaqus")
    bdf = BDF(debug=False)
    for i, p in enumerate(m.points):
        bdf.add_grid(i + 1, p.tolist())
    for e, cell in enumerate(tets):
        nids = [int(n) + 1 for n in _convert_to_nastran_ordering(cell.tolist(), "CTETRA")]
        bdf.add_ctetra(e + 1, 1, nids)
    bdf.add_psolid(1, 1)
    bdf.add_mat1(1, E, None, NU, rho=RHO)
    bdf.add_spc1(1, "123", sorted(n + 1 for n in clamp))
    bdf.write_bdf(path("anchor_tet10.bdf"), size=16, is_double=True)
    json.dump({"source": "make_industrial.py: anchor_tet10.msh read by meshio",
               "n_nodes": int(len(m.points)), "n_tet10": int(len(tets)),
               "n_clamped_nodes": len(clamp),
               "max_mid_edge_offset_over_length": bow,
               "min_dihedral_deg": min_dihedral},
              open(path("anchor_tet10.json"), "w"), indent=1)


# ----------------------------------------------------------------------------- mixed.bdf

# Reference cells (natural node positions, squeal/VTK order, 0-based) whose corners the
# script places and distorts; mid-edge nodes at the midpoints of straight edges.
HEX = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]
HEX_EDGES = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
             (0, 4), (1, 5), (2, 6), (3, 7)]
WEDGE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1]]
WEDGE_EDGES = [(0, 1), (1, 2), (2, 0), (3, 4), (4, 5), (5, 3), (0, 3), (1, 4), (2, 5)]
TET = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
TET_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
PYR = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.8]]
PYR_EDGES = [(0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (1, 4), (2, 4), (3, 4)]

SHAPES = {
    "hexahedron": (HEX, HEX_EDGES, "CHEXA_"),
    "wedge": (WEDGE, WEDGE_EDGES, "CPENTA_"),
    "tetra": (TET, TET_EDGES, "CTETRA_"),
    "pyramid": (PYR, PYR_EDGES, "CPYRA_"),
}
# The mirror of a cell (corners and mid-edge nodes), so that it is written inverted.
MIRROR = {
    ("hexahedron", False): [4, 5, 6, 7, 0, 1, 2, 3],
    ("hexahedron", True): [4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11, 16, 17, 18, 19],
    ("wedge", False): [3, 4, 5, 0, 1, 2],
    ("wedge", True): [3, 4, 5, 0, 1, 2, 9, 10, 11, 6, 7, 8, 12, 13, 14],
    ("tetra", False): [0, 2, 1, 3],
    ("tetra", True): [0, 2, 1, 3, 6, 5, 4, 7, 9, 8],
    ("pyramid", False): [0, 3, 2, 1, 4],
    ("pyramid", True): [0, 3, 2, 1, 4, 8, 7, 6, 5, 9, 12, 11, 10],
}


def vtk_cell(shape, quadratic, offset, rng, mirror):
    """Node positions of one distorted cell in VTK order: corners moved by up to 15 % of the
    cell size, mid-edge nodes at the midpoints of the straight edges; `mirror`: reordered so
    that the cell as written has a negative Jacobian (each mid-edge node stays on its edge)."""
    corners, edges, _ = SHAPES[shape]
    c = np.array(corners, float) * 0.01
    c += rng.uniform(-0.0015, 0.0015, c.shape)
    c += offset
    pts = list(c)
    if quadratic:
        for a, b in edges:
            pts.append((c[a] + c[b]) / 2)
    pts = np.array(pts)
    if mirror:
        pts = pts[MIRROR[(shape, quadratic)]]
    return pts


def mixed():
    rng = np.random.default_rng(23)
    bdf = BDF(debug=False)
    systems = BDF(debug=False)
    # Coordinate systems: 1 rectangular (turned), 2 cylindrical defined in 1, 3 spherical
    # defined in 2, 4 CORD1R on three grids; grids located in each.
    for model in (bdf, systems):
        model.add_cord2r(1, [0.05, 0.01, -0.02], [0.05, 0.02, 0.98], [1.05, 0.5, -0.02])
        model.add_cord2c(2, [0.01, 0.0, 0.0], [0.01, 0.0, 1.0], [1.0, 0.2, 0.0], rid=1)
        model.add_cord2s(3, [0.0, 0.0, 0.02], [0.0, 0.0, 1.0], [1.0, 30.0, 0.0], rid=2)
    systems.cross_reference()
    model_cells = []
    nid = 1
    eid = 1
    grids = {}  # nid -> basic xyz
    for k, (shape, quadratic, mirror) in enumerate(
        [("hexahedron", False, False), ("hexahedron", True, True),
         ("wedge", False, True), ("wedge", True, False),
         ("tetra", False, False), ("tetra", True, True),
         ("pyramid", False, False), ("pyramid", True, True)]
    ):
        pts = vtk_cell(shape, quadratic, np.array([0.03 * k, 0.0, 0.0]), rng, mirror)
        nids = list(range(nid, nid + len(pts)))
        for n, x in zip(nids, pts):
            grids[n] = x
        nid += len(pts)
        card = SHAPES[shape][2]
        name = {"CHEXA_": "chexa", "CPENTA_": "cpenta", "CTETRA_": "ctetra", "CPYRA_": "cpyram"}[card]
        nastran = _convert_to_nastran_ordering(nids, card) if quadratic else nids
        pid = 1 if k < 4 else 2
        getattr(bdf, f"add_{name}")(eid, pid, nastran)
        model_cells.append({"eid": eid, "card": name.upper(), "vtk": nids, "mirrored": mirror})
        eid += 1
    # Locate grids in the systems (CP), and some displacement systems (CD).
    cps = [0, 1, 2, 3]
    grid_cards = BDF(debug=False)
    for n, x in grids.items():
        cp = cps[n % 4]
        local = x if cp == 0 else systems.coords[cp].transform_node_to_local(x)
        cd = 1 if n % 7 == 0 else 0
        grid_cards.add_grid(n, list(map(float, local)), cp=cp, cd=cd)
    # A CORD1R on three grids (used as a CORDM below).
    bdf.add_cord1r(4, 1, 2, 4)
    # Properties, materials.
    bdf.add_psolid(1, 1)
    bdf.add_psolid(2, 9, cordm=4)
    bdf.add_mat1(1, 2.0e11, None, 0.29, rho=7800.0)
    c = np.zeros((6, 6))
    iu = np.triu_indices(6)
    vals = rng.uniform(0.1, 1.0, 21) * 1e9
    c[iu] = vals
    c = c + c.T - np.diag(np.diag(c))
    c += np.eye(6) * 2e10  # positive definite
    g = {f"G{i+1}{j+1}": float(c[i, j]) for i, j in zip(*iu)}
    bdf.add_mat9(9, rho=1800.0, **g)
    # Constraints: SPC1 with THRU, SPC, SPCADD; a SET1; skin faces of the first hex.
    bdf.add_spc1(11, "123", [1, 2, 3])
    bdf.add_spc(12, [5], ["3"], [0.0])
    bdf.add_spcadd(10, [11, 12])
    bdf.add_set1(5, [1, 2, 3, 4])
    bdf.add_pshell(7, mid1=1, t=0.001)
    bdf.add_cquad4(100, 7, [1, 2, 3, 4])
    bdf.add_cquad4(101, 7, [5, 6, 7, 8])
    bdf.add_conm2(200, 1, 0.5)
    bdf.add_param("AUTOSPC", "YES")
    bdf.add_eigrl(1, nd=10)
    # Grids in their own file, large field (double precision).
    grid_cards.write_bdf(path("mixed_grids.bdf"), size=16, is_double=True,
                         write_header=False, enddata=False)
    with open(path("mixed_grids.bdf")) as f:
        text = f.read()
    # Only the GRID cards go there (the systems are in the main deck).
    lines = text.splitlines()
    keep, on = [], False
    for l in lines:
        head = l[:8].strip().upper()
        if head.startswith("GRID"):
            on = True
        elif head and not head.startswith("*") and not head.startswith("$"):
            on = False
        if on:
            keep.append(l)
    with open(path("mixed_grids.bdf"), "w") as f:
        f.write("$ grids of mixed.bdf in large field\n")
        f.write("\n".join(keep) + "\n")
    bdf.write_bdf(path("mixed_main.tmp"), size=8, enddata=False)
    with open(path("mixed_main.tmp")) as f:
        main = f.read()
    os.remove(path("mixed_main.tmp"))
    with open(path("mixed.bdf"), "w") as f:
        f.write("$ squeal reader test deck (make_industrial.py)\n")
        f.write("SOL 103\nCEND\nTITLE = mixed solids\nSPC = 10\nMETHOD = 1\nBEGIN BULK\n")
        f.write("INCLUDE 'mixed_grids.bdf'\n")
        f.write("INCLUDE 'mixed_free.bdf'\n")
        for l in main.splitlines():
            if l.strip().upper().startswith(("BEGIN", "ENDDATA", "SOL ", "CEND", "$PYNASTRAN")):
                continue
            f.write(l + "\n")
        f.write("ENDDATA\n")
    # Free-field cards, written by hand: a CPENTA in free field with a continuation, the
    # exponent forms Nastran allows, a comment after data.
    n0 = max(grids) + 1
    tri = np.array([[0.30, 0.0, 0.0], [0.31, 0.0, 0.0], [0.30, 0.01, 0.0]])
    top = tri + np.array([0.001, 0.0005, 0.01])
    free_pts = np.vstack([tri, top])
    with open(path("mixed_free.bdf"), "w") as f:
        f.write("$ free-field cards (written by make_industrial.py)\n")
        for k, x in enumerate(free_pts):
            f.write(f"GRID,{n0 + k},,{fortran(x[0])},{fortran(x[1])},{fortran(x[2])}  $ free\n")
        ids = [n0 + k for k in range(6)]
        f.write(f"CPENTA,{eid},1,{ids[0]},{ids[1]},{ids[2]},{ids[3]},{ids[4]},{ids[5]}\n")
        f.write("GRID*,9001,,1.5,2.5\n*,3.5\n")
        f.write("SET1,6,1,THRU,4\n")
    model_cells.append({"eid": eid, "card": "CPENTA", "vtk": ids, "mirrored": False})
    # pyNastran's reading is the reference.
    ref = read_bdf(path("mixed.bdf"), debug=False, xref=True)
    positions = {str(n): ref.nodes[n].get_position().tolist() for n in sorted(ref.nodes)}
    elems = {str(e): {"card": el.type, "nodes": [int(x) for x in el.node_ids]}
             for e, el in sorted(ref.elements.items())}
    cord4 = ref.coords[4]
    mat9 = ref.materials[9]
    json.dump(
        {
            "source": "pyNastran 1.4 read_bdf(xref=True) of mixed.bdf",
            "positions": positions,
            "elements": elems,
            "cells": model_cells,
            "cordm4": {"origin": cord4.origin.tolist(),
                       "axes": [cord4.i.tolist(), cord4.j.tolist(), cord4.k.tolist()]},
            "mat9": mat9.D().tolist() if hasattr(mat9, "D") else c.tolist(),
            "cd1_axes": [ref.coords[1].i.tolist(), ref.coords[1].j.tolist(),
                         ref.coords[1].k.tolist()],
        },
        open(path("mixed.json"), "w"),
        indent=1,
    )


def fortran(x):
    """A Nastran real without the exponent letter (e.g. 3.1-2 for 0.031)."""
    if x == 0:
        return "0."
    e = int(np.floor(np.log10(abs(x))))
    m = x / 10.0**e
    return f"{m:.15f}{e:+d}"


# ----------------------------------------------------------------------------- assembly.inp

def rodrigues(a, b, deg):
    k = (np.array(b, float) - np.array(a, float))
    k /= np.linalg.norm(k)
    t = np.radians(deg)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(t) * K + (1 - np.cos(t)) * K @ K


def assembly():
    rng = np.random.default_rng(7)
    # A part "LINK": two C3D20R hexes side by side (12 + 20 + … nodes), a C3D10, a C3D15 and
    # a C3D8I, each its own cell with its own nodes except the two hexes, which share a face.
    nodes = {}
    elems = []
    lab = 1

    def add_nodes(pts):
        nonlocal lab
        ids = []
        for x in pts:
            nodes[lab] = x
            ids.append(lab)
            lab += 1
        return ids

    h1 = vtk_cell("hexahedron", True, np.array([0.0, 0.0, 0.0]), rng, False)
    ids1 = add_nodes(h1)
    # The second hex shares the +x face of the first: corners 1, 2, 6, 5 → its 0, 3, 7, 4.
    c1 = h1[:8]
    c2 = np.array([c1[1], c1[1] + [0.01, 0, 0], c1[2] + [0.01, 0.001, 0], c1[2],
                   c1[5], c1[5] + [0.01, 0, 0.001], c1[6] + [0.01, 0, 0], c1[6]])
    shared = {0: ids1[1], 3: ids1[2], 7: ids1[6], 4: ids1[5]}
    ids2 = []
    for k in range(8):
        ids2.append(shared[k] if k in shared else add_nodes([c2[k]])[0])
    for a, b in HEX_EDGES:
        # Shared edge (0,3),(3,7),(7,4),(4,0) of hex 2 = edges (1,2),(2,6),(6,5),(5,1) of hex 1.
        pair = {frozenset((0, 3)): 9, frozenset((3, 7)): 18, frozenset((7, 4)): 13,
                frozenset((4, 0)): 17}.get(frozenset((a, b)))
        if pair is not None:
            ids2.append(ids1[pair])
        else:
            ids2.append(add_nodes([(c2[a] + c2[b]) / 2])[0])
    elems.append((1, "C3D20R", ids1))
    elems.append((2, "C3D20R", ids2))
    t10 = vtk_cell("tetra", True, np.array([0.04, 0.0, 0.0]), rng, False)
    elems.append((3, "C3D10", add_nodes(t10)))
    w15 = vtk_cell("wedge", True, np.array([0.06, 0.0, 0.0]), rng, False)
    elems.append((4, "C3D15", add_nodes(w15)))
    h8 = vtk_cell("hexahedron", False, np.array([0.08, 0.0, 0.0]), rng, False)
    elems.append((5, "C3D8I", add_nodes(h8)))

    def fmt(x):
        return f"{x:.17g}"

    lines = ["*HEADING", "squeal reader test (written by make_industrial.py)",
             "** a comment line", "*PART, NAME=Link", "*NODE"]
    for k, x in nodes.items():
        lines.append(f"{k}, {fmt(x[0])}, {fmt(x[1])}, {fmt(x[2])}")
    for e, ty, ids in elems:
        lines.append(f"*ELEMENT, TYPE={ty}, ELSET=E_{ty}")
        items = [str(e)] + [str(i) for i in ids]
        # 16 items per line at most: the rest continue after a trailing comma.
        chunks = [items[i:i + 16] for i in range(0, len(items), 16)]
        lines.append(",\n".join(", ".join(c) for c in chunks))
    lines += [
        "*ELSET, ELSET=HEXES, GENERATE", "1, 2, 1",
        "*ELSET, ELSET=ALL", "HEXES, 3, 4, 5",
        "*NSET, NSET=FIX", f"{ids1[0]}, {ids1[3]}, {ids1[4]}, {ids1[7]}, {ids1[11]}",
        f"*NSET, NSET=HEX1NODES, ELSET=E_C3D20R",
        "*SURFACE, NAME=BOTTOM, TYPE=ELEMENT", "HEXES, S1",
        "*SURFACE, NAME=TETFACE", "3, S2",
        "*SURFACE, NAME=SKIN", "E_C3D15",
        "*ORIENTATION, NAME=FIBRES, SYSTEM=RECTANGULAR",
        "0.6, 0.8, 0.0, -0.8, 0.6, 0.0, 0.0, 0.0, 0.0",
        "3, 0.",
        "*ORIENTATION, NAME=RING, SYSTEM=CYLINDRICAL",
        "0.0, 0.0, -1.0, 0.0, 0.0, 1.0",
        "*SOLID SECTION, ELSET=HEXES, MATERIAL=LINING, ORIENTATION=FIBRES", ",",
        "*SOLID SECTION, ELSET=E_C3D10, MATERIAL=STEEL", ",",
        "*SOLID SECTION, ELSET=E_C3D15, MATERIAL=ORTHO, ORIENTATION=RING", ",",
        "*SOLID SECTION, ELSET=E_C3D8I, MATERIAL=STEEL",
        "*BOUNDARY", "FIX, 1, 3",
        "*END PART",
        "**",
        "*ASSEMBLY, NAME=Assembly",
        "*INSTANCE, NAME=Link-1, PART=Link",
        "*END INSTANCE",
        "*INSTANCE, NAME=Link-2, PART=Link",
        "0.01, 0.2, -0.03",
        "0.01, 0.2, -0.03, 0.11, 0.25, -0.01, 37.5",
        "*END INSTANCE",
        "*NSET, NSET=TIPS, INSTANCE=Link-2",
        f"{ids1[6]}",
        "*NSET, NSET=BOTH_FIX",
        "Link-1.FIX, Link-2.FIX",
        "*SURFACE, NAME=ASM_BOTTOM",
        "Link-2.HEXES, S1",
        "*END ASSEMBLY",
        "*INCLUDE, INPUT=assembly_materials.inp",
        "*STEP", "*FREQUENCY", "10,", "*BOUNDARY", "TIPS, PINNED", "*END STEP",
    ]
    with open(path("assembly.inp"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(path("assembly_materials.inp"), "w") as f:
        f.write(
            "** materials of assembly.inp\n"
            "*MATERIAL, NAME=Steel\n*ELASTIC\n2.1E11, 0.3\n*DENSITY\n7850.,\n"
            "*Material, name=LINING\n*Elastic, type=ENGINEERING CONSTANTS\n"
            "4.0E9, 4.0E9, 1.2E9, 0.25, 0.1, 0.1, 1.6E9, 0.6E9,\n0.6E9\n"
            "*Density\n2500.\n*Damping, structural=0.05\n"
            "*MATERIAL, NAME=ORTHO\n*ELASTIC, TYPE=ORTHOTROPIC\n"
            "12.E9, 3.E9, 10.E9, 2.E9, 2.5E9, 9.E9, 2.E9, 3.E9,\n2.5E9\n*DENSITY\n3000.\n"
            "*EXPANSION\n1.2E-5\n"
        )
    rot = rodrigues([0.01, 0.2, -0.03], [0.11, 0.25, -0.01], 37.5)
    a = np.array([0.01, 0.2, -0.03])
    t = np.array([0.01, 0.2, -0.03])
    placed2 = {str(k): (a + rot @ (np.array(x) + t - a)).tolist() for k, x in nodes.items()}
    json.dump(
        {
            "source": "make_industrial.py (numpy): Link-2 = translation, then the rotation "
                      "by 37.5 deg about the axis through a and b (Abaqus *INSTANCE)",
            "link1": {str(k): list(map(float, x)) for k, x in nodes.items()},
            "link2": placed2,
            "rotation": rot.tolist(),
            "elements": [[e, ty, ids] for e, ty, ids in elems],
        },
        open(path("assembly.json"), "w"),
        indent=1,
    )


if __name__ == "__main__":
    bracket()
    bracket_ortho()
    anchor()
    mixed()
    assembly()
