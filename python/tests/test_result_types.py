"""The result dicts have exactly the keys and scalar types of their TypedDicts
(``squeal.results``), which name the Rust structs' fields: a field renamed, added or removed on
the Rust side, or a type changed (an int that becomes a float, an Option that appears), fails
here. Checked recursively into every nested TypedDict, list and Optional; ``Any`` and
``Dict[str, Any]`` parts are not checked.

The models are the other tests' small ones: the tiny brake (transient, CEA with a friction
sweep, compare), the fv52 hex20 plate (modes), Hoffmann's model (limit cycle, propensity).
The conversion's own rules (tuples as lists, non-finite floats as None, the result equal to
the CLI's JSON file) are checked against the files ``squeal compare`` writes."""

from __future__ import annotations

import json
import typing
from typing import Any, Union, get_args, get_origin, get_type_hints

import pytest

import squeal
from squeal import results as R
from conftest import EXAMPLES
from test_propensity import hoffmann

TINY = EXAMPLES / "transient" / "tiny-brake.toml"
FV52 = EXAMPLES / "verification" / "fv52-hex20.toml"
HOFFMANN = EXAMPLES / "limit-cycle" / "hoffmann.toml"

_SCALARS = (bool, int, float, str)


def _is_typeddict(tp: Any) -> bool:
    return isinstance(tp, type) and issubclass(tp, dict) and hasattr(tp, "__required_keys__")


def conforms(value: Any, tp: Any, path: str, seen: set) -> None:
    """Asserts `value` is a `tp` (a TypedDict, List, Dict, Optional/Union, scalar or Any)."""
    if tp is Any:
        return
    if _is_typeddict(tp):
        assert isinstance(value, dict), f"{path}: {type(value).__name__}, not a dict ({tp.__name__})"
        seen.add(tp.__name__)
        hints = get_type_hints(tp)
        required, optional = set(tp.__required_keys__), set(tp.__optional_keys__)
        keys = set(value)
        assert required <= keys, f"{path} ({tp.__name__}): missing keys {sorted(required - keys)}"
        assert keys <= required | optional, (
            f"{path} ({tp.__name__}): keys not in the TypedDict {sorted(keys - required - optional)}"
        )
        for k, v in value.items():
            conforms(v, hints[k], f"{path}.{k}", seen)
        return
    origin, args = get_origin(tp), get_args(tp)
    if origin is Union:
        if value is None:
            assert type(None) in args, f"{path}: None, but {tp} is not Optional"
            return
        alternatives = [a for a in args if a is not type(None)]
        errors = []
        for a in alternatives:
            try:
                conforms(value, a, path, seen)
                return
            except AssertionError as e:
                errors.append(str(e))
        raise AssertionError(f"{path}: {value!r:.80} is none of {alternatives}: {errors}")
    if origin is list:
        assert isinstance(value, list), f"{path}: {type(value).__name__}, not a list"
        for i, x in enumerate(value):
            conforms(x, args[0], f"{path}[{i}]", seen)
        return
    if origin is dict:
        assert isinstance(value, dict), f"{path}: {type(value).__name__}, not a dict"
        for k, x in value.items():
            assert isinstance(k, str), f"{path}: key {k!r} is not a str"
            conforms(x, args[1], f"{path}.{k}", seen)
        return
    assert tp in _SCALARS, f"{path}: unexpected annotation {tp}"
    # Exact types: True is not an int field, 1 is not a float field.
    assert type(value) is tp, f"{path}: {type(value).__name__} {value!r:.60}, not {tp.__name__}"


def check(value: Any, tp: Any) -> set:
    seen: set = set()
    conforms(value, tp, tp.__name__ if _is_typeddict(tp) else str(tp), seen)
    return seen


def hint(cls: type, field: str) -> Any:
    return get_type_hints(cls)[field]


def test_transient_summary_verdict_and_columns():
    t = squeal.transient(squeal.Scene.from_file(TINY))
    seen = check(t.summary, R.TransientSummary)
    # The nested results the summary carries on this model, each checked field by field.
    assert {"TransientStatus", "Verdict", "VerdictRoot", "PencilFit", "Envelope", "Resolution",
            "BdfStats", "BsqlStats", "EnergyBalance", "ContactValidity", "GapEvent", "StepBound",
            "VerdictCea", "RootPair", "Effect", "InputWarning"} <= seen, seen
    check(t.verdict, R.Verdict)
    for c in t.column_info:
        check(c, R.HistoryColumn)
    # The annotations the package declares are these TypedDicts.
    assert hint(squeal.TransientResult, "summary") is R.TransientSummary
    assert hint(squeal.TransientResult, "verdict") is R.Verdict


def test_cea_report_modes_and_sweep(tmp_path):
    c = squeal.cea(squeal.Scene.from_file(TINY), mu=(0.1, 0.9, 5), cache=tmp_path / "cache")
    check(c.cache, R.CacheUse)
    seen = check(c.report, R.CeaReport)
    assert {"CeaMode", "CeaSteadyState", "CeaStateSource", "CeaContact", "CeaOutsideBand",
            "CeaStats"} <= seen, seen
    assert c.report["modes"], "the tiny brake has roots in its band"
    seen = check(c.sweep, R.CeaSweep)
    assert "CeaCoupling" in seen or not c.sweep["couplings"]
    assert hint(squeal.CeaResult, "report") is R.CeaReport
    assert hint(squeal.CeaResult, "sweep") == typing.Optional[R.CeaSweep]
    assert hint(squeal.CeaResult, "cache") == typing.Optional[R.CacheUse]


def test_modes_report():
    m = squeal.modes(squeal.Scene.from_file(FV52))
    seen = check(m.report, R.ModesReport)
    assert {"FeAssemblyStats", "MeshReport"} <= seen
    assert hint(squeal.ModesResult, "report") is R.ModesReport


def test_limit_cycle_report():
    r = squeal.limit_cycle(squeal.Scene.from_file(HOFFMANN))
    seen = check(r.report, R.LimitCycleReport)
    assert "LimitCycleMode" in seen
    assert hint(squeal.LimitCycleResult, "report") is R.LimitCycleReport


def test_propensity_report_and_the_plan_as_dicts(tmp_path):
    r = squeal.propensity(hoffmann(), {"friction.law.mu": "uniform(0.2, 0.5)",
                                       "rotor.rpm": "uniform(9000, 10000)"}, 64, out=tmp_path)
    seen = check(r.report, R.PropensityReport)
    assert {"PropensityInput", "PropensityModel", "Probability", "BandProbability",
            "MaxRealPart", "SobolIndices", "PropensityStats"} <= seen, seen
    assert hint(squeal.PropensityResult, "report") is R.PropensityReport
    # A component property (the optional `component` key of an input) on the tiny brake.
    tiny = squeal.Scene.from_file(TINY).set("cea", {})
    c = squeal.propensity(tiny, {"components.pad.young_scale": "uniform(0.9, 1.1)"}, 16,
                          out=tmp_path / "component")
    assert "ComponentInput" in check(c.report, R.PropensityReport)
    # The report is propensity.json as json.load reads it (the timings are set before the
    # file is written).
    assert r.report == json.loads((tmp_path / "propensity.json").read_text())
    # The plan and a chunk's samples are dicts that pickle (a Dask worker receives them) and
    # come back into Rust as they went out.
    import pickle

    from squeal import _squeal

    plan = _squeal.propensity_plan(hoffmann(), [("friction.law.mu", "uniform(0.2, 0.5)")], [], 16)
    assert isinstance(plan, dict) and pickle.loads(pickle.dumps(plan)) == plan
    ev = _squeal.propensity_evaluate(hoffmann(), pickle.loads(pickle.dumps(plan)),
                                     list(range(len(plan["design"]["rows"]))), str(tmp_path / "w"))
    check(ev, R.PropensityEvaluated)
    out = _squeal.propensity_finish(hoffmann(), plan, ev["samples"], str(tmp_path / "p"))
    check(out, R.PropensityReport)
    # A plan that is not one names the argument (SceneError.field).
    bad = dict(plan)
    del bad["design"]
    with pytest.raises(squeal.SceneError, match="not a propensity plan") as e:
        _squeal.propensity_evaluate(hoffmann(), bad, [0], str(tmp_path / "w"))
    assert e.value.field == "plan"


def test_sweep_point(tmp_path):
    from squeal import _squeal
    from squeal.sweep import _failed_point

    p = _squeal.sweep_value(squeal.Scene.from_file(TINY), [("friction.law.mu0", 0.5)], "0.5", 0,
                            "both", str(tmp_path / "cache"), str(tmp_path / "v0"))
    seen = check(p, R.SweepPoint)
    assert {"SweepCea", "SweepTransient", "VerdictState", "TransientStatus"} <= seen, seen
    assert p["error"] is None and p["value"] == 0.5
    # The point the package records for a value that raised has the same keys.
    check(_failed_point(1, "x", str(tmp_path / "v1"), "an error"), R.SweepPoint)


def test_compare_report_is_its_file_with_infinity_as_none(cli, tmp_path):
    # Two CEA run folders of different models (the tiny brake, its pad 5 % stiffer): their
    # `model_hash` strings differ, a difference with no relative measure, so the summary check's
    # `worst` is +inf in Rust (compare::checks), `null` in compare.json and None in the dict.
    from test_compare import _stiffer_pad

    stiffer = _stiffer_pad(tmp_path)
    a, _ = cli("cea", str(TINY), "--mu", "0.1:0.9:5")
    b, _ = cli("cea", str(stiffer), "--mu", "0.1:0.9:5")
    r = squeal.compare(a, b, tol_summary=1e-3, tol_root=1e-3, out=tmp_path / "cmp")
    seen = check(r.report, R.CompareReport)
    assert {"CompareInput", "CompareRootPair", "SummaryRow", "CompareCheck"} <= seen, seen
    # The two models themselves: matrices and MAC-paired modes.
    models = squeal.compare(TINY, stiffer, tol_matrix=1e-3, cea=False).report
    seen = check(models, R.CompareReport)
    assert {"MatrixDiff", "ModePair"} <= seen, seen
    # Tuples are lists, as in the file: (n_dofs a, n_dofs b), a matrix entry's (row, col).
    assert isinstance(models["n_dofs"], list) and len(models["n_dofs"]) == 2
    assert all(isinstance(m["at"], list) for m in models["matrices"] if m["at"] is not None)
    assert any(m["at"] is not None for m in models["matrices"])
    assert hint(squeal.CompareResult, "report") is R.CompareReport
    on_disk = json.loads((tmp_path / "cmp" / "compare.json").read_text())
    # The dict is the file as json.load reads it, +inf as None.
    assert r.report == on_disk
    summary = {c["tolerance_name"]: c for c in r.report["checks"]}["tol_summary"]
    assert summary["worst"] is None and summary["at"] == "model_hash" and not summary["passed"]
