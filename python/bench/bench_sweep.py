"""Benchmark: design sweeps on the study brake through the Python package on 1 and 2 Dask
workers, against the CLI's `squeal sweep`. Writes docs/bench/python_sweep.json.

    .venv/bin/python python/bench/bench_sweep.py [--squeal target/debug/squeal]

Two sweeps on examples/sample-brake/base.toml, CEA per value, each run with a fresh model
cache:
- mu: the 7-value μ0 sweep 0.3…0.9 (one reduced model);
- grid: rotor thickness 0.5, 0.6, 0.7 in × pad arc of 3, 4, 5 rotor elements (nine models;
  the CLI sweeps one parameter, so it runs one `squeal sweep` over thickness per arc).
The Python module is built in the workspace's dev profile (numerical crates at opt-level 2):
compare it with the CLI of the same profile (target/debug/squeal, the default).
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

import squeal

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / "examples" / "sample-brake" / "base.toml"
MUS = [0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]
THICKNESS = [0.5, 0.6, 0.7]
ARCS = [3, 4, 5]
ARC_KEYS = ("components.1.geometry.n_elements", "components.2.geometry.n_elements")


def cli_runs(squeal_bin: str, tmp: Path) -> dict:
    out = {}
    t0 = time.perf_counter()
    subprocess.run([squeal_bin, "-q", "sweep", str(BASE), "--param", "friction.law.mu0",
                    "--values", ",".join(map(str, MUS)), "--out", str(tmp / "cli-mu"),
                    "--cache", str(tmp / "cli-mu-cache")], check=True)
    out["mu"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    for n in ARCS:
        sets = sum((["--set", f"{k}={n}"] for k in ARC_KEYS), [])
        subprocess.run([squeal_bin, "-q", "sweep", str(BASE), *sets, "--param",
                        "components.0.geometry.thickness", "--values", ",".join(map(str, THICKNESS)),
                        "--out", str(tmp / f"cli-grid-{n}"), "--cache", str(tmp / "cli-grid-cache")],
                       check=True)
    out["grid"] = time.perf_counter() - t0
    return out


def py_runs(workers: int, tmp: Path) -> dict:
    from dask.distributed import Client, LocalCluster

    scene = squeal.Scene.from_file(BASE)
    res = {}
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        client.run(lambda: __import__("squeal"))  # workers import the package before timing
        t0 = time.perf_counter()
        df = squeal.sweep(scene, "friction.law.mu0", MUS, client=client,
                          out=tmp / f"py{workers}-mu", cache=tmp / f"py{workers}-mu-cache")
        res["mu"] = {"wall_s": time.perf_counter() - t0, "n_built": df.attrs["n_built"],
                     "n_failed": df.attrs["n_failed"],
                     "max_real_part": [float(x) for x in df["cea.max_real_part"]]}
        keys = ("components.0.geometry.thickness", *ARC_KEYS)
        grid = [(t, n, n) for t in THICKNESS for n in ARCS]
        t0 = time.perf_counter()
        df = squeal.sweep(scene, keys, grid, client=client,
                          out=tmp / f"py{workers}-grid", cache=tmp / f"py{workers}-grid-cache")
        res["grid"] = {"wall_s": time.perf_counter() - t0, "n_built": df.attrs["n_built"],
                       "n_failed": df.attrs["n_failed"],
                       "max_real_part": [float(x) for x in df["cea.max_real_part"]]}
    return res


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--squeal", default=str(ROOT / "target" / "debug" / "squeal"))
    ap.add_argument("--out", default=str(ROOT / "docs" / "bench" / "python_sweep.json"))
    args = ap.parse_args()
    load_before = os.getloadavg()
    with tempfile.TemporaryDirectory(prefix="squeal-bench-") as d:
        tmp = Path(d)
        cli = cli_runs(args.squeal, tmp)
        py = {w: py_runs(w, tmp) for w in (1, 2)}
    doc = {
        "what": "CEA sweeps on examples/sample-brake/base.toml, fresh model cache each; wall seconds",
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(),
                    "load_average_1_5_15_before": list(load_before),
                    "load_average_1_5_15_after": list(os.getloadavg())},
        "build": "Python module: workspace dev profile (numerical crates opt-level 2); CLI: "
                 + os.path.relpath(args.squeal, ROOT),
        "sweeps": {
            "mu": {"values": MUS, "models": 1,
                   "cli_s": cli["mu"],
                   "dask_1_worker_s": py[1]["mu"]["wall_s"],
                   "dask_2_workers_s": py[2]["mu"]["wall_s"],
                   "n_built": [py[1]["mu"]["n_built"], py[2]["mu"]["n_built"]],
                   "max_real_part": py[2]["mu"]["max_real_part"]},
            "grid": {"thickness": THICKNESS, "pad_arc_elements": ARCS, "models": 9,
                     "cli_s": cli["grid"],
                     "dask_1_worker_s": py[1]["grid"]["wall_s"],
                     "dask_2_workers_s": py[2]["grid"]["wall_s"],
                     "n_built": [py[1]["grid"]["n_built"], py[2]["grid"]["n_built"]],
                     "max_real_part": py[2]["grid"]["max_real_part"]},
        },
    }
    Path(args.out).write_text(json.dumps(doc, indent=2) + "\n")
    print(json.dumps(doc["sweeps"], indent=2))


if __name__ == "__main__":
    main()
