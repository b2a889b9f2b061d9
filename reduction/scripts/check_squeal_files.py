#!/usr/bin/env python3
"""Read OP4 and punch (DMIG) files written by squeal with pyyeti and pyNastran, and compare
them with the values they were written from.

    .venv/bin/python reduction/scripts/check_squeal_files.py MANIFEST.json

MANIFEST.json: {"files": [{"file": path, "format": "op4" | "punch", "single": bool,
"rtol": float, "binary": bool (op4), "matrices": [{"name", "form", "type", "nrows", "ncols",
"re": column-major list, "im": list or null, "rows"/"cols": [[grid, comp], ...] (punch)}]}]}.

OP4 files are read with pyyeti (every layout) and with pyNastran (ASCII files; its binary
reader is not used). Punch files are read with pyyeti's rddmig and pyNastran's BDF reader.
Single-precision files are compared exactly with the values rounded to float32. Exits 1 on
any mismatch, listing them.
"""

import json
import sys

import numpy as np
import pandas as pd
from pyNastran.bdf.bdf import BDF
from pyNastran.op4.op4 import read_op4
from pyyeti.nastran import bulk
from pyyeti.nastran import op4 as yop4


def truth(m):
    shape = (m["ncols"], m["nrows"])
    a = np.array(m["re"], dtype=float).reshape(shape).T
    if m.get("im") is not None:
        a = a + 1j * np.array(m["im"], dtype=float).reshape(shape).T
    return a


def compare(got, want, single, rtol):
    got = np.asarray(got)
    if got.shape != want.shape:
        return f"shape {got.shape} != {want.shape}"
    if single:
        dt = np.complex64 if np.iscomplexobj(want) else np.float32
        if not np.array_equal(got.astype(dt), want.astype(dt)):
            return f"single-precision values differ (max {np.abs(got - want).max():.3e})"
        return None
    scale = np.abs(want).max() if want.size else 0.0
    err = np.abs(got - want).max() if want.size else 0.0
    if err > rtol * scale:
        return f"max |difference| {err:.3e} > {rtol:g} x {scale:.3e}"
    return None


def check_op4(f, fail):
    path = f["file"]
    y = yop4.load(path, into="dct", justmatrix=False, sparse=False)
    for m in f["matrices"]:
        key = m["name"].lower()
        if key not in y:
            fail(f"{path}: pyyeti finds no {m['name']} (has {list(y)})")
            continue
        mat, form, mtype = y[key]
        if (form, mtype) != (m["form"], m["type"]):
            fail(f"{path} {m['name']}: pyyeti reads form {form} type {mtype}, wrote {m['form']} {m['type']}")
        err = compare(mat, truth(m), f["single"], f["rtol"])
        if err:
            fail(f"{path} {m['name']} (pyyeti): {err}")
    if f.get("binary"):
        return
    pn = read_op4(path, debug=False)
    for m in f["matrices"]:
        got = pn.get(m["name"])
        if got is None:
            fail(f"{path}: pyNastran finds no {m['name']} (has {list(pn)})")
            continue
        data = got.data if hasattr(got, "data") else got[1]
        if hasattr(data, "toarray"):
            data = data.toarray()
        err = compare(data, truth(m), f["single"], f["rtol"])
        if err:
            fail(f"{path} {m['name']} (pyNastran): {err}")


def check_punch(f, fail):
    path = f["file"]
    y = bulk.rddmig(path)
    model = BDF(debug=None)
    model.read_bdf(path, punch=True)
    for m in f["matrices"]:
        want = truth(m)
        rows = [tuple(r) for r in m["rows"]]
        cols = [tuple(c) for c in m["cols"]]
        df = y.get(m["name"].lower(), y.get(m["name"]))
        if df is None:
            fail(f"{path}: pyyeti finds no DMIG {m['name']}")
        else:
            full = df.reindex(index=pd.MultiIndex.from_tuples(rows), columns=pd.MultiIndex.from_tuples(cols),
                              fill_value=0.0)
            err = compare(full.values, want, f["single"], f["rtol"])
            if err:
                fail(f"{path} {m['name']} (pyyeti): {err}")
        d = model.dmig.get(m["name"])
        if d is None:
            fail(f"{path}: pyNastran finds no DMIG {m['name']}")
            continue
        if (d.matrix_form, d.tin) != (m["form"], m["type"]):
            fail(f"{path} {m['name']}: pyNastran reads IFO {d.matrix_form} TIN {d.tin}, wrote {m['form']} {m['type']}")
        got, prow, pcol = d.get_matrix(is_sparse=False, apply_symmetry=True)
        ri = {tuple(map(int, v)): k for k, v in prow.items()}
        ci = {tuple(map(int, v)): k for k, v in pcol.items()}
        sub = np.array([[got[ri[a], ci[b]] if a in ri and b in ci else 0.0 for b in cols] for a in rows])
        err = compare(sub, want, f["single"], f["rtol"])
        if err:
            fail(f"{path} {m['name']} (pyNastran): {err}")


def main():
    manifest = json.load(open(sys.argv[1]))
    failures = []
    for f in manifest["files"]:
        try:
            (check_op4 if f["format"] == "op4" else check_punch)(f, failures.append)
        except Exception as exc:  # noqa: BLE001 - a reader crash is a failure to report
            failures.append(f"{f['file']}: reader raised {type(exc).__name__}: {exc}")
    for msg in failures:
        print("MISMATCH", msg)
    print(f"checked {len(manifest['files'])} files, {len(failures)} mismatches")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
