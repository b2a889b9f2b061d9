"""Design iteration on the study brake: rotor thickness × pad arc angle against the largest
real part of the complex eigenvalues (the squeal indicator), with a plot.

    .venv/bin/python examples/python/design_iteration.py [--out out/design-iteration] [--workers N]

Runs the 3 × 3 grid (thickness 0.5, 0.6, 0.7 in; pads of 3, 4, 5 rotor elements = 33.75°,
45°, 56.25° of arc) as CEA at each design's steady sliding state, on a local Dask cluster with
``--workers N`` processes (default: local threads), each reduced model built once and shared
through the model cache. Writes ``design.csv`` and ``design.png`` into ``--out``.
"""

from __future__ import annotations

import argparse
import itertools
from pathlib import Path

import squeal

ROOT = Path(__file__).resolve().parents[2]
THICKNESS = [0.5, 0.6, 0.7]
ARC_ELEMENTS = [3, 4, 5]  # of the rotor's 32 circumferential elements
N_CIRC = 32


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/design-iteration")
    ap.add_argument("--workers", type=int, default=0, help="Dask worker processes (0: threads)")
    args = ap.parse_args()
    out = Path(args.out).resolve()

    scene = squeal.Scene.from_file(ROOT / "examples" / "sample-brake" / "base.toml")
    # Both pads take the same arc: two keys set together, one grid axis.
    keys = (
        "components.0.geometry.thickness",
        "components.1.geometry.n_elements",
        "components.2.geometry.n_elements",
    )
    grid = [(t, n, n) for t, n in itertools.product(THICKNESS, ARC_ELEMENTS)]
    client = None
    if args.workers:
        from dask.distributed import Client, LocalCluster

        client = Client(LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True))
    df = squeal.sweep(scene, keys, grid, analysis="cea", client=client, out=out,
                      progress=_progress())
    if client is not None:
        client.close()
    df["arc_deg"] = df["components.1.geometry.n_elements"] * 360.0 / N_CIRC
    df["thickness_in"] = df["components.0.geometry.thickness"]
    cols = ["thickness_in", "arc_deg", "cea.max_real_part", "cea.max_real_part_frequency_hz",
            "cea.n_unstable", "cache_hit", "build_s", "analysis_s", "error"]
    df[cols].to_csv(out / "design.csv", index=False)
    print(df[cols].to_string(index=False))
    print(f"models built {df.attrs['n_built']}, read {df.attrs['n_cached']}, "
          f"failed {df.attrs['n_failed']}, {df.attrs['wall_s']:.1f} s")
    _plot(df, out / "design.png")


def _progress():
    try:
        return squeal.TqdmProgress()
    except ImportError:
        return None


def _plot(df, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for arc, g in df.groupby("arc_deg"):
        ax.plot(g["thickness_in"], g["cea.max_real_part"].astype(float), "o-", label=f"pad arc {arc:.2f}°")
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xlabel("rotor thickness (in)")
    ax.set_ylabel("largest Re p (1/s)")
    ax.set_title("study brake: CEA at the steady sliding state, μ = μ0 − 0.0005 V")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"plot: {path}")


if __name__ == "__main__":
    main()
