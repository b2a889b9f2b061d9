"""Nothing wrong passes silently, and Ctrl-C means stop (issue 26).

- Argument errors name the function and the argument (``TypeError`` for a type,
  ``ValueError`` for a value); a complex stiffness and an empty model are refused.
- SIGINT during a model build, a CEA friction sweep, a transient and a Dask sweep raises
  ``KeyboardInterrupt`` soon after the signal (a generous bound: a behaviour test on a
  loaded machine, not a benchmark) and leaves no cache entry of the interrupted model, no
  temporary file and no result file.
- Two tasks of one model on a Dask LocalCluster sharing a cache folder build it once (the
  entry's lock: one waits and reads what the other stored).
"""

from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import squeal
from squeal import _squeal
from conftest import EXAMPLES

TINY = EXAMPLES / "transient" / "tiny-brake.toml"
BIG_ROTOR = {
    "components.0.geometry.nx": 16,
    "components.0.geometry.ny": 16,
    "components.0.geometry.nz": 3,
    "components.0.element": "hex20",
}
STOP_BOUND_S = 15.0


def _scene() -> squeal.Scene:
    return squeal.Scene.from_file(TINY)


# ------------------------------------------------------------------ argument errors


@pytest.mark.parametrize(
    "call, kind, words",
    [
        (lambda s: s.set(123, 1), TypeError, ["Scene.set", "`key`", "int 123"]),
        (lambda s: s.set_many({1: 2}), TypeError, ["Scene.set_many", "`values`", "key int 1"]),
        (lambda s: s.set_many([("a", 1)]), TypeError, ["Scene.set_many", "`values`", "list"]),
        (lambda s: squeal.Scene.from_file(5), TypeError, ["Scene.from_file", "`path`"]),
        (lambda s: squeal.Scene.from_dict([1]), TypeError, ["Scene.from_dict", "`data`"]),
        (lambda s: squeal.Scene.from_toml("", set=[1]), TypeError, ["Scene.from_toml", "`set`"]),
        (lambda s: squeal.cea(s, mu=(0.1, 0.9, -3)), ValueError, ["squeal.cea", "mu[2] (count)", "-3"]),
        (lambda s: squeal.cea(s, mu=(0.1, 0.9)), TypeError, ["squeal.cea", "`mu`"]),
        (lambda s: squeal.cea(s, progress=5), TypeError, ["squeal.cea", "`progress`", "int 5"]),
        (lambda s: squeal.transient(s, cache=3.5), TypeError, ["squeal.transient", "`cache`"]),
        (lambda s: squeal.reduce("scene.toml"), TypeError, ["squeal.reduce", "`scene`"]),
        (lambda s: squeal.compare("a", "b", modes=-1), ValueError, ["squeal.compare", "`modes`", "-1"]),
        (lambda s: squeal.compare("a", "b", tol_mac="x"), TypeError, ["squeal.compare", "`tol_mac`"]),
        (lambda s: squeal.compare("a", "b", cea=1), TypeError, ["squeal.compare", "`cea`"]),
        (lambda s: squeal.sweep(s, 5, [1]), TypeError, ["squeal.sweep", "`param`"]),
        (lambda s: squeal.sweep(s, "friction.law.mu0", 0.5), TypeError, ["squeal.sweep", "`values`"]),
        (lambda s: squeal.sweep(s, "friction.law.mu0", [0.5], analysis="both!"), ValueError,
         ["squeal.sweep", "`analysis`"]),
        (lambda s: squeal.sweep(s, "friction.law.mu0", [0.5], jobs=0), ValueError, ["squeal.sweep", "`jobs`"]),
    ],
)
def test_argument_errors_name_the_argument(call, kind, words):
    with pytest.raises(kind) as e:
        call(_scene())
    for w in words:
        assert w in str(e.value), str(e.value)


def test_compare_tolerances_are_checked_as_the_cli_checks_them(tmp_path):
    for kw, named in [({"tol_mac": 1.5}, "compare.tol_mac"),
                      ({"pair_mac": 0.95, "tol_mac": 0.9}, "compare.pair_mac"),
                      ({"modes": 0, "tol_freq": 1e-9}, "compare.modes")]:
        with pytest.raises(squeal.SceneError) as e:
            squeal.compare(TINY, TINY, out=tmp_path / "c", **kw)
        assert named in str(e.value)


def _arrays():
    r = squeal.reduce(_scene())
    return r


def test_complex_stiffness_and_empty_model_are_refused():
    r = _arrays()
    K = r.K.astype(complex) * (1 + 0.02j)  # a structural damping K(1 + i eta), eta = 0.02
    with pytest.raises(squeal.InputError) as e:
        squeal.Scene.from_arrays(K, r.M, r.dofs, gaps=r.gaps, p_brake=r.p_brake)
    msg = str(e.value)
    assert "<arrays>.K" in msg and "complex" in msg and "2.000e-2" in msg, msg
    # A complex dtype whose imaginary parts are all zero is real: accepted, same scene.
    a = squeal.Scene.from_arrays(r.K.astype(complex), r.M, r.dofs, gaps=r.gaps, p_brake=r.p_brake)
    b = squeal.Scene.from_arrays(r.K, r.M, r.dofs, gaps=r.gaps, p_brake=r.p_brake)
    np.testing.assert_array_equal(squeal.reduce(a).K, squeal.reduce(b).K)
    empty = squeal.Scene.from_arrays(np.zeros((0, 0)), np.zeros((0, 0)), [], toml="[cea]\n")
    with pytest.raises(squeal.InputError) as e:
        squeal.cea(empty)
    assert "no DOF" in str(e.value)


# ------------------------------------------------------------------ Ctrl-C


def _interrupt_after(seconds: float) -> dict:
    """SIGINT to this process after `seconds`; the returned dict gets the time it was sent."""
    sent = {}

    def fire():
        sent["t"] = time.perf_counter()
        os.kill(os.getpid(), signal.SIGINT)

    threading.Timer(seconds, fire).start()
    return sent


def _no_partial_files(*dirs: Path) -> None:
    for d in dirs:
        for p in Path(d).rglob("*"):
            name = p.name
            assert not (name.endswith(".tmp") or name.startswith(".tmp-") or name.startswith(".trash-")), p


def test_ctrl_c_stops_a_model_build(tmp_path):
    scene = _scene().set_many(BIG_ROTOR)
    # At 1 s: on an idle machine the whole build and its cache entry were done before 2.5 s.
    sent = _interrupt_after(1.0)
    with pytest.raises(KeyboardInterrupt):
        squeal.reduce(scene, cache=tmp_path / "cache", workdir=tmp_path / "work")
    took = time.perf_counter() - sent["t"]
    assert took < STOP_BOUND_S, took
    _no_partial_files(tmp_path)
    # No model entry (complete component entries may stay): lock files only at the top.
    for p in (tmp_path / "cache").iterdir():
        assert p.name.startswith(".lock-") or p.name == "components", p


def test_ctrl_c_stops_a_cea_sweep_and_a_transient(tmp_path):
    cache = tmp_path / "cache"
    scene = _scene().set("cea", {})
    squeal.cea(scene, cache=cache)  # the model in the cache: the next runs start computing
    sent = _interrupt_after(2.0)
    with pytest.raises(KeyboardInterrupt):
        squeal.cea(scene, mu=(0.1, 0.9, 600), cache=cache)
    assert time.perf_counter() - sent["t"] < STOP_BOUND_S
    sent = _interrupt_after(2.0)
    with pytest.raises(KeyboardInterrupt):
        squeal.transient(scene.set("transient.tfinal", 1000.0), cache=cache)
    assert time.perf_counter() - sent["t"] < STOP_BOUND_S
    _no_partial_files(tmp_path)


def test_ctrl_c_stops_a_dask_sweep_and_a_shared_cache_builds_once(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    scene = _scene().set_many(BIG_ROTOR)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        # Two tasks of one model at once on one cache folder: one builds, one waits and reads.
        cache = tmp_path / "shared"
        futs = [client.submit(_squeal.sweep_value, _scene(), [("friction.law.mu0", mu)], str(mu), i, "cea",
                              str(cache), str(tmp_path / f"v{i}"), pure=False)
                for i, mu in enumerate([0.4, 0.8])]
        # The point comes back from the worker as a dict (no JSON text crosses the binding).
        points = [f.result() for f in futs]
        assert [p["error"] for p in points] == [None, None]
        assert sorted(p["cache_hit"] for p in points) == [False, True], points
        assert len({p["cache_key"] for p in points}) == 1
        assert sum(1 for p in cache.iterdir() if (p / "entry.json").is_file()) == 1

        # Ctrl-C during a sweep of forty big-rotor models: every task stops, nothing is stored.
        # (Four models took 4.3 s on an idle machine, so a SIGINT at 4 s could come after the
        # sweep's end; forty take over 20 s, and the SIGINT comes at 2 s.)
        values = [0.2 + 0.005 * i for i in range(40)]
        out, cache = tmp_path / "sweep", tmp_path / "cache"
        sent = _interrupt_after(2.0)
        with pytest.raises(KeyboardInterrupt):
            squeal.sweep(scene, "components.0.geometry.lz", values, client=client, out=out, cache=cache)
        took = time.perf_counter() - sent["t"]
    assert took < STOP_BOUND_S, took
    _no_partial_files(tmp_path)
    assert not list(out.rglob("summary.json")), list(out.rglob("summary.json"))
    if cache.exists():
        for p in cache.iterdir():
            assert p.name.startswith(".lock-") or p.name == "components", p
