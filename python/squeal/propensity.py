"""Squeal propensity under uncertain inputs (``squeal propensity``): a scrambled-Sobol
quasi-Monte Carlo design over scene values, one CEA per sample on one reduced model, the
sample chunks on local threads or a Dask distributed cluster."""

from __future__ import annotations

import os
import tempfile
import time
import uuid
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from . import _args, _squeal
from ._squeal import Scene
from .results import PropensityEvaluated, PropensityReport, SobolIndices


@dataclass
class PropensityResult:
    """What :func:`propensity` found.

    ``report`` is ``propensity.json`` as a dict (``p_unstable`` with its ``interval``, ``bands``,
    ``max_real_part``, ``sobol_max_real_part``, ``sobol_unstable``, ``inputs``, ``stats``);
    ``samples`` a pandas DataFrame with one row per evaluation: ``row, replicate, kind``, one
    column per input key, ``max_real_part``, ``max_real_part_frequency_hz``, ``unstable``,
    ``n_unstable``, ``error``; ``out`` the folder holding ``propensity.json`` and
    ``samples.csv``."""

    report: PropensityReport
    samples: Any
    out: str
    keys: List[str] = field(default_factory=list)

    @property
    def p_unstable(self) -> float:
        return float(self.report["p_unstable"]["p"])

    @property
    def interval(self) -> Tuple[float, float]:
        lo, hi = self.report["p_unstable"]["interval"]
        return float(lo), float(hi)

    def bands(self) -> Any:
        """The per-band probabilities as a DataFrame (``center_hz, lower_hz, upper_hz, p,
        lo, hi``)."""
        import pandas as pd

        rows = [dict(center_hz=b["center_hz"], lower_hz=b["lower_hz"], upper_hz=b["upper_hz"],
                     p=b["p"], lo=b["interval"][0], hi=b["interval"][1]) for b in self.report["bands"]]
        return pd.DataFrame(rows)

    def sobol(self, output: str = "max_real_part") -> Any:
        """Sobol indices of ``"max_real_part"`` or ``"unstable"`` as a DataFrame indexed by key
        (``S1, S1_lo, S1_hi, ST, ST_lo, ST_hi``); None when the study has none."""
        import pandas as pd

        by_output: Dict[str, Optional[SobolIndices]] = {
            "max_real_part": self.report["sobol_max_real_part"],
            "unstable": self.report["sobol_unstable"],
        }
        s = by_output.get(output)
        if s is None:
            return None
        return pd.DataFrame(
            {"S1": s["first_order"], "S1_lo": [i[0] for i in s["first_order_interval"]],
             "S1_hi": [i[1] for i in s["first_order_interval"]], "ST": s["total"],
             "ST_lo": [i[0] for i in s["total_interval"]], "ST_hi": [i[1] for i in s["total_interval"]]},
            index=s["keys"],
        )

    def plot(self, path: Optional[Union[str, "os.PathLike[str]"]] = None) -> Any:
        """Three panels: the histogram of the largest Re p (unstable samples in red), the
        probability per one-third-octave band with its interval, and the Sobol indices of the
        largest Re p. Returns the matplotlib figure (saved to ``path`` when given)."""
        import matplotlib

        if path is not None:
            matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(1, 3, figsize=(15, 4))
        df = self.samples
        ok = df[df["error"].isna() | (df["error"] == "")] if "error" in df else df
        re = ok["max_real_part"].astype(float)
        uns = ok["unstable"].astype(str).str.lower() == "true"
        ax[0].hist([re[~uns], re[uns]], bins=30, stacked=True, color=["tab:blue", "tab:red"],
                   label=["stable", "unstable"])
        ax[0].axvline(0.0, color="k", lw=0.8)
        ax[0].set_xlabel("largest Re p (1/s)")
        ax[0].set_ylabel("samples")
        ax[0].legend()
        lo, hi = self.interval
        ax[0].set_title(f"P(unstable) = {self.p_unstable:.3f} [{lo:.3f}, {hi:.3f}]")
        b = self.bands()
        b = b[(b["hi"] > 0) & (b["p"] >= 0)]
        shown = b[b["p"] > 0] if (b["p"] > 0).any() else b.head(0)
        ax[1].bar(range(len(shown)), shown["p"],
                  yerr=[shown["p"] - shown["lo"], shown["hi"] - shown["p"]], capsize=3)
        ax[1].set_xticks(range(len(shown)))
        ax[1].set_xticklabels([f"{c:.0f}" for c in shown["center_hz"]], rotation=45)
        ax[1].set_xlabel("one-third-octave band (Hz)")
        ax[1].set_ylabel("P(unstable root in band)")
        s = self.sobol()
        if s is not None:
            x = range(len(s))
            ax[2].bar([i - 0.2 for i in x], s["S1"], width=0.4, label="S1",
                      yerr=[s["S1"] - s["S1_lo"], s["S1_hi"] - s["S1"]], capsize=3)
            ax[2].bar([i + 0.2 for i in x], s["ST"], width=0.4, label="ST",
                      yerr=[s["ST"] - s["ST_lo"], s["ST_hi"] - s["ST"]], capsize=3)
            ax[2].set_xticks(list(x))
            ax[2].set_xticklabels(list(s.index), rotation=20, fontsize=8)
            ax[2].legend()
        ax[2].set_title("Sobol indices of the largest Re p")
        fig.tight_layout()
        if path is not None:
            fig.savefig(os.fspath(path))
        return fig


def _evaluate(scene: Scene, plan: Dict[str, Any], rows: List[int], workdir: str, cache: Optional[str],
              cancel_event: Optional[str] = None) -> PropensityEvaluated:
    """One chunk of design rows (a task on a thread or a Dask worker; ``plan`` is the dict
    ``propensity_plan`` returns, pickled to the worker)."""
    cancel = None
    if cancel_event is not None:
        from distributed import Event

        cancel = Event(cancel_event).is_set
    return _squeal.propensity_evaluate(scene, plan, rows, workdir, cache, cancel=cancel)


def _dist_list(f: str, distributions: Any) -> List[Tuple[str, str]]:
    if isinstance(distributions, Mapping):
        items = list(distributions.items())
    elif isinstance(distributions, Sequence) and not isinstance(distributions, (str, bytes)):
        items = []
        for d in distributions:
            if isinstance(d, str) and "=" in d:
                k, v = d.split("=", 1)
                items.append((k.strip(), v.strip()))
            elif isinstance(d, (tuple, list)) and len(d) == 2:
                items.append((d[0], d[1]))
            else:
                raise _args.type_error(f, "distributions", "a dict {key: 'uniform(a, b)'} or 'KEY=DIST' strings", d)
    else:
        raise _args.type_error(f, "distributions", "a dict {key: 'uniform(a, b)'} or 'KEY=DIST' strings",
                               distributions)
    for k, v in items:
        if not isinstance(k, str) or not isinstance(v, str):
            raise _args.type_error(f, "distributions", "str keys and str distributions ('uniform(0.3, 0.5)')",
                                   (k, v))
    return items


def propensity(
    scene: Scene,
    distributions: Union[Mapping[str, str], Sequence[str]],
    n: int = 1000,
    *,
    correlation: Optional[Mapping[Tuple[str, str], float]] = None,
    replicates: Optional[int] = None,
    seed: int = 1,
    rereduce: bool = False,
    basis_tolerance: float = 0.05,
    client: Any = None,
    chunks: Optional[int] = None,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    cache: Optional[Union[str, "os.PathLike[str]"]] = None,
    progress: Optional[Callable[[Dict[str, Any]], None]] = None,
) -> PropensityResult:
    """The probability that the brake squeals (an unstable CEA root) when scene values vary.

    ``distributions`` maps dotted scene keys (as ``--set`` writes them) to
    ``"uniform(a, b)"``, ``"normal(mean, sd)"``, ``"lognormal(mu, sigma)"`` or
    ``"truncnormal(mean, sd, lo, hi)"``; ``correlation`` maps key pairs to the correlation of
    their normal scores (a Gaussian copula). ``n`` is the budget of CEA evaluations: a
    randomised QMC design (Saltelli's A, B, A_B^(i) on Owen-scrambled Sobol points in
    ``replicates`` independent scramblings) uses up to ``n`` of them. The reduced model is
    built once (an input that changes it is refused unless ``rereduce``); a component's
    moduli or densities vary on it through the reduced-matrix derivative, and one volume's
    material (``components.1.materials.lining.young``) is first checked against re-reduction
    at its 0.5 % and 99.5 % quantiles: a change of the largest Re λ above
    ``basis_tolerance`` × |Re λ| (at least 1 /s) raises, naming the key.

    With ``client`` (a ``dask.distributed.Client``) the design rows go to the cluster in
    ``chunks`` tasks (default: twice the workers' thread count); without it, the rows run on
    this process's threads. ``out`` (default: a new temporary folder) receives
    ``propensity.json``, ``samples.csv`` and ``summary.json``, as ``squeal propensity`` writes
    them; the model goes through the model cache ``cache`` (default ``<out>/.squeal-cache``),
    which on a cluster must be a folder every worker sees.
    """
    import pandas as pd

    f = "squeal.propensity"
    _args.scene(f, scene)
    items = _dist_list(f, distributions)
    n = _args.integer(f, "n", n, 1)
    replicates = _args.integer(f, "replicates", replicates, 2)
    chunks = _args.integer(f, "chunks", chunks, 1)
    cache = _args.path(f, "cache", cache)
    out = _args.path(f, "out", out)
    _args.callback(f, "progress", progress)
    if client is not None and not hasattr(client, "submit"):
        raise _args.type_error(f, "client", "a dask.distributed.Client or None", client)
    corr: List[Tuple[str, str, float]] = []
    if correlation is not None:
        if not isinstance(correlation, Mapping):
            raise _args.type_error(f, "correlation", "a dict {(key_a, key_b): rho}", correlation)
        for pair, rho in correlation.items():
            if not (isinstance(pair, tuple) and len(pair) == 2 and all(isinstance(k, str) for k in pair)):
                raise _args.type_error(f, "correlation", "keys that are (key_a, key_b) tuples", pair)
            corr.append((pair[0], pair[1], float(rho)))

    t0 = time.perf_counter()
    plan = _squeal.propensity_plan(scene, items, corr, n, replicates, seed, rereduce)
    rows_total = len(plan["design"]["rows"])
    out = os.path.abspath(os.fspath(out) if out is not None else tempfile.mkdtemp(prefix="squeal-propensity-"))
    cache = os.path.abspath(os.fspath(cache) if cache is not None else os.path.join(out, ".squeal-cache"))
    os.makedirs(out, exist_ok=True)
    work = os.path.join(out, "work")
    basis_tolerance = float(basis_tolerance)
    # Once, before the rows are distributed (no-op without a volume input).
    basis_checks = _squeal.propensity_check_basis(scene, plan, os.path.join(out, "basis-check"),
                                                  basis_tolerance, cache)

    def emit(kind: str, **kw: Any) -> None:
        if progress is not None:
            ev = {"kind": kind, "task": id(plan), "label": "", "message": "", "fraction": None, "bar": False}
            ev.update(kw)
            progress(ev)

    results: List[PropensityEvaluated] = []
    emit("begin", label=f"propensity ({rows_total} CEAs)", bar=True)
    if client is not None:
        from distributed import Event, wait
        from dask.distributed import as_completed

        if chunks is None:
            threads = sum(client.nthreads().values()) or 1
            chunks = 2 * threads
        parts = [list(range(rows_total))[i::chunks] for i in range(min(chunks, rows_total))]
        stop_name = f"squeal-propensity-cancel-{uuid.uuid4().hex}"
        stop = Event(stop_name, client=client)
        # A work folder per chunk: chunks that build the model (a volume input needs its
        # component blocks) write the same mesh files, and two workers writing one folder tore
        # the rotor's .msh under the other's reader.
        futures = [client.submit(_evaluate, scene, plan, p, os.path.join(work, f"chunk-{k:03d}"), cache,
                                 cancel_event=stop_name, pure=False)
                   for k, p in enumerate(parts)]
        try:
            done = 0
            for fut in as_completed(futures):
                results.append(fut.result())
                done += 1
                emit("update", fraction=done / len(futures), message=f"chunk {done}/{len(futures)}")
        except KeyboardInterrupt:
            stop.set()
            wait(futures, timeout=30)
            client.cancel(futures)
            raise
        nthreads = sum(client.nthreads().values())
    else:
        # One task: the library spreads the rows over this process's threads (rayon).
        results.append(_squeal.propensity_evaluate(scene, plan, list(range(rows_total)), work, cache))
        nthreads = os.cpu_count() or 1
    emit("end", message=f"{rows_total} CEAs")
    samples = [s for r in results for s in r["samples"]]
    build_s = max((r["build_s"] for r in results), default=0.0)
    evaluate_s = time.perf_counter() - t0 - build_s
    n_dofs, n_gaps = (results[0]["n_dofs"], results[0]["n_gaps"]) if results else (0, 0)
    report = _squeal.propensity_finish(
        scene, plan, samples, out, n_dofs, n_gaps,
        build_s, evaluate_s, time.perf_counter() - t0, nthreads, basis_checks,
    )
    keys = [i["key"] for i in report["inputs"]]
    df = pd.read_csv(os.path.join(out, "samples.csv"), keep_default_na=True)
    df["unstable"] = df["unstable"].map({True: True, False: False, "true": True, "false": False})
    return PropensityResult(report=report, samples=df, out=out, keys=keys)
