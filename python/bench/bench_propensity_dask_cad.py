"""Benchmark: `squeal.propensity` on a Dask LocalCluster of 2 workers (1 thread each) on the
full-size cad brake's 2 043-DOF model (`components.0.interface.degree = 8`, 550 gaps), with
μ ~ U(0.35, 0.55) (a late value: the workers read the model from the shared model cache and
make the CEA's projection basis once per chunk), and with `--linings` also both pads' lining
modulus U(5.6, 10.4) GPa (the CLI study of docs/bench/propensity_cad_brake_2043_1000.json: then
the client checks the basis against re-reduction and every chunk builds the model with its
component blocks for the reduced-matrix derivative). Writes docs/bench/propensity_cad_brake_dask.json.

    .venv/bin/python python/bench/bench_propensity_dask_cad.py [--samples 160] [--linings] [--cache DIR] [--out F]

The cache folder must hold the model or is filled by the first worker (a miss builds the
301k-DOF model: about 2 min and 8.7 GB). The Python package is the one `scripts/install-python.sh`
installs (the workspace's dev profile: the numerical crates at opt-level 2), or a release build
of it (`MATURIN_PEP517_ARGS="--profile release"` before that script's pip install); the JSON
records which (`profile`).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import tempfile
import time
from pathlib import Path

import squeal

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "examples" / "cad-brake" / "brake.toml"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=160)
    ap.add_argument("--cache", default=None)
    ap.add_argument("--linings", action="store_true")
    ap.add_argument("--profile", default="dev", help="the profile the installed package was built in (recorded)")
    ap.add_argument("--out", default=str(ROOT / "docs" / "bench" / "propensity_cad_brake_dask.json"))
    a = ap.parse_args()
    from distributed import Client, LocalCluster

    scene = squeal.Scene.from_file(SCENE, set={"components.0.interface.degree": 8})
    cache = a.cache or tempfile.mkdtemp(prefix="squeal-cache-")
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster, Client(cluster) as client:
        t0 = time.perf_counter()
        dists = {"friction.law.mu": "uniform(0.35, 0.55)"}
        if a.linings:
            for c in (1, 2):
                dists[f"components.{c}.materials.lining.young"] = "uniform(5.6e9, 10.4e9)"
        r = squeal.propensity(scene, dists, a.samples,
                              client=client, chunks=2, cache=cache,
                              out=tempfile.mkdtemp(prefix="squeal-prop-"))
        wall = time.perf_counter() - t0
    rep = r.report
    s = rep["stats"]
    out = {
        "what": "squeal.propensity on the cad brake's 2 043-DOF model, Dask LocalCluster 2 workers x 1 thread, chunks=2",
        "date": time.strftime("%Y-%m-%d"),
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform()},
        "samples": a.samples,
        "inputs": [i["key"] for i in rep["inputs"]],
        "profile": a.profile,
        "wall_s": wall,
        "stats": s,
        "per_evaluation_s": (s["wall_s"] - s["build_s"]) / max(s["evaluations"], 1),
        "p_unstable": rep["p_unstable"],
        "max_real_part": {k: rep["max_real_part"][k] for k in ("mean", "min", "max")},
        "model": {k: v for k, v in rep["model"].items() if k != "bands"},
    }
    Path(a.out).write_text(json.dumps(out, indent=1))
    print(json.dumps({k: out[k] for k in ("wall_s", "per_evaluation_s", "p_unstable")}, indent=1))


if __name__ == "__main__":
    main()
