"""Design iterations: one scene parameter (or a grid of several) swept on local threads or a
Dask distributed cluster, the reduced models shared through a model cache on a folder every
worker sees."""

from __future__ import annotations

import os
import re
import tempfile
import threading
import time
import uuid
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Tuple, Union

from . import _args, _squeal
from ._squeal import Scene, SquealError
from .results import SweepPoint

Value = Union[bool, int, float, str]


def _label(v: Value) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    return str(v)


def _value_dir(index: int, label: str) -> str:
    clean = re.sub(r"[^A-Za-z0-9._-]", "_", label)[:40]
    return f"{index:02d}_{clean}"


def _failed_point(index: int, label: str, run_dir: str, error: str) -> SweepPoint:
    return {
        "index": index, "value": label, "label": label, "run_dir": run_dir,
        "cache_hit": None, "cache_key": None, "build_s": 0.0, "analysis_s": 0.0,
        "cea": None, "transient": None, "error": error, "failed": True,
    }


def _run_point(
    scene: Scene,
    assignments: List[Tuple[str, Value]],
    label: str,
    index: int,
    analysis: str,
    cache: str,
    run_dir: str,
    after: Any = None,
    cancel: Optional[Callable[[], bool]] = None,
    cancel_event: Optional[str] = None,
) -> SweepPoint:
    """One value (a task on a thread or a Dask worker): never raises for a failed value.

    ``cancel()`` (threads) or the ``distributed.Event`` named ``cancel_event`` (Dask) stops it:
    polled before it starts and every 100 ms while it runs (the library then stops inside its
    loops, kills gmsh and stores nothing partial)."""
    if cancel_event is not None:
        from distributed import Event

        cancel = Event(cancel_event).is_set
    if cancel is not None and cancel():
        return _failed_point(index, label, run_dir, "cancelled before it started")
    try:
        return _squeal.sweep_value(
            scene, assignments, label, index, analysis, cache, run_dir, cancel=cancel,
        )
    except SquealError as e:
        return _failed_point(index, label, run_dir, str(e))


def sweep(
    scene: Scene,
    param: Union[str, Sequence[str]],
    values: Sequence[Any],
    analysis: str = "cea",
    *,
    client: Any = None,
    cache: Optional[Union[str, "os.PathLike[str]"]] = None,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    jobs: Optional[int] = None,
    progress: Optional[Callable[[Dict[str, Any]], None]] = None,
) -> Any:
    """Runs ``analysis`` (``"cea"``, ``"transient"`` or ``"both"``) for each value of ``param``.

    ``param`` is a dotted scene key as ``--set`` writes it (``friction.law.mu0``,
    ``components.0.geometry.thickness``), or a tuple of keys with ``values`` a list of tuples
    (a grid, e.g. ``itertools.product(thicknesses, mus)``); the keys of one value are set
    together and the scene validated once (values that must change together, like both pads'
    arc, can be two keys of one axis).

    With ``client`` (a ``dask.distributed.Client``) each value is one task on the cluster;
    without it, values run on ``jobs`` local threads (default: the CPU count). The reduced
    models go through the model cache in ``cache`` (default ``<out>/.squeal-cache``), and
    each value's files into ``<out>/NN_<value>/`` (default ``out``: a new temporary folder):
    on a cluster both must be folders every worker can see. Values that share a reduced model
    (same mesh, FE and reduction inputs) wait for the first of them, so each model is built
    once. A value that fails is recorded with its error (column ``error``) and the others go
    on.

    Returns a pandas DataFrame with one row per value and the columns of ``sweep.json``
    (``index, value, label, run_dir, cache_hit, cache_key, build_s, analysis_s, error``, the
    CEA's ``cea.max_real_part``, ``cea.n_unstable``, … and the transient's ``transient.squeal``,
    ``transient.growth_rate_per_s``, …) plus one column per parameter; ``df.attrs`` holds
    ``n_built``, ``n_cached``, ``n_failed``, ``failed``, ``wall_s``.
    """
    import pandas as pd

    f = "squeal.sweep"
    _args.scene(f, scene)
    if not isinstance(param, str):
        if not isinstance(param, Sequence) or not param or not all(isinstance(k, str) for k in param):
            raise _args.type_error(f, "param", "a dotted scene key (str) or a non-empty tuple of them", param)
    if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
        raise _args.type_error(f, "values", "a sequence of values (or of tuples, one entry per key)", values)
    _args.text(f, "analysis", analysis, ("cea", "transient", "both"))
    cache = _args.path(f, "cache", cache)
    out = _args.path(f, "out", out)
    jobs = _args.integer(f, "jobs", jobs, 1)
    _args.callback(f, "progress", progress)
    if client is not None and not hasattr(client, "submit"):
        raise _args.type_error(f, "client", "a dask.distributed.Client or None", client)

    t0 = time.perf_counter()
    keys = [param] if isinstance(param, str) else list(param)
    rows: List[Tuple[Value, ...]] = []
    for v in values:
        if isinstance(param, str):
            rows.append((v,))
        elif isinstance(v, (str, bytes)) or not isinstance(v, Iterable):
            raise _args.type_error(f, "values", f"tuples of {len(keys)} entries (one per key of `param`)", v)
        else:
            rows.append(tuple(v))
    if not rows:
        raise _squeal.SceneError("--values: no values to sweep")
    for r in rows:
        if len(r) != len(keys):
            raise _squeal.SceneError(f"sweep value {r!r} has {len(r)} entries for {len(keys)} keys")
    out = os.path.abspath(os.fspath(out) if out is not None else tempfile.mkdtemp(prefix="squeal-sweep-"))
    cache = os.path.abspath(os.fspath(cache) if cache is not None else os.path.join(out, ".squeal-cache"))
    os.makedirs(out, exist_ok=True)

    tasks = []
    for i, r in enumerate(rows):
        label = ",".join(_label(v) for v in r)
        assignments = list(zip(keys, r))
        # The model key of the value's scene groups values sharing a reduced model; a value
        # whose scene is invalid has none (its task records the error).
        try:
            s = scene.set_many(dict(assignments))
            mkey = _squeal.model_key(s)
        except SquealError:
            mkey = None
        tasks.append((i, label, assignments, mkey, os.path.join(out, _value_dir(i, label))))

    first: Dict[str, int] = {}
    for i, _l, _a, mkey, _d in tasks:
        if mkey is not None:
            first.setdefault(mkey, i)

    def emit(kind: str, **kw: Any) -> None:
        if progress is not None:
            ev = {"kind": kind, "task": id(tasks), "label": "", "message": "", "fraction": None, "bar": False}
            ev.update(kw)
            progress(ev)

    emit("begin", label=f"sweep ({len(tasks)} values)", bar=True)
    points: Dict[int, SweepPoint] = {}
    if client is not None:
        from distributed import Event, wait

        futures = {}
        stop_name = f"squeal-sweep-cancel-{uuid.uuid4().hex}"
        stop = Event(stop_name, client=client)
        order = sorted(tasks, key=lambda t: t[3] is None or first.get(t[3]) != t[0])
        for i, label, assignments, mkey, rdir in order:
            dep = futures.get(first[mkey]) if mkey is not None and first[mkey] != i else None
            futures[i] = client.submit(
                _run_point, scene, assignments, label, i, analysis, cache, rdir, dep,
                cancel_event=stop_name, pure=False,
            )
        try:
            from dask.distributed import as_completed

            done = 0
            for fut in as_completed(list(futures.values())):
                i = next(k for k, f in futures.items() if f is fut)
                try:
                    points[i] = fut.result()
                except Exception as e:  # a worker died or the task could not run
                    t = tasks[i]
                    points[i] = _failed_point(i, t[1], t[4], f"{type(e).__name__}: {e}")
                done += 1
                emit("update", fraction=done / len(tasks), message=f"{points[i]['label']} done")
        except KeyboardInterrupt:
            # Every task sees the event (before it starts, or within 100 ms while it runs)
            # and ends without storing anything partial; wait for them, so that no worker
            # writes into `out` or `cache` after this returns.
            stop.set()
            wait(list(futures.values()), timeout=30)
            client.cancel(list(futures.values()))
            raise
    else:
        cancel = threading.Event()
        with ThreadPoolExecutor(max_workers=jobs or os.cpu_count() or 1) as pool:
            futs = {}
            order = sorted(tasks, key=lambda t: t[3] is None or first.get(t[3]) != t[0])

            def after_first(i: int, *args: Any) -> SweepPoint:
                mkey = tasks[i][3]
                if mkey is not None and first[mkey] != i:
                    futs[first[mkey]].exception()  # wait for the model's first value
                return _run_point(*args, cancel=cancel.is_set)

            for i, label, assignments, mkey, rdir in order:
                futs[i] = pool.submit(after_first, i, scene, assignments, label, i, analysis, cache, rdir)
            try:
                remaining = set(futs)
                while remaining:
                    for i in sorted(remaining):
                        f = futs[i]
                        try:
                            points[i] = f.result(timeout=0.1)
                        except TimeoutError:
                            continue
                        except Exception as e:
                            t = tasks[i]
                            points[i] = _failed_point(i, t[1], t[4], f"{type(e).__name__}: {e}")
                        remaining.discard(i)
                        emit("update", fraction=len(points) / len(tasks), message=f"{points[i]['label']} done")
            except KeyboardInterrupt:
                # Running values stop within ~0.1 s (the pool's exit waits for them), queued
                # ones never start.
                cancel.set()
                for f in futs.values():
                    f.cancel()
                raise
    emit("end", message=f"{len(tasks)} values")

    ordered = [points[i] for i in range(len(tasks))]
    df = pd.json_normalize(ordered)
    for j, k in enumerate(keys):
        df[k] = [r[j] for r in rows]
    failed = [p["label"] for p in ordered if p.get("failed")]
    df.attrs.update(
        param=keys[0] if isinstance(param, str) else keys,
        analysis=analysis,
        cache_dir=cache,
        out=out,
        n_built=sum(1 for p in ordered if p.get("cache_hit") is False),
        n_cached=sum(1 for p in ordered if p.get("cache_hit") is True),
        n_failed=len(failed),
        failed=failed,
        wall_s=time.perf_counter() - t0,
    )
    return df

