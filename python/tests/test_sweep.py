"""Sweeps on threads and on a Dask LocalCluster agree with `squeal sweep`; a failed value is
recorded; a grid builds each model once."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import squeal
from conftest import EXAMPLES, read_json

TINY = EXAMPLES / "transient" / "tiny-brake.toml"
MUS = [0.3, 0.6, 0.9]


def test_thread_sweep_agrees_with_cli(cli, tmp_path):
    d, _ = cli("sweep", str(TINY), "--param", "friction.law.mu0", "--values", ",".join(map(str, MUS)),
               "--cache", str(tmp_path / "cli-cache"))
    ref = read_json(d / "sweep.json")
    df = squeal.sweep(squeal.Scene.from_file(TINY), "friction.law.mu0", MUS, out=tmp_path / "py", jobs=2)
    assert list(df["label"]) == [p["label"] for p in ref["points"]]
    assert list(df["friction.law.mu0"]) == MUS
    for k in ("max_real_part", "max_real_part_frequency_hz", "n_unstable"):
        a = np.array(df[f"cea.{k}"], dtype=float)
        b = np.array([p["cea"][k] if p["cea"][k] is not None else np.nan for p in ref["points"]], dtype=float)
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=0, equal_nan=True)
    # One model for the three values of mu.
    assert df.attrs["n_built"] == 1 and df.attrs["n_cached"] == 2 and df.attrs["n_failed"] == 0
    assert set(ref["points"][0]) <= set(c.split(".")[0] for c in df.columns)


def test_failed_value_is_recorded_and_others_go_on(tmp_path):
    df = squeal.sweep(squeal.Scene.from_file(TINY), "friction.law.mu0", [0.5, -1.0e30, "x", 0.7],
                      out=tmp_path, jobs=2)
    assert df.attrs["n_failed"] >= 1
    assert "x" in df.attrs["failed"]
    ok = df[df["label"].isin(["0.5", "0.7"])]
    assert ok["error"].isna().all() and np.isfinite(ok["cea.max_real_part"].astype(float)).all()
    bad = df[df["label"] == "x"].iloc[0]
    assert "friction.law.mu0" in bad["error"]


def test_dask_grid_builds_each_model_once(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    keys = ("components.1.geometry.lz", "friction.law.mu0")
    grid = list(itertools.product([0.2, 0.25], [0.4, 0.8]))
    scene = squeal.Scene.from_file(TINY)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        df = squeal.sweep(scene, keys, grid, client=client, out=tmp_path / "dask", cache=tmp_path / "cache")
    assert df.attrs["n_failed"] == 0, df["error"].tolist()
    assert df.attrs["n_built"] == 2 and df.attrs["n_cached"] == 2
    assert df.groupby("components.1.geometry.lz")["cache_key"].nunique().tolist() == [1, 1]
    # The same values on local threads give the same numbers.
    local = squeal.sweep(scene, keys, grid, out=tmp_path / "local", cache=tmp_path / "cache", jobs=2)
    np.testing.assert_allclose(local["cea.max_real_part"].astype(float), df["cea.max_real_part"].astype(float),
                               rtol=1e-12)
    assert local.attrs["n_cached"] == 4
