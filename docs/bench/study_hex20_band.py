"""Collects the band-limited, unilateral hex20 study's per-case figures into
docs/bench/study_hex20_band.json from the run folders of

    squeal reproduce examples/sample-brake/study-hex20.toml --out OUT --jobs 1 \
      --set transient.band_limited=true --set contact.0.separation=true \
      --set contact.1.separation=true --set 'output.verdict_cea="always"'

Usage: python docs/bench/study_hex20_band.py LABEL=OUT [LABEL=OUT ...] (e.g. paper_tf=OUT and
long_40ms=OUT2 for examples/sample-brake/study-hex20-long.toml)
"""
import json
import os
import sys

cases = []
for arg in sys.argv[1:]:
    label, out = arg.split("=", 1)
    for name in sorted(os.listdir(out)):
        f = os.path.join(out, name, "summary.json")
        if not name.startswith("case") or not os.path.exists(f):
            continue
        s = json.load(open(f))
        v = s["verdict"]
        cases.append({
            "study": label,
            "case": int(name[4:]),
            "status": s["status"],
            "steps": s["steps"],
            "integrator_cpu_s": s["cpu_s"],
            "us_per_step": 1e6 * s["cpu_s"] / max(s["steps"], 1),
            "verdict": v["state"],
            "reasons": [r["reason"] for r in v.get("reasons", [])],
            "evidence": v.get("evidence"),
            "growth_rate_per_s": v.get("growth_rate_per_s"),
            "dominant_frequency_hz": v.get("dominant_frequency_hz"),
            "min_pressure": s["contact"]["min_pressure"],
            "bdf": {k: s["bdf_stats"].get(k) for k in (
                "convergence_failures", "setups_branch", "jacobian_setups", "order_histogram")},
            "verdict_cea_unstable_in_band": (s.get("verdict_cea") or {}).get("unstable_in_band"),
            "band_limited": {k: s["band_limited"][k] for k in (
                "kept", "removed", "removed_unstable", "error_estimate")},
        })
json.dump({"what": "hex20 study, band-limited model, both pairs unilateral (docs/study-hex20.md)",
           "cases": cases}, open("docs/bench/study_hex20_band.json", "w"), indent=2)
print(len(cases), "cases")
