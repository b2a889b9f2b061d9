"""Every compute function agrees with the CLI's files on the same scene to 1e-12."""

from __future__ import annotations

import numpy as np
import pytest

import squeal
from conftest import EXAMPLES, read_json

TINY = EXAMPLES / "transient" / "tiny-brake.toml"
FV52 = EXAMPLES / "verification" / "fv52-hex20.toml"
RTOL = 1e-12


def close(a, b, rtol=RTOL):
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, (a.shape, b.shape)
    scale = max(np.max(np.abs(b)), 1e-300) if b.size else 1.0
    err = np.max(np.abs(a - b)) / scale if b.size else 0.0
    assert err <= rtol, f"relative difference {err:.3e} > {rtol}"


def test_modes_agree_with_cli(cli):
    d, _ = cli("modes", str(FV52))
    ref = read_json(d / "modes.json")
    m = squeal.modes(squeal.Scene.from_file(FV52))
    close(m.frequencies_hz, ref["frequencies_hz"])
    assert m.shapes.shape == (m.nodes.shape[0], 3, len(ref["frequencies_hz"]))
    import meshio

    vtu = meshio.read(d / "modes.vtu")
    close(m.nodes, vtu.points)
    names = sorted(k for k in vtu.point_data if k.startswith("mode_"))
    for j, name in enumerate(names):
        close(m.shapes[:, :, j], vtu.point_data[name])
    # Cells as meshio takes them, matching the CLI's VTU.
    assert [c[0] for c in m.cells] == [c.type for c in vtu.cells]
    np.testing.assert_array_equal(m.cells[0][1], vtu.cells[0].data)


def test_reduce_agrees_with_cli(cli):
    d, _ = cli("reduce", str(TINY))
    r = squeal.reduce(squeal.Scene.from_file(TINY))
    from pyNastran.op4.op4 import read_op4

    mats = read_op4(str(d / "reduced.op4"))
    close(r.K, mats["KR"].data)
    close(r.M, mats["MR"].data)
    close(r.p_brake, np.ravel(mats["PBRAKE"].data))
    assert (r.B is None) == ("BR" not in mats)
    dm = read_json(d / "dofmap.json")["dofs"]
    assert len(dm) == len(r.dofs) == r.K.shape[0]
    for a, b in zip(r.dofs, dm):
        assert a["component"] == b["component"] and a["kind"] == b["kind"]
        assert (a["grid"], a["comp"], a["index"]) == (b.get("grid"), b.get("comp"), b.get("index"))
    gj = read_json(d / "gaps.json")["gaps"]
    assert len(gj) == len(r.gaps) > 0
    close([[g["x"], g["y"], g["z"]] for g in r.gaps], [g["coords"] for g in gj])
    close([[g["nx"], g["ny"], g["nz"]] for g in r.gaps], [g["normal"] for g in gj])
    close([g["area"] for g in r.gaps], [g["area"] for g in gj])
    close([g["p0"] for g in r.gaps], [g["p0"] for g in gj])
    assert [g["pad_grid"] for g in r.gaps] == [g["pad_node"] for g in gj]


def test_transient_agrees_with_cli(cli):
    d, _ = cli("transient", str(TINY))
    t = squeal.transient(squeal.Scene.from_file(TINY))
    hist = np.load(d / "history.npy")
    hmap = read_json(d / "history_map.json")
    assert t.columns == [c["name"] for c in hmap["columns"]]
    close(t.history, hist)
    close(t.time, hist[:, 0])
    s = read_json(d / "summary.json")
    assert t.success and t.summary["steps"] == s["steps"]
    assert t.summary["squeal"] == s["squeal"]
    for k in ("growth_rate_per_s", "dominant_frequency_hz", "energy_residual", "t_end"):
        if s[k] is None:
            assert t.summary[k] is None
        else:
            close(t.summary[k], s[k])
    assert t.verdict["state"] == s["verdict"]["state"]
    import pandas as pd

    assert isinstance(t.to_dataframe(), pd.DataFrame)


def test_cea_agrees_with_cli(cli):
    d, _ = cli("cea", str(TINY), "--mu", "0.1:0.9:5")
    c = squeal.cea(squeal.Scene.from_file(TINY), mu=(0.1, 0.9, 5))
    ref = read_json(d / "cea.json")
    close(c.frequencies_hz, [m["frequency_hz"] for m in ref["modes"]])
    close(c.real_parts, [m["real_part"] for m in ref["modes"]])
    close(
        np.nan_to_num(c.damping_ratios),
        [m["damping_ratio"] if m["damping_ratio"] is not None else 0.0 for m in ref["modes"]],
    )
    assert list(np.flatnonzero(c.unstable)) == sorted(ref["unstable"])
    assert c.shapes.shape == (len(c.dofs), len(ref["modes"]))
    # Unit 2-norm shapes, as the solver returns them.
    close(np.linalg.norm(c.shapes, axis=0), np.ones(len(ref["modes"])))
    sw = read_json(d / "cea.sweep.json")
    assert c.sweep is not None
    assert c.sweep["lowest_critical_mu"] == pytest.approx(sw["lowest_critical_mu"], rel=RTOL) if sw["lowest_critical_mu"] is not None else c.sweep["lowest_critical_mu"] is None
    assert len(c.sweep["tracks"]) == len(sw["tracks"])


def test_arrays_scene_agrees_with_the_meshed_scene():
    """A stored-matrix scene built from numpy arrays in memory (no files) gives the meshed
    scene's CEA and transient."""
    scene = squeal.Scene.from_file(TINY).set("cea", {})
    r = squeal.reduce(scene)
    rest = scene.to_dict()
    for k in ("components", "contact", "reduction", "model"):
        rest.pop(k, None)
    rest["loads"] = {k: v for k, v in rest["loads"].items() if k not in ("pressure", "force")}
    rest.setdefault("model", {})["band_hz"] = scene.to_dict()["reduction"]["frequency_of_interest_hz"]
    arr = squeal.Scene.from_arrays(
        r.K, r.M, r.dofs, gaps=r.gaps, B=r.B, p_brake=r.p_brake, toml=rest
    )
    assert arr.model_source == "arrays"
    a, b = squeal.cea(scene), squeal.cea(arr)
    close(b.eigenvalues, a.eigenvalues)
    # A DataFrame of the records is accepted too, and the scene pickles with its arrays.
    import pickle

    import pandas as pd

    arr2 = squeal.Scene.from_arrays(r.K, r.M, pd.DataFrame(r.dofs), gaps=pd.DataFrame(r.gaps), B=r.B,
                                    p_brake=r.p_brake, toml=rest)
    arr3 = pickle.loads(pickle.dumps(arr2))
    close(squeal.cea(arr3).eigenvalues, a.eigenvalues)
    ta, tb = squeal.transient(scene), squeal.transient(arr)
    close(tb.history, ta.history)


def test_bad_arrays_name_the_array():
    scene = squeal.Scene.from_file(TINY).set("cea", {})
    r = squeal.reduce(scene)
    M = r.M.copy()
    M[0, 1] += 1e-3 * np.abs(M).max()
    with pytest.raises(squeal.InputError, match=r"<arrays>\.M"):
        squeal.cea(squeal.Scene.from_arrays(r.K, M, r.dofs, gaps=r.gaps, toml="[cea]"))
    gaps = [dict(g) for g in r.gaps]
    gaps[1]["area"] = -0.5
    with pytest.raises(squeal.InputError, match=r"<arrays>\.gaps.*row 1.*area"):
        squeal.cea(squeal.Scene.from_arrays(r.K, r.M, r.dofs, gaps=gaps, toml="[cea]"))
    with pytest.raises(squeal.InputError, match=r"<arrays>\.K.*2x2"):
        squeal.cea(squeal.Scene.from_arrays(np.eye(2), r.M, r.dofs, toml="[cea]"))
    with pytest.raises(squeal.SceneError, match="model.from"):
        squeal.Scene.from_toml('[model]\nfrom = "arrays"\n')


def test_cea_energy_closes_and_sums_per_pair():
    # CeaResult.energy is cea.json's energy balance (docs/insight.md): per root, net work per
    # cycle = 2σT (the identity, to 1e-8 as the Rust tests), each pair's feed-in the sum of its
    # gaps', the kinetic shares summing to 1 with the strain and contact-spring shares.
    c = squeal.cea(squeal.Scene.from_file(TINY).set("cea", {}))
    e = c.energy
    assert e["roots"] and len(e["roots"]) == len(c.eigenvalues)
    assert e["max_identity_residual"] < 1e-8
    for r in e["roots"]:
        assert abs(r["net"] - r["growth"]) <= 1e-8 * max(1.0, abs(r["feed_in_total"]))
        assert abs(sum(r["feed_in_per_pair"]) - sum(r["feed_in_per_gap"])) <= 1e-12 * max(
            1.0, sum(abs(x) for x in r["feed_in_per_gap"])
        )
        shares = sum(r["kinetic_share"]) + sum(r["strain_share"]) + r["contact_strain_share"]
        assert abs(shares - 1.0) < 1e-8, shares


def test_cea_sensitivity_ranked_with_the_change_to_neutral():
    # CeaResult.sensitivity is cea.json's sensitivity (docs/insight.md): per root the design
    # parameters ranked by |normalised| = scale x dRe p/dtheta, each with the first-order change
    # -Re p / (dRe p/dtheta) that brings Re p to zero (the Rust tests check the derivatives
    # against finite differences of the re-solved CEA); the friction law's mu0 is among them.
    c = squeal.cea(squeal.Scene.from_file(TINY).set("cea", {}))
    s = c.sensitivity
    assert s["roots"] and s["parameters"]
    names = {p["name"] for p in s["parameters"]}
    assert {"friction.law.mu0", "loads.pmax", "rotor.rpm"} <= names
    unstable = set(np.flatnonzero(c.unstable))
    for r in s["roots"]:
        assert r["unstable"] == (r["mode"] in unstable)
        norms = [abs(p["normalised"]) for p in r["params"]]
        assert norms == sorted(norms, reverse=True)
        assert len(r["params"]) == len(s["parameters"])
        for p in r["params"]:
            if p["status"] == "zero_derivative":
                assert p["delta_to_neutral"] is None
                continue
            assert p["delta_to_neutral"] == pytest.approx(
                -r["refined_real_part"] / p["d_real_part"], rel=1e-12
            )
    off = squeal.cea(squeal.Scene.from_file(TINY).set("cea", {"sensitivity": False}))
    assert off.sensitivity == {}
