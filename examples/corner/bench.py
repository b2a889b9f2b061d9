"""The corner's benchmark: mesh → Craig–Bampton → contact → CEA and a μ sweep on a cold cache,
timed with its peak memory, written as docs/bench/corner.json.

    cargo build --release -p squeal-cli
    python examples/corner/bench.py [--mu 0.2:0.6:21] [--out out/corner-bench]

Or from a run already made the same way (the CLI's folder, its cache, and the output of
`/usr/bin/time -v` around it):

    python examples/corner/bench.py --use RUN_DIR CACHE_DIR TIME_LOG
"""
import argparse
import collections
import datetime
import glob
import json
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def time_v(log):
    text = open(log).read()
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", text).group(1)
    parts = [float(x) for x in wall.split(":")]
    secs = sum(p * 60 ** i for i, p in enumerate(reversed(parts)))
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1))
    user = float(re.search(r"User time \(seconds\): (\S+)", text).group(1))
    system = float(re.search(r"System time \(seconds\): (\S+)", text).group(1))
    build = re.search(r"built and stored in (\S+) s", text)
    return {"wall_s": secs, "cpu_s": user + system, "peak_rss_gb": rss / 1024 ** 2,
            "model_build_s": float(build.group(1)) if build else None}


def extract(run, cache, log):
    d = json.load(open(os.path.join(run, "cea.json")))
    dofmap = json.load(open(glob.glob(os.path.join(cache, "*", "dofmap.json"))[0]))
    sizes = collections.OrderedDict()
    for x in dofmap["dofs"]:
        sizes.setdefault(x["component"], collections.Counter())[x["kind"]] += 1
    import meshio  # the project's .venv
    mesh = {}
    for f in sorted(glob.glob(os.path.join(run, "mesh", "*.msh"))):
        m = meshio.read(f)
        mesh[os.path.basename(f)[:-4]] = {"nodes": len(m.points),
                                          "tet10": sum(len(c.data) for c in m.cells if c.type == "tetra10")}
    s = d["stats"]
    e = d["energy"]
    roots = []
    unstable = set(d["unstable"])  # the CEA's: Re p above its threshold, in band
    for r in e["roots"]:
        if r["mode"] in unstable:
            roots.append({
                "frequency_hz": r["frequency_hz"],
                "real_part_per_s": r["real_part"],
                "kinetic_energy_share": {n: 2 * x for n, x in zip(e["components"], r["kinetic_share"])
                                         if 2 * x > 1e-3},
                "feed_in_per_pair": dict(zip([p["name"] for p in e["pairs"]], r["feed_in_per_pair"])),
            })
    out = {
        "what": "examples/corner/corner.toml: mesh -> Craig-Bampton -> contact -> CEA and mu sweep, cold cache",
        "date": datetime.date.today().isoformat(),
        "machine": "2 cores, 24 GiB (the project's CI machine class)",
        "process": time_v(log),
        "meshes": mesh,
        "full_dofs": 3 * sum(v["nodes"] for v in mesh.values()),
        "reduced_dofs": sum(sum(c.values()) for c in sizes.values()),
        "reduced_dofs_per_component": {k: dict(v) for k, v in sizes.items()},
        "gaps_per_pair": d["steady_state"]["contact"].get("per_pair"),
        "cea": {k: s[k] for k in s if k.startswith("time") or k in
                ("n", "n_constraints", "method", "n_basis", "n_modes", "n_unstable")},
        "unstable_in_band": roots,
    }
    sweep = os.path.join(run, "cea.sweep.json")
    if os.path.exists(sweep):
        sw = json.load(open(sweep))
        out["sweep"] = {k: sw[k] for k in sw if k in (
            "mu", "lowest_critical_mu_in_band", "lowest_critical_mu_in_band_status", "stats")}
        out["sweep"]["onsets"] = [
            {"frequency_hz": t["critical"]["frequency_hz"], "mu": t["critical"]["mu"],
             "mu_projected": t["critical"]["mu_located"],
             "exact": None if t["critical"].get("exact") is None else {
                 k: t["critical"]["exact"][k] for k in ("converged", "mu", "n_solves", "time_s")}}
            for t in sw["tracks"] if t.get("critical")]
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mu", default="0.2:0.6:21")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "corner-bench"))
    ap.add_argument("--use", nargs=3, metavar=("RUN", "CACHE", "TIME_LOG"))
    ap.add_argument("--json", default=os.path.join(ROOT, "docs", "bench", "corner.json"))
    a = ap.parse_args()
    if a.use:
        run, cache, log = a.use
    else:
        run, cache = os.path.join(a.out, "run"), os.path.join(a.out, "cache")
        log = os.path.join(a.out, "time.log")
        shutil.rmtree(a.out, ignore_errors=True)
        os.makedirs(a.out)
        squeal = os.path.join(ROOT, "target", "release", "squeal")
        cmd = ["/usr/bin/time", "-v", squeal, "cea", os.path.join(HERE, "corner.toml"), "--out", run,
               "--cache", cache, "--mu", a.mu]
        with open(log, "w") as f:
            if subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT) != 0:
                sys.exit(f"the run failed: {log}")
    out = extract(run, cache, log)
    with open(a.json, "w") as f:
        json.dump(out, f, indent=1)
    print(f"wrote {a.json}")


if __name__ == "__main__":
    main()
