"""``squeal.limit_cycle`` agrees with ``squeal limit-cycle``'s ``limit_cycle.json`` on
Hoffmann's model with a separating compliant contact (examples/limit-cycle/hoffmann.toml), and
its cycle is the one the Rust test (pipeline/tests/limit_cycle.rs) checks against the
transient: 0.1591 Hz, peak rotor normal velocity 0.9694, stable."""

from __future__ import annotations

import numpy as np
import pytest

import squeal
from conftest import EXAMPLES, read_json

HOFFMANN = EXAMPLES / "limit-cycle" / "hoffmann.toml"


def test_limit_cycle_agrees_with_cli(cli):
    d, _ = cli("limit-cycle", str(HOFFMANN))
    ref = read_json(d / "limit_cycle.json")
    r = squeal.limit_cycle(squeal.Scene.from_file(HOFFMANN))
    assert isinstance(r, squeal.LimitCycleResult)
    modes = ref["modes"]
    assert len(modes) == 1 and r.reached.tolist() == [m["reached"] for m in modes]
    for key, got in (
        ("frequency_hz", r.frequencies_hz),
        ("peak_normal_velocity", r.peak_normal_velocity),
        ("rms_normal_velocity", r.rms_normal_velocity),
    ):
        np.testing.assert_allclose(got, [m[key] for m in modes], rtol=1e-9)
    assert r.report["band_model"]["kept"] == ref["band_model"]["kept"] == 3
    assert modes[0]["stable"] is True
    # The transient's cycle on the same scene (pipeline/tests/limit_cycle.rs) is at
    # 0.1589 Hz with peak 0.9694: HB within 1 %.
    assert abs(r.frequencies_hz[0] - 0.1589) < 0.01 * 0.1589
    assert abs(r.peak_normal_velocity[0] - 0.9694) < 0.01 * 0.9694


def test_band_keys_are_checked_when_set():
    with pytest.raises(squeal.SceneError, match="transient.band_cutoff"):
        squeal.Scene.from_file(HOFFMANN, set={"transient.band_cutoff": 0.5})
    with pytest.raises(squeal.SceneError, match="limit_cycle"):
        squeal.Scene.from_file(HOFFMANN, set={"limit_cycle.harmonics": 0})
