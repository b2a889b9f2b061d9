"""squeal.compare against `squeal compare` on the same inputs: the tiny brake against itself and
against a copy whose pad is 5 % stiffer (E 5000 -> 5250)."""

from __future__ import annotations

import math

import squeal
from conftest import EXAMPLES, read_json

TINY = EXAMPLES / "transient" / "tiny-brake.toml"


def _stiffer_pad(tmp_path):
    text = TINY.read_text()
    old = "material = { young = 5.0e3, poisson = 0.3, density = 1.0 }"
    assert text.count(old) == 1
    p = tmp_path / "tiny-brake-stiffer-pad.toml"
    p.write_text(text.replace(old, "material = { young = 5.25e3, poisson = 0.3, density = 1.0 }"))
    return p


def _same(a, b):
    if isinstance(a, float) or isinstance(b, float):
        if a is None or b is None:
            return a is b
        return a == b or abs(a - b) <= 1e-12 * max(abs(a), abs(b))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return a == b


def test_model_against_itself_passes_with_zero_differences(tmp_path):
    r = squeal.compare(TINY, TINY, tol_freq=0.0, tol_matrix=0.0, tol_mac=1.0 - 1e-9,
                       cea=False, out=tmp_path)
    assert r.passed and r.exit_code == 0
    assert all(v == 0.0 for v in r.matrices().values())
    assert r.report["modes"] and all(m["mac"] > 1.0 - 1e-9 for m in r.report["modes"])
    assert (tmp_path / "compare.json").is_file() and (tmp_path / "compare.md").is_file()


def test_stiffer_pad_agrees_with_the_cli(cli, tmp_path):
    b = _stiffer_pad(tmp_path)
    args = ("--tol-matrix", "1e-3", "--no-cea")
    d, p = cli("compare", str(TINY), str(b), *args, check=False)
    assert p.returncode == 4, p.stderr
    r = squeal.compare(TINY, b, tol_matrix=1e-3, cea=False)
    assert not r.passed and r.exit_code == p.returncode
    m = r.matrices()
    # Scaling one component's E scales its K alone: the Craig-Bampton basis (fixed-interface
    # eigenvectors, constraint modes -Kii^-1 Kib) is unchanged, so MR moves by round-off only.
    assert m["KR"] > 1e-3 and m["MR"] < 1e-12
    # Only the pad's stiffness changed: no frequency falls, and the stiffest change is 5 %
    # (a mode living in the pad alone scales by sqrt(1.05)).
    for pair in r.report["modes"]:
        if pair["relative_frequency_difference"] is not None and pair["frequency_a_hz"] > 1.0:
            assert -1e-9 <= pair["relative_frequency_difference"] <= math.sqrt(1.05) - 1 + 1e-9
    cli_report = read_json(d / "compare.json")
    for key in ("matrices", "modes", "checks", "passed", "n_dofs"):
        assert _same(r.report[key], cli_report[key]), key


def test_a_negative_or_nan_tolerance_is_an_error_naming_it(cli, tmp_path):
    # The check lives in the library (CompareOptions::validate), so the package and the
    # command line refuse the same values with the same message.
    import pytest

    for kw, flag, value in [("tol_freq", "--tol-freq", -0.1), ("pair_mac", "--pair-mac", math.nan)]:
        with pytest.raises(squeal.SceneError, match=f"compare.{kw}"):
            squeal.compare(TINY, TINY, cea=False, **{kw: value})
        d, p = cli("compare", str(TINY), str(TINY), f"{flag}={value}", check=False)
        assert p.returncode != 0 and f"compare.{kw}" in p.stderr, p.stderr
