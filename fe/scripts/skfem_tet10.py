"""Independent reference for squeal's tet10: scikit-fem on the same gmsh tet10 mesh.

The mesh `fe/tests/data/skfem_tet10.msh` is gmsh's (from `skfem_tet10.geo`: a 0.2 x 0.02 x
0.01 m steel bar, second-order tetrahedra with straight edges, physical surface `clamp` at
x = 0). scikit-fem builds its own P2 Lagrange basis on the tetrahedra's corners (ElementTetP2,
its own quadrature), assembles linear elasticity and the consistent mass, clamps the `clamp`
nodes and solves the first eigenpairs with scipy's shift-invert Lanczos. The frequencies go to
`fe/tests/data/skfem_tet10.json`, which `fe/tests/elements.rs` compares with squeal's.

Run: python fe/scripts/skfem_tet10.py   (needs scikit-fem, meshio, numpy, scipy)
"""
import json
from pathlib import Path

import meshio
import numpy as np
import skfem
from scipy.sparse.linalg import eigsh
from skfem.models.elasticity import lame_parameters, linear_elasticity

here = Path(__file__).resolve().parent.parent / "tests" / "data"
E, NU, RHO = 200e9, 0.3, 8000.0

m = meshio.read(here / "skfem_tet10.msh")
tets = m.cells_dict["tetra10"][:, :4]
used = np.unique(tets)
index = -np.ones(len(m.points), dtype=int)
index[used] = np.arange(len(used))
mesh = skfem.MeshTet(m.points[used].T, index[tets].T)
basis = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementTetP2()))
K = skfem.asm(linear_elasticity(*lame_parameters(E, NU)), basis)


@skfem.BilinearForm
def mass(u, v, w):
    return RHO * skfem.helpers.dot(u, v)


M = skfem.asm(mass, basis)
clamped = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
free = np.setdiff1d(np.arange(basis.N), clamped)
Kf, Mf = K[free][:, free], M[free][:, free]
lam, _ = eigsh(Kf, k=6, M=Mf, sigma=0.0, which="LM", tol=1e-12)
freqs = np.sort(np.sqrt(lam)) / (2 * np.pi)
out = {
    "source": "scikit-fem %s, ElementTetP2 (vector), linear_elasticity + consistent mass, "
    "clamped at x = 0, scipy eigsh shift-invert; mesh fe/tests/data/skfem_tet10.msh (gmsh, "
    "%d tet10); E = 200 GPa, nu = 0.3, rho = 8000 kg/m^3; written by fe/scripts/skfem_tet10.py"
    % (skfem.__version__, len(tets)),
    "frequencies_hz": [float(f) for f in freqs],
}
(here / "skfem_tet10.json").write_text(json.dumps(out, indent=1) + "\n")
print(out)
