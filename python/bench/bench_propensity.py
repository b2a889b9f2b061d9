"""Benchmark: `squeal propensity` on the study brake, 1 000 evaluations, through the CLI, the
Python package on local threads, and the Python package on a Dask LocalCluster of 2 workers.
Writes docs/bench/propensity.json.

    .venv/bin/python python/bench/bench_propensity.py [--squeal target/release/squeal] [--samples 1000]

Inputs (late values: one reduced model, built before the timed part is split out as build_s):
- friction.law.mu0 ~ U(0.35, 0.55) (the study brake's μ0 = 0.7 law, lowered to the range of a
  production pad: the critical μ is 0.391 with the compliant contact, README);
- loads.pmax ~ lognormal(0, 0.2) (brake pressure ±20 % around the light stop's line pressure);
- contact.0.normal_stiffness ~ U(5e5, 2e6) psi/in (the inboard interface's compliance around
  base.toml's 1e6).
Three independent inputs: Saltelli's design has d + 2 = 5 rows per base point; the budget of
1 000 gives 6 replicates × 32 base points = 960 CEAs. Each path uses a fresh model cache, so
each builds the reduced model once (its seconds are reported apart).
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
DISTS = {
    "friction.law.mu0": "uniform(0.35, 0.55)",
    "loads.pmax": "lognormal(0, 0.2)",
    "contact.0.normal_stiffness": "uniform(5e5, 2e6)",
}


def summary(report: dict) -> dict:
    s = report["stats"]
    return {
        "wall_s": s["wall_s"],
        "build_s": s["build_s"],
        "evaluations": s["evaluations"],
        "failed": s["failed"],
        "per_evaluation_ms": 1e3 * (s["wall_s"] - s["build_s"]) / max(s["evaluations"], 1),
        "p_unstable": report["p_unstable"]["p"],
        "interval": report["p_unstable"]["interval"],
        "max_real_part_median": dict(map(tuple, report["max_real_part"]["quantiles"]))[0.5]
        if report["max_real_part"] else None,
        "sobol_total_max_real_part": dict(zip(report["sobol_max_real_part"]["keys"],
                                              report["sobol_max_real_part"]["total"]))
        if report["sobol_max_real_part"] else None,
    }


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--squeal", default=str(ROOT / "target" / "release" / "squeal"))
    ap.add_argument("--samples", type=int, default=1000)
    ap.add_argument("--out", default=str(ROOT / "docs" / "bench" / "propensity.json"))
    ap.add_argument("--note", default="machine shared with other builds (2 cores, other helpers compiling)")
    ap.add_argument("--paths", default="cli,threads,dask", help="which of cli, threads, dask to run")
    ap.add_argument("--dask-samples", type=int, default=None, help="budget of the Dask run (default --samples)")
    ap.add_argument("--cli-result", default=None, help="a propensity.json of an earlier CLI run to report instead")
    a = ap.parse_args()
    res: dict = {
        "what": "squeal propensity on the study brake (examples/sample-brake/base.toml), "
                "CEA per evaluation on one reduced model",
        "inputs": DISTS,
        "samples_budget": a.samples,
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(), "note": a.note},
        "cli_binary": a.squeal,
        "python_module_profile": "dev (workspace crates at opt-level 2)",
    }
    paths = a.paths.split(",")
    with tempfile.TemporaryDirectory(prefix="squeal-bench-prop-") as tmp:
        tmp = Path(tmp)
        cli = None
        if a.cli_result:
            cli = json.loads(Path(a.cli_result).read_text())
            res["cli"] = {**summary(cli), "threads": cli["stats"]["threads"], "from_earlier_run": a.cli_result}
        elif "cli" in paths:
            # CLI (rayon over the machine's cores).
            cmd = [a.squeal, "-q", "propensity", str(BASE), "--samples", str(a.samples), "--out", str(tmp / "cli"),
                   "--cache", str(tmp / "cli-cache")]
            for k, d in DISTS.items():
                cmd += ["--dist", f"{k}={d}"]
            t0 = time.perf_counter()
            subprocess.run(cmd, check=True)
            cli = json.loads((tmp / "cli" / "propensity.json").read_text())
            res["cli"] = {**summary(cli), "process_wall_s": time.perf_counter() - t0,
                          "threads": cli["stats"]["threads"]}
        scene = squeal.Scene.from_file(BASE)
        r = r2 = None
        if "threads" in paths:
            # Python, local threads.
            t0 = time.perf_counter()
            r = squeal.propensity(scene, DISTS, a.samples, out=tmp / "py", cache=tmp / "py-cache")
            res["python_threads"] = {**summary(r.report), "call_wall_s": time.perf_counter() - t0}
        if "dask" in paths:
            # Python, Dask LocalCluster with 2 worker processes of one thread each.
            from dask.distributed import Client, LocalCluster

            n = a.dask_samples or a.samples
            with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                              dashboard_address=None) as cluster, Client(cluster) as client:
                t0 = time.perf_counter()
                r2 = squeal.propensity(scene, DISTS, n, client=client, out=tmp / "dask",
                                       cache=tmp / "dask-cache")
                res["python_dask_2_workers"] = {**summary(r2.report), "samples_budget": n,
                                                "call_wall_s": time.perf_counter() - t0}
        if cli is not None and r2 is not None:
            res["ratio_dask_to_cli_per_evaluation"] = (res["python_dask_2_workers"]["per_evaluation_ms"]
                                                       / res["cli"]["per_evaluation_ms"])
        if cli is not None and r is not None:
            res["same_p_unstable_cli_threads"] = cli["p_unstable"]["p"] == r.report["p_unstable"]["p"]
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(res, indent=2) + "\n")
    print(json.dumps(res, indent=2))


if __name__ == "__main__":
    main()
