"""squeal's CEA beside numpy/scipy on the same matrices, in one run (issue 13, item 3).

Runs the Rust benchmark ``bench_cea_brake`` (the hex20 sample brake: 2153 reduced DOFs, 234
gaps) with ``--npy``: it times squeal's projected + refined CEA, the exact dense CEA and the
50-point friction sweep, and writes the real first-order matrix of the exact method
(``first_order.npy``, size 2(n - ng); its eigenvalues are the roots) with squeal's roots. Then,
on that same matrix:

- ``scipy.linalg.eig`` (all eigenvalues, LAPACK dgeev), compared root by root with squeal's
  dense CEA;
- ``scipy.sparse.linalg.eigs`` in shift-invert mode (ARPACK, sigma = each of squeal's refined
  in-band unstable roots, 6 eigenvalues each), compared with squeal's refined roots.

Writes ``docs/bench/cea_scipy.json`` (seconds and root differences)::

    cargo build --release -p squeal-pipeline --example bench_cea_brake
    .venv/bin/python python/bench/bench_cea_scipy.py [--out docs/bench/cea_scipy.json]
        [--work DIR] [--sweep 50] [--reuse]

``--reuse`` skips the Rust run and reads DIR (default: a folder under the system temp dir).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
import scipy
import scipy.linalg
import scipy.sparse.linalg

ROOT = Path(__file__).resolve().parents[2]


def upper(vals: np.ndarray) -> np.ndarray:
    """One root of each conjugate pair (Im >= 0) and every real root."""
    return vals[vals.imag >= 0.0]


def nearest_rel(p: complex, cands: np.ndarray) -> tuple[complex, float]:
    i = int(np.argmin(np.abs(cands - p)))
    return complex(cands[i]), float(abs(cands[i] - p) / abs(p))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=str(ROOT / "docs/bench/cea_scipy.json"))
    ap.add_argument("--work", default=str(Path(tempfile.gettempdir()) / "squeal-cea-scipy"))
    ap.add_argument("--bench", default=str(ROOT / "target/release/examples/bench_cea_brake"))
    ap.add_argument("--scene", default="examples/transient/sample-brake-case2.toml",
                    help="relative to the repository root (the benchmark runs there)")
    ap.add_argument("--sweep", type=int, default=50)
    ap.add_argument("--reuse", action="store_true")
    a = ap.parse_args()
    work = Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    squeal_json = work / "cea_brake.json"
    if not a.reuse:
        env = dict(os.environ)
        venv_bin = ROOT / ".venv" / "bin"
        env["PATH"] = f"{venv_bin}{os.pathsep}{env.get('PATH', '')}"
        cmd = [a.bench, a.scene, "--npy", str(work), "--out", str(squeal_json),
               "--sweep", str(a.sweep)]
        print(" ".join(cmd), flush=True)
        subprocess.run(cmd, check=True, cwd=ROOT, env=env, stdout=subprocess.DEVNULL)
    sq = json.loads((work / "squeal_roots.json").read_text())
    bench = json.loads(squeal_json.read_text())
    A = np.load(work / "first_order.npy")
    k = A.shape[0]
    print(f"first-order matrix {k} x {k}", flush=True)

    # scipy.linalg.eig: every root.
    t = time.perf_counter()
    w = scipy.linalg.eig(A, right=False, check_finite=False)
    eig_s = time.perf_counter() - t
    w = upper(w)
    print(f"scipy.linalg.eig: {eig_s:.1f} s", flush=True)
    eig_cmp = None
    if sq.get("dense_all"):
        dense = np.array([complex(r[0], r[1]) for r in sq["dense_all"]])
        rel = np.array([nearest_rel(p, w)[1] for p in dense])
        band = sq.get("band_hz") or np.inf
        in_band = np.abs(dense.imag) / (2 * np.pi) <= band
        eig_cmp = {
            "n_roots_squeal": int(len(dense)),
            "n_roots_scipy": int(len(w)),
            "max_rel_diff_all": float(rel.max()),
            "max_rel_diff_in_band": float(rel[in_band].max()) if in_band.any() else None,
            "median_rel_diff_all": float(np.median(rel)),
        }

    # scipy.sparse.linalg.eigs, shift-invert at each refined root.
    Ac = A.astype(complex)
    targets = [complex(r[0], r[1]) for r in sq["refined_in_band_unstable"]]
    per = []
    t_all = time.perf_counter()
    for p in targets:
        t = time.perf_counter()
        vals = scipy.sparse.linalg.eigs(Ac, k=6, sigma=p, which="LM", return_eigenvectors=False)
        dt = time.perf_counter() - t
        q, rel = nearest_rel(p, vals)
        per.append({"squeal_refined": [p.real, p.imag], "scipy_eigs": [q.real, q.imag],
                    "rel_diff": rel, "seconds": dt})
        print(f"eigs at {p:.6g}: {dt:.2f} s, rel diff {rel:.2e}", flush=True)
    eigs_s = time.perf_counter() - t_all

    out = {
        "what": "squeal CEA vs scipy on the same first-order matrix (hex20 sample brake)",
        "machine": {"cpus": os.cpu_count(), "python": platform.python_version(),
                    "numpy": np.__version__, "scipy": scipy.__version__},
        "n_dofs": sq["n_dofs"], "n_gaps": sq["n_gaps"], "first_order_size": k,
        "squeal": {
            "projected_refined_s": sq["projected_s"],
            "dense_exact_s": sq["dense_s"],
            "first_order_form_s": sq["first_order_form_s"],
            "refine": sq["refine"],
            "sweep": bench.get("sweep"),
        },
        "scipy": {
            "eig_s": eig_s,
            "eig_vs_squeal_dense": eig_cmp,
            "eigs_shift_invert_total_s": eigs_s,
            "eigs_shift_invert": per,
            "max_rel_diff_eigs_vs_squeal_refined": max((r["rel_diff"] for r in per),
                                                       default=None),
        },
    }
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(out, indent=2) + "\n")
    print(json.dumps(out["scipy"], indent=2))


if __name__ == "__main__":
    main()
