#!/usr/bin/env python3
"""Write the OP4 and punch (DMIG) interoperability test files of squeal-reduction.

Run from the repository root with the project virtual environment:

    .venv/bin/python reduction/scripts/make_interop_data.py

Needs numpy, scipy, pandas, pyNastran and pyyeti (``.venv/bin/pip install pyNastran pyyeti``).
Matrices come from a seeded RNG; the exact values are written to ``tests/data/truth.json`` (float
reprs round-trip exactly) next to the files, and ``tests/data/manifest.json`` lists every file, its
writer, and the name, form and type code of every matrix it holds. Each file is read back with
pyyeti (and pyNastran where it can) and compared with the truth before it is listed; files a
library writes inconsistently are left out, with a message.
"""

import io
import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import scipy.sparse as sp
import pyNastran
import pyyeti
from pyNastran.bdf.bdf import BDF
from pyNastran.op4.op4 import OP4 as PnOP4
from pyyeti.nastran import bulk
from pyyeti.nastran import op4 as yop4

OUT = Path(__file__).resolve().parent.parent / "tests" / "data"
SEED = 20240611


def random_matrices(rng):
    """Dense test matrices with zero runs, a zero column and entries over 12 decades."""

    def scaled(shape):
        return rng.standard_normal(shape) * 10.0 ** rng.integers(-6, 7, size=shape)

    n = 7
    a = scaled((n, n))
    a[rng.random((n, n)) < 0.4] = 0.0
    ksym = np.tril(a) + np.tril(a, -1).T
    rect = scaled((6, 4))
    rect[rng.random((6, 4)) < 0.3] = 0.0
    rect[:, 2] = 0.0  # an all-zero column is not written
    rect[1:4, 0] = 0.0  # a zero run inside a column: two sparse strings
    cplx = scaled((5, 5)) + 1j * scaled((5, 5))
    cplx[rng.random((5, 5)) < 0.35] = 0.0
    return {"KSYM": ksym, "RECT": rect, "CPLX": cplx}


def dmig_matrices(rng):
    """DMIG test matrices with their DOFs; values k/8 (small field) or k/16 (large field) so
    that every field width holds them exactly."""
    kdofs = [(101, 1), (101, 2), (101, 3), (101, 6), (205, 1), (205, 2), (205, 3), (9001, 0)]
    n = len(kdofs)
    a = rng.integers(-4000, 4000, size=(n, n)) / 8.0
    a[rng.random((n, n)) < 0.4] = 0.0
    np.fill_diagonal(a, np.abs(np.diag(a)) + 1.0)
    k = np.tril(a) + np.tril(a, -1).T
    rdofs = [(11, 1), (11, 3), (12, 2), (12, 4), (13, 5), (9002, 0)]
    cdofs = [(11, 1), (13, 6), (9003, 0)]
    r = rng.integers(-2**19, 2**19, size=(len(rdofs), len(cdofs))) / 16.0
    r[0, 1] = 0.0
    sdofs = [(7, 1), (7, 2), (8, 1)]
    s = rng.integers(-4000, 4000, size=(3, 3)) / 8.0
    s[2, 0] = 0.0
    c = (rng.integers(-2**19, 2**19, size=(3, 3)) + 1j * rng.integers(-2**19, 2**19, size=(3, 3))) / 16.0
    c[1, 2] = 0.0
    return {
        "KDMIG": (k, kdofs, kdofs, 6),
        "RDMIG": (r, rdofs, cdofs, 2),
        "SDMIG": (s, sdofs, sdofs, 1),
        "CDMIG": (c, sdofs, sdofs, 1),
    }


def truth_entry(m, rows=None, cols=None):
    m = np.asarray(m)
    e = {
        "nrows": int(m.shape[0]),
        "ncols": int(m.shape[1]),
        # column-major, like faer
        "re": [float(x) for x in np.real(m).T.ravel()],
    }
    if np.iscomplexobj(m):
        e["im"] = [float(x) for x in np.imag(m).T.ravel()]
    if rows is not None:
        e["rows"] = [list(map(int, d)) for d in rows]
        e["cols"] = [list(map(int, d)) for d in cols]
    return e


def close(a, b, single):
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape:
        return False
    if single:
        b = b.astype(np.complex64 if np.iscomplexobj(b) else np.float32)
        return np.array_equal(a.astype(b.dtype), b)
    return np.allclose(a, b, rtol=1e-12, atol=0.0)


def check_op4(path, truth, single):
    got = yop4.read(str(path), justmatrix=True, sparse=False)
    for name, m in truth.items():
        if not close(got[name.lower()], m, single):
            raise RuntimeError(f"pyyeti reads back {name} of {path.name} differently")


def dmig_frame(m, rows, cols):
    ri = pd.MultiIndex.from_tuples(rows, names=["id", "dof"])
    ci = pd.MultiIndex.from_tuples(cols, names=["id", "dof"])
    return pd.DataFrame(m, index=ri, columns=ci)


def main():
    rng = np.random.default_rng(SEED)
    mats = random_matrices(rng)
    dmig = dmig_matrices(rng)
    (OUT / "op4").mkdir(parents=True, exist_ok=True)
    (OUT / "punch").mkdir(parents=True, exist_ok=True)
    forms = {"KSYM": 6, "RECT": 2, "CPLX": 1}
    manifest = []
    yeti = f"pyyeti {pyyeti.__version__}"
    pyn = f"pyNastran {pyNastran.__version__}"

    def listed(rel, writer, names, typ, kind="op4", single=False):
        entry = {"file": rel, "format": kind, "writer": writer, "single": single, "matrices": []}
        for nm in names:
            t = typ(nm)
            entry["matrices"].append({"name": nm, "form": forms_all[nm], "type": t})
        manifest.append(entry)

    forms_all = dict(forms)
    forms_all.update({k: v[3] for k, v in dmig.items()})
    real_type = lambda single: (lambda nm: (1 if single else 2) + (2 if nm in ("CPLX", "CDMIG") else 0))

    # ---- OP4 by pyyeti: double precision, every layout, both byte orders ----
    o4 = yop4.OP4()
    names = list(mats)
    cases = [
        ("yeti_ascii_dense.op4", dict(binary=False, sparse="dense")),
        ("yeti_ascii_nonbigmat.op4", dict(binary=False, sparse="nonbigmat")),
        ("yeti_ascii_bigmat.op4", dict(binary=False, sparse="bigmat")),
        ("yeti_bin_dense_le.op4", dict(binary=True, sparse="dense", endian="<")),
        ("yeti_bin_dense_be.op4", dict(binary=True, sparse="dense", endian=">")),
        ("yeti_bin_nonbigmat_le.op4", dict(binary=True, sparse="nonbigmat", endian="<")),
        ("yeti_bin_bigmat_be.op4", dict(binary=True, sparse="bigmat", endian=">")),
    ]
    for fname, kw in cases:
        path = OUT / "op4" / fname
        o4.write(str(path), names, [mats[n] for n in names], forms=[forms[n] for n in names], **kw)
        check_op4(path, mats, single=False)
        listed(f"op4/{fname}", f"{yeti} OP4.write({kw})", names, real_type(False))

    # ---- OP4 by pyNastran: ASCII, single precision (float32 / complex64) and double ----
    pn = PnOP4()
    for fname, single in (("pynastran_ascii_single.op4", True), ("pynastran_ascii_double.op4", False)):
        path = OUT / "op4" / fname
        conv = {
            n: (forms[n], m.astype((np.complex64 if np.iscomplexobj(m) else np.float32) if single else m.dtype))
            for n, m in mats.items()
        }
        pn.write_op4(str(path), conv, name_order=names, is_binary=False)
        try:
            check_op4(path, mats, single=single)
        except Exception as exc:  # noqa: BLE001 - report and leave the file out
            print(f"skipping {fname}: {exc}", file=sys.stderr)
            path.unlink()
            continue
        listed(f"op4/{fname}", f"{pyn} write_op4(is_binary=False)", names, real_type(single), single=single)

    # ---- punch DMIG by pyyeti (small-field header, large-field columns, 10 digits) ----
    path = OUT / "punch" / "yeti_large.pch"
    frames = {n: dmig_frame(m, r, c) for n, (m, r, c, _) in dmig.items()}
    with open(path, "w") as f:
        bulk.wtdmig(f, frames)
    back = bulk.rddmig(str(path))
    for n, (m, r, c, _) in dmig.items():
        df = back[n.lower()] if n.lower() in back else back[n]
        full = df.reindex(index=pd.MultiIndex.from_tuples(r), columns=pd.MultiIndex.from_tuples(c), fill_value=0.0)
        if not close(full.values, m, False):
            raise RuntimeError(f"pyyeti reads back DMIG {n} differently")
    listed("punch/yeti_large.pch", f"{yeti} bulk.wtdmig", list(dmig), real_type(False), kind="punch")

    # ---- punch DMIG by pyNastran: small field (TIN 1) and large field (TIN 2, 4) ----
    for fname, size, single in (("pynastran_small.pch", 8, True), ("pynastran_large.pch", 16, False)):
        model = BDF(debug=None)
        for n, (m, r, c, ifo) in dmig.items():
            if single and np.iscomplexobj(m):
                continue
            if single and n == "RDMIG":
                continue  # k/16 values need more than 8 characters
            gcj, gci, re, im = [], [], [], []
            for j, cd in enumerate(c):
                for i, rd in enumerate(r):
                    if m[i, j] != 0 and (ifo != 6 or i >= j):
                        gcj.append(tuple(cd)); gci.append(tuple(rd))
                        re.append(float(np.real(m[i, j]))); im.append(float(np.imag(m[i, j])))
            cplx = np.iscomplexobj(m)
            tin = (3 if cplx else 1) if single else (4 if cplx else 2)
            model.add_dmig(n, ifo, tin, 0, 0, 0, gcj, gci, re, Complex=im if cplx else None)
        path = OUT / "punch" / fname
        model.write_bdf(str(path), size=size, is_double=False)
        names_in = list(model.dmig)
        check = BDF(debug=None)
        check.read_bdf(str(path), punch=True)
        for n in names_in:
            m, r, c, ifo = dmig[n]
            got, rows, cols = check.dmig[n].get_matrix(is_sparse=False, apply_symmetry=True)
            ri = {tuple(map(int, v)): k for k, v in rows.items()}
            ci = {tuple(map(int, v)): k for k, v in cols.items()}
            sub = np.array([[got[ri[tuple(a)], ci[tuple(b)]] if tuple(a) in ri and tuple(b) in ci else 0.0
                             for b in c] for a in r])
            if not close(sub, m, single):
                raise RuntimeError(f"pyNastran reads back DMIG {n} of {fname} differently")
        listed(f"punch/{fname}", f"{pyn} BDF.write_bdf(size={size})", names_in, real_type(single),
               kind="punch", single=single)

    truth = {n: truth_entry(m) for n, m in mats.items()}
    truth.update({n: truth_entry(m, r, c) for n, (m, r, c, _) in dmig.items()})
    (OUT / "truth.json").write_text(json.dumps(truth, indent=1) + "\n")
    (OUT / "manifest.json").write_text(json.dumps(
        {"generator": "reduction/scripts/make_interop_data.py", "seed": SEED, "files": manifest},
        indent=1) + "\n")
    total = sum(p.stat().st_size for p in OUT.rglob("*") if p.is_file())
    print(f"wrote {len(manifest)} files, {total} bytes in {OUT}")


if __name__ == "__main__":
    main()
