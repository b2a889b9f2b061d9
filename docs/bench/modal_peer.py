"""squeal's modal solve beside scipy ``eigsh`` + CHOLMOD on the same matrices, in one run.

The peer: ``scipy.sparse.linalg.eigsh`` (ARPACK, implicitly restarted Lanczos) in shift-invert
mode at squeal's shift sigma, with the operator (K - sigma M)^-1 applied by CHOLMOD's supernodal
Cholesky (scikit-sparse; CHOLMOD's own ordering choice, AMD/METIS) on OpenBLAS. squeal: the
Rust benchmark ``bench_modal`` (block shift-invert Lanczos, ``fe/src/modal``) on the hex20
annulus it builds, which also exports K and M (``--export``).

Each round runs squeal (its own process), then the peer, so that both see the same machine
load; the ratio of each round is peer / squeal wall seconds of the eigen solve (factorisation
included, assembly excluded). Frequencies are compared mode by mode.

Install (Debian 12; scikit-sparse 0.5 needs SuiteSparse 7 and numpy 2, hence 0.4.12)::

    apt-get install libsuitesparse-dev libopenblas0-pthread libopenblas-dev
    .venv/bin/python -m pip install scikit-sparse==0.4.12 numpy==1.26.4

Run::

    cargo build --release -p squeal-fe --example bench_modal
    .venv/bin/python docs/bench/modal_peer.py [--modes 50] [--rounds 3] [--tol 1e-6]
        [--out docs/bench/modal_peer.json] [--bench-args "..."]
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
import scipy.sparse as sp
import scipy.sparse.linalg as spla

ROOT = Path(__file__).resolve().parents[2]


def load_csc(work: Path, name: str, n: int) -> sp.csc_matrix:
    ptr = np.load(work / f"{name}_indptr.npy")
    idx = np.load(work / f"{name}_indices.npy")
    val = np.load(work / f"{name}_data.npy")
    return sp.csc_matrix((val, idx, ptr), shape=(n, n))


def loadavg() -> str:
    try:
        return Path("/proc/loadavg").read_text().strip()
    except OSError:
        return "unknown"


def cholmod_version() -> str:
    for lib in ("/usr/lib/x86_64-linux-gnu/libcholmod.so.3",):
        p = Path(lib)
        if p.exists():
            return os.path.realpath(p).rsplit(".so.", 1)[-1]
    return "unknown"


def blas_of_cholmod() -> str:
    try:
        out = subprocess.run(["ldd", "/usr/lib/x86_64-linux-gnu/libblas.so.3"],
                             capture_output=True, text=True).stdout
        real = os.path.realpath("/usr/lib/x86_64-linux-gnu/libblas.so.3")
        return real + (" (openblas)" if "openblas" in real or "openblas" in out else "")
    except OSError:
        return "unknown"


def peer(k: sp.csc_matrix, m: sp.csc_matrix, sigma: float, nev: int, tol: float) -> dict:
    from sksparse.cholmod import cholesky

    t0 = time.perf_counter()
    c0 = time.process_time()
    a = (k - sigma * m).tocsc()
    t1 = time.perf_counter()
    f = cholesky(a)
    t2 = time.perf_counter()
    n = k.shape[0]
    count = {"solves": 0}

    def solve(b):
        count["solves"] += 1
        return f(b)

    op = spla.LinearOperator((n, n), matvec=solve, dtype=np.float64)
    vals, _ = spla.eigsh(k, k=nev, M=m, sigma=sigma, which="LM", OPinv=op, tol=tol)
    t3 = time.perf_counter()
    c3 = time.process_time()
    vals = np.sort(vals)
    hz = np.sign(vals) * np.sqrt(np.abs(vals)) / (2 * np.pi)
    return {
        "shifted_matrix_s": t1 - t0,
        "factor_s": t2 - t1,
        "eigsh_s": t3 - t2,
        "total_s": t3 - t0,
        "cpu_s": c3 - c0,
        "solves": count["solves"],
        "frequencies_hz": hz.tolist(),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--modes", type=int, default=50)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--tol", type=float, default=1e-6,
                    help="ARPACK tol (relative Ritz residual, as squeal's modal.tol); 0 = machine precision")
    ap.add_argument("--out", default=str(ROOT / "docs/bench/modal_peer.json"))
    ap.add_argument("--bench", default=str(ROOT / "target/release/examples/bench_modal"))
    ap.add_argument("--bench-args", default="", help="extra arguments for bench_modal")
    ap.add_argument("--work", default=str(Path(tempfile.gettempdir()) / "squeal-modal-peer"))
    ap.add_argument("--note", default="", help="what else ran on the machine")
    a = ap.parse_args()
    work = Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    rounds = []
    k = m = None
    for r in range(a.rounds):
        sq_json = work / f"squeal_{r}.json"
        cmd = [a.bench, str(sq_json), "--only", "nd", "--modes", str(a.modes)]
        cmd += a.bench_args.split()
        if r == 0:
            cmd += ["--export", str(work)]
        load0 = loadavg()
        print(" ".join(cmd), flush=True)
        subprocess.run(cmd, check=True, cwd=ROOT, stdout=subprocess.DEVNULL)
        sq = json.loads(sq_json.read_text())
        run = sq["runs"][0]
        if k is None:
            meta = json.loads((work / "meta.json").read_text())
            n, sigma = meta["n"], meta["shift"]
            k = load_csc(work, "k", n)
            m = load_csc(work, "m", n)
        load1 = loadavg()
        pe = peer(k, m, sigma, a.modes, a.tol)
        load2 = loadavg()
        fs = np.array(sq["frequencies_hz"])
        fp = np.array(pe["frequencies_hz"])
        elastic = np.abs(fs) > 1.0
        rel = np.abs(fs - fp)[elastic] / np.abs(fs[elastic])
        rounds.append({
            "round": r,
            "loadavg_before_squeal": load0,
            "loadavg_before_peer": load1,
            "loadavg_after_peer": load2,
            "squeal": {key: run[key] for key in
                       ("factor_nnz", "ordering_s", "factor_s", "lanczos_s", "solve_s",
                        "total_s", "cpu_s", "peak_rss_mb")} | {"modal": run["modal"]},
            "peer": {key: v for key, v in pe.items() if key != "frequencies_hz"},
            "ratio_peer_over_squeal": pe["total_s"] / run["total_s"],
            "cpu_ratio_peer_over_squeal": pe["cpu_s"] / run["cpu_s"] if run.get("cpu_s") else None,
            "max_rel_frequency_difference_elastic": float(rel.max()) if rel.size else None,
            "n_rigid_modes_squeal": int((~elastic).sum()),
        })
        print(f"round {r}: squeal {run['total_s']:.2f} s, peer {pe['total_s']:.2f} s "
              f"(factor {pe['factor_s']:.2f} s, eigsh {pe['eigsh_s']:.2f} s, "
              f"{pe['solves']} solves, cpu {pe['cpu_s']:.2f} s vs {run['cpu_s']:.2f} s), "
              f"ratio {pe['total_s'] / run['total_s']:.2f}, "
              f"max rel freq diff {rounds[-1]['max_rel_frequency_difference_elastic']:.1e}",
              flush=True)
    ratios = sorted(x["ratio_peer_over_squeal"] for x in rounds)
    cpu_ratios = sorted(x["cpu_ratio_peer_over_squeal"] for x in rounds
                        if x["cpu_ratio_peer_over_squeal"] is not None)
    sq_t = sorted(x["squeal"]["total_s"] for x in rounds)
    pe_t = sorted(x["peer"]["total_s"] for x in rounds)
    import sksparse
    report = {
        "what": "modal solve, squeal bench_modal (fe/src/modal) vs scipy eigsh shift-invert + "
                "CHOLMOD (scikit-sparse) on the same K, M, same shift and mode count",
        "case": sq["case"],
        "n_dofs": sq["n_dofs"],
        "n_modes": a.modes,
        "tol": a.tol,
        "shift": sigma,
        "bench_args": a.bench_args,
        "rounds": rounds,
        "median_squeal_s": sq_t[len(sq_t) // 2],
        "median_peer_s": pe_t[len(pe_t) // 2],
        "median_ratio_peer_over_squeal": ratios[len(ratios) // 2],
        "median_cpu_ratio_peer_over_squeal": cpu_ratios[len(cpu_ratios) // 2] if cpu_ratios else None,
        "min_ratio": ratios[0],
        "max_ratio": ratios[-1],
        "squeal_seconds_per_mode": sq_t[len(sq_t) // 2] / a.modes,
        "peer_seconds_per_mode": pe_t[len(pe_t) // 2] / a.modes,
        "versions": {
            "python": platform.python_version(),
            "numpy": np.__version__,
            "scipy": scipy.__version__,
            "scikit_sparse": getattr(sksparse, "__version__", "0.4.12"),
            "cholmod_so": cholmod_version(),
            "blas_of_cholmod": blas_of_cholmod(),
        },
        "threads": os.cpu_count(),
        "machine": platform.processor() or platform.machine(),
        "note": a.note,
        "squeal_frequencies_hz": sq["frequencies_hz"],
    }
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(report, indent=1))
    print(json.dumps({key: report[key] for key in
                      ("median_squeal_s", "median_peer_s", "median_ratio_peer_over_squeal")}))


if __name__ == "__main__":
    main()
