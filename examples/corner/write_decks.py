"""The corner as a CAE department hands it over: a Nastran deck and an Abaqus input file written
from the gmsh meshes squeal makes of the .geo files, and a scene for each that reads them.

    squeal mesh examples/corner/corner.toml --out out/corner-mesh     # the gmsh meshes
    python examples/corner/write_decks.py out/corner-mesh/mesh out/corner-decks
    squeal cea out/corner-decks/corner-bdf.toml                       # the Nastran route
    squeal cea out/corner-decks/corner-inp.toml                       # the Abaqus route

Pass the same --set values to `squeal mesh` as to the runs you compare (mesh sizes, pad_angle);
give `--set` lines after `--` to apply them to the scene read here too (materials, …).

What the files hold (everything the gmsh route takes from the scene):
- corner.bdf (pyNastran, large field, double precision): per component its GRIDs (ids from
  1 000 000 × (component + 1)), CTETRA 10-node elements with one PSOLID per body (PID
  100 × (component + 1) + body), MAT1 (isotropic; GE = the loss factor) or MAT9 (the
  transversely isotropic lining and shim, the 6×6 stiffness in Nastran's order from the
  engineering constants; GE) in the basic system, CTRIA6 shells with one non-structural PSHELL per
  named face set (PID 100 × (component + 1) + 50 + set: squeal reads them as the face set
  pid_<PID>), and SPC1 set 1 for the fixed sets.
- corner.inp: one *PART per component (C3D10, *ELSET per body, element-based *SURFACE per
  named face set with the faces S1…S4, *SOLID SECTION per body), one *INSTANCE each, the
  *MATERIALs (*ELASTIC ISOTROPIC or ENGINEERING CONSTANTS, *DENSITY, *DAMPING STRUCTURAL) and
  the fixed sets as *BOUNDARY on instance node sets.
- corner-bdf.toml, corner-inp.toml: corner.toml with each component's geometry read from the
  file, its materials and fixed sets taken from the file, and the face names the file's.

Tet10 node orders: meshio returns VTK's (edges 01, 12, 20, 03, 13, 23), which is Abaqus's
C3D10 order and, through meshio's permutation, Nastran's CTETRA.
"""
import os
import sys
import tomllib

import meshio
import numpy as np
from meshio.nastran._nastran import _convert_to_nastran_ordering
from pyNastran.bdf.bdf import BDF

HERE = os.path.dirname(os.path.abspath(__file__))
DOFS = {"x": "1", "y": "2", "z": "3"}
TET_FACES = [(0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0)]  # Abaqus S1..S4 (0-based corners)


def set_value(scene, key, value):
    """Applies one `dotted.key=value` override (numbers, strings, booleans)."""
    parts = key.split(".")
    node = scene
    for p in parts[:-1]:
        node = node[int(p)] if isinstance(node, list) else node.setdefault(p, {})
    v = value
    for conv in (int, float):
        try:
            v = conv(value)
            break
        except ValueError:
            pass
    if value in ("true", "false"):
        v = value == "true"
    last = parts[-1]
    if isinstance(node, list):
        node[int(last)] = v
    else:
        node[last] = v


def orthotropic(m):
    """(e1, e2, e3, nu12, nu13, nu23, g12, g13, g23) of a scene material table, or None."""
    t = m.get("transversely_isotropic")
    if t is not None:
        g12 = t["e_plane"] / (2 * (1 + t["nu_plane"]))
        return (t["e_plane"], t["e_plane"], t["e_axis"], t["nu_plane"], t["nu_plane_axis"],
                t["nu_plane_axis"], g12, t["g_axis"], t["g_axis"])
    o = m.get("orthotropic")
    if o is not None:
        return tuple(o[k] for k in ("e1", "e2", "e3", "nu12", "nu13", "nu23", "g12", "g13", "g23"))
    return None


def stiffness_nastran(c):
    """MAT9's 6x6 stiffness in Nastran's strain order (xx, yy, zz, xy, yz, zx)."""
    e1, e2, e3, n12, n13, n23, g12, g13, g23 = c
    s = np.zeros((6, 6))
    s[0, 0], s[1, 1], s[2, 2] = 1 / e1, 1 / e2, 1 / e3
    s[0, 1] = s[1, 0] = -n12 / e1
    s[0, 2] = s[2, 0] = -n13 / e1
    s[1, 2] = s[2, 1] = -n23 / e2
    s[3, 3], s[4, 4], s[5, 5] = 1 / g12, 1 / g23, 1 / g13
    return np.linalg.inv(s)


def check_axes(m, where):
    axes = m.get("axes")
    if axes is None:
        return
    if not (axes.get("kind") == "rectangular" and axes.get("e1") == [1.0, 0.0, 0.0]
            and axes.get("e2") == [0.0, 1.0, 0.0]):
        sys.exit(f"{where}: material axes other than the global ones are not written here")


class Component:
    """One component's mesh: points, tet10 cells (VTK order) per body, tri6 faces per set."""

    def __init__(self, spec, mesh_dir):
        self.name = spec["name"]
        m = meshio.read(os.path.join(mesh_dir, self.name + ".msh"))
        names = {int(tag): name for name, (tag, dim) in m.field_data.items()}
        self.points = m.points
        self.bodies = {}  # name -> tet10 cells
        self.faces = {}   # name -> tri6 faces
        for block, tags in zip(m.cells, m.cell_data["gmsh:physical"]):
            for tag in np.unique(tags):
                cells = np.asarray(block.data)[tags == tag]
                name = names[int(tag)]
                if block.type == "tetra10":
                    self.bodies.setdefault(name, []).append(cells)
                elif block.type == "triangle6":
                    self.faces.setdefault(name, []).append(cells)
                else:
                    sys.exit(f"{self.name}: cells of type {block.type} are not written here")
        self.bodies = {k: np.vstack(v) for k, v in sorted(self.bodies.items())}
        self.faces = {k: np.vstack(v) for k, v in sorted(self.faces.items())}
        # Every face of a set as (element index within the component, Abaqus face number).
        cells = np.vstack(list(self.bodies.values()))
        owner = {}
        for e, c in enumerate(cells):
            for k, f in enumerate(TET_FACES):
                owner.setdefault(tuple(sorted(int(c[i]) for i in f)), (e, k + 1))
        self.cells = cells
        self.face_owner = {}
        for name, tris in self.faces.items():
            try:
                self.face_owner[name] = [owner[tuple(sorted(int(x) for x in t[:3]))] for t in tris]
            except KeyError:
                sys.exit(f"{self.name}: face set {name} has a face that is no tet10's face")

    def materials(self, spec):
        """Material table per body: the scene's materials.<body>, else its material."""
        out = {}
        for body in self.bodies:
            m = spec.get("materials", {}).get(body, spec.get("material"))
            if m is None:
                sys.exit(f"{self.name}: body {body} has no material in the scene")
            check_axes(m, f"components[{self.name}].materials.{body}")
            out[body] = m
        return out

    def node_set(self, face_set):
        return sorted({int(n) for t in self.faces[face_set] for n in t})


def write_bdf(comps, specs, path):
    bdf = BDF(debug=False)
    pid_of_face = {}
    mid = 0
    for k, (c, spec) in enumerate(zip(comps, specs)):
        base = 1_000_000 * (k + 1)
        for i, x in enumerate(c.points):
            bdf.add_grid(base + i + 1, [float(v) for v in x])
        e = base
        materials = c.materials(spec)
        for b, (body, cells) in enumerate(c.bodies.items()):
            pid = 100 * (k + 1) + b + 1
            mid += 1
            m = materials[body]
            ge = m.get("loss_factor", 0.0)
            ortho = orthotropic(m)
            if ortho is not None:
                s = stiffness_nastran(ortho)
                g = [s[i, j] for i in range(6) for j in range(i, 6)]
                bdf.add_mat9(mid, *g, rho=m["density"], ge=ge)
            else:
                bdf.add_mat1(mid, m["young"], None, m["poisson"], rho=m["density"], ge=ge)
            bdf.add_psolid(pid, mid, cordm=0)
            for cell in cells:
                e += 1
                nids = [base + int(n) + 1 for n in _convert_to_nastran_ordering(cell.tolist(), "CTETRA")]
                bdf.add_ctetra(e, pid, nids)
        for s, (name, tris) in enumerate(c.faces.items()):
            pid = 100 * (k + 1) + 50 + s + 1
            pid_of_face[(c.name, name)] = f"pid_{pid}"
            bdf.add_pshell(pid, mid1=None, t=None)
            for t in tris:
                e += 1
                bdf.add_ctria6(e, pid, [base + int(n) + 1 for n in t])
        for f in spec.get("fixed", []):
            comp = "".join(DOFS[d] for d in f["dofs"])
            bdf.add_spc1(1, comp, [base + n + 1 for n in c.node_set(f["set"])])
    bdf.write_bdf(path, size=16, is_double=True)
    return pid_of_face


def fortran(x):
    return repr(float(x))


def write_inp(comps, specs, path):
    lines = ["*HEADING", "squeal corner (examples/corner/write_decks.py)"]
    mats = []
    for c, spec in zip(comps, specs):
        part = c.name.upper()
        lines += [f"*PART, NAME={part}", "*NODE"]
        lines += [f"{i + 1}, {fortran(x[0])}, {fortran(x[1])}, {fortran(x[2])}" for i, x in enumerate(c.points)]
        e = 0
        materials = c.materials(spec)
        for body, cells in c.bodies.items():
            lines.append(f"*ELEMENT, TYPE=C3D10, ELSET={body}")
            for cell in cells:
                e += 1
                lines.append(f"{e}, " + ", ".join(str(int(n) + 1) for n in cell))
        for name, owners in c.face_owner.items():
            lines.append(f"*SURFACE, TYPE=ELEMENT, NAME={name}")
            lines += [f"{el + 1}, S{k}" for el, k in owners]
        for f in spec.get("fixed", []):
            nodes = c.node_set(f["set"])
            lines.append(f"*NSET, NSET={f['set']}")
            lines += [", ".join(str(n + 1) for n in nodes[i:i + 16]) for i in range(0, len(nodes), 16)]
        for body in c.bodies:
            mname = f"{c.name}_{body}".upper()
            lines.append(f"*SOLID SECTION, ELSET={body}, MATERIAL={mname}")
            lines.append(",")
            mats.append((mname, materials[body]))
        lines.append("*END PART")
    lines.append("*ASSEMBLY, NAME=CORNER")
    for c in comps:
        lines += [f"*INSTANCE, NAME={c.name}, PART={c.name.upper()}", "*END INSTANCE"]
    lines.append("*END ASSEMBLY")
    for name, m in mats:
        lines.append(f"*MATERIAL, NAME={name}")
        ortho = orthotropic(m)
        if ortho is not None:
            v = [fortran(x) for x in ortho]
            lines += ["*ELASTIC, TYPE=ENGINEERING CONSTANTS", ", ".join(v[:8]) + ",", v[8]]
        else:
            lines += ["*ELASTIC, TYPE=ISOTROPIC", f"{fortran(m['young'])}, {fortran(m['poisson'])}"]
        lines += ["*DENSITY", fortran(m["density"])]
        if m.get("loss_factor", 0.0) > 0:
            lines.append(f"*DAMPING, STRUCTURAL={fortran(m['loss_factor'])}")
    for c, spec in zip(comps, specs):
        for f in spec.get("fixed", []):
            for d in f["dofs"]:
                lines.append("*BOUNDARY")
                lines.append(f"{c.name}.{f['set']}, {DOFS[d]}, {DOFS[d]}")
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")


# ----------------------------------------------------------------------------- scenes


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {toml_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(type(v))


def toml_table(name, d, array=False):
    head = f"[[{name}]]" if array else f"[{name}]"
    lines = [head]
    for k, v in d.items():
        lines.append(f"{k} = {toml_value(v)}")
    return "\n".join(lines)


def write_scene(scene, path, geometry, face_name, header):
    s = {k: v for k, v in scene.items()}
    comps = []
    for k, c in enumerate(s["components"]):
        c = dict(c)
        c["geometry"] = geometry(k, c)
        c.pop("materials", None)
        c.pop("material", None)
        c.pop("fixed", None)
        comps.append(c)
    s["components"] = comps
    s["ties"] = [{**t, "a": {**t["a"], "faces": face_name(t["a"]["component"], t["a"]["faces"])},
                  "b": {**t["b"], "faces": face_name(t["b"]["component"], t["b"]["faces"])}}
                 for t in s.get("ties", [])]
    s["contact"] = [{**p, "pad_faces": face_name(p["pad"], p["pad_faces"]),
                     "rotor_faces": face_name(p["rotor"], p["rotor_faces"])} for p in s.get("contact", [])]
    if "loads" in s:
        s["loads"] = {**s["loads"], "pressure": [{**p, "faces": face_name(p["component"], p["faces"])}
                                                 for p in s["loads"].get("pressure", [])]}
    out = [header]
    for k, v in s.items():
        if not isinstance(v, (dict, list)) or (isinstance(v, list) and v and not isinstance(v[0], dict)):
            out.append(f"{k} = {toml_value(v)}")
    for k, v in s.items():
        if isinstance(v, dict):
            out.append(toml_table(k, v))
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            out += [toml_table(k, x, array=True) for x in v]
    with open(path, "w") as f:
        f.write("\n\n".join(out) + "\n")


def main():
    args = sys.argv[1:]
    sets = []
    if "--" in args:
        i = args.index("--")
        args, sets = args[:i], args[i + 1:]
    if len(args) != 2:
        sys.exit(__doc__)
    mesh_dir, out_dir = args
    scene_path = os.path.join(HERE, "corner.toml")
    with open(scene_path, "rb") as f:
        scene = tomllib.load(f)
    for s in sets:
        k, v = s.split("=", 1)
        set_value(scene, k, v)
    os.makedirs(out_dir, exist_ok=True)
    specs = scene["components"]
    comps = [Component(spec, mesh_dir) for spec in specs]
    bdf_names = write_bdf(comps, specs, os.path.join(out_dir, "corner.bdf"))
    write_inp(comps, specs, os.path.join(out_dir, "corner.inp"))
    header = ("# Written by examples/corner/write_decks.py from examples/corner/corner.toml: the "
              "same corner, every component read from {}.")
    pids = {k: sorted(100 * (k + 1) + b + 1 for b in range(len(c.bodies))) for k, c in enumerate(comps)}
    write_scene(scene, os.path.join(out_dir, "corner-bdf.toml"),
                lambda k, c: {"kind": "bdf", "path": "corner.bdf", "pids": pids[k], "spc": 1},
                lambda comp, faces: bdf_names[(comp, faces)], header.format("the Nastran deck corner.bdf"))
    write_scene(scene, os.path.join(out_dir, "corner-inp.toml"),
                lambda k, c: {"kind": "inp", "path": "corner.inp", "instances": [c["name"]]},
                lambda comp, faces: faces, header.format("the Abaqus input corner.inp"))
    sizes = {c.name: {"nodes": len(c.points), "tet10": len(c.cells)} for c in comps}
    print(f"wrote {out_dir}/corner.bdf, corner.inp, corner-bdf.toml, corner-inp.toml: {sizes}")


if __name__ == "__main__":
    main()
