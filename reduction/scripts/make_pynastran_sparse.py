#!/usr/bin/env python3
"""Write pyNastran's ASCII *sparse* OP4 test file of squeal-reduction.

Run from the repository root with the project virtual environment:

    .venv/bin/python reduction/scripts/make_pynastran_sparse.py

pyNastran (1.4) writes a scipy ``coo_matrix`` as a sparse ASCII OP4 whose non-BIGMAT string
headers ``IS = IROW + 65536 (L + 1)`` carry the word count of the whole column (``L + 1`` =
the column record's ``NW``, ``L`` = twice the column's number of values) instead of the
string's, and a column record ``NW = L + 1`` that is not the sum of its strings: each string's
numbers end where the next integer line starts (that is how pyNastran reads them back). The
file holds a real double, a real single (float32) and a complex double matrix, with columns of
one and of several strings and an empty column; ``pynastran_ascii_sparse.json`` holds the exact
values (column-major, like faer). The file is read back with pyNastran and compared before it
is kept.
"""

import json
from pathlib import Path

import numpy as np
import pyNastran
import scipy.sparse as sp
from pyNastran.op4.op4 import OP4

OUT = Path(__file__).resolve().parent.parent / "tests" / "data" / "op4"


def main():
    a = np.zeros((7, 4))
    a[0, 0], a[1, 0], a[4, 0], a[5, 0] = 1.5, -2.25, 3.0e-7, 4.0e12  # two strings
    a[2, 1] = 7.0  # one string of one value
    # column 2 empty (not written)
    a[3, 3], a[6, 3], a[0, 3] = 4.0, 1.0e-3, -0.5  # three strings
    s = (a * 0.75).astype(np.float32)
    z = a[:, :3] * (1.0 + 2.0j) + 0.5j * (a[:, :3] != 0)
    mats = {"RD": (2, sp.coo_matrix(a)), "RS": (2, sp.coo_matrix(s)), "ZD": (1, sp.coo_matrix(z))}
    names = list(mats)
    path = OUT / "pynastran_ascii_sparse.op4"
    OP4().write_op4(str(path), mats, name_order=names, is_binary=False)
    back = OP4().read_op4(str(path))
    truth = {}
    for name, (form, m) in mats.items():
        dense = m.toarray()
        got = back[name].data
        got = got.toarray() if hasattr(got, "toarray") else np.asarray(got)
        if got.shape != dense.shape or not np.array_equal(got, dense):
            raise RuntimeError(f"pyNastran reads back {name} differently:\n{got}\n{dense}")
        e = {
            "nrows": int(dense.shape[0]),
            "ncols": int(dense.shape[1]),
            "form": form,
            "re": [float(x) for x in np.real(dense).T.ravel()],
        }
        if np.iscomplexobj(dense):
            e["im"] = [float(x) for x in np.imag(dense).T.ravel()]
        truth[name] = e
    meta = {"writer": f"pyNastran {pyNastran.__version__} OP4.write_op4(coo_matrix, is_binary=False)",
            "generator": "reduction/scripts/make_pynastran_sparse.py", "matrices": truth}
    (OUT / "pynastran_ascii_sparse.json").write_text(json.dumps(meta, indent=1) + "\n")
    print(f"wrote {path} ({path.stat().st_size} bytes)")


if __name__ == "__main__":
    main()
