"""squeal.propensity: Hoffmann's model with a uniform μ gives P(unstable) = (b − μc)/(b − a)
exactly (Hoffmann, Fischer, Bieser & Gaul 2002: μc = 1/3 for these stiffnesses); a Dask
LocalCluster of 2 workers gives the threads' numbers; the CLI's `squeal propensity` the
same file; bad inputs name the flag."""

from __future__ import annotations

import numpy as np
import pytest

import squeal
from conftest import EXAMPLES, read_json

TINY = EXAMPLES / "transient" / "tiny-brake.toml"

HOFFMANN_TOML = """
[friction]
law = { kind = "constant", mu = 0.1 }
vtol = 1e-6
[rotor]
rpm = 9549.296585513720
axis = [0.0, 0.0, 1.0]
[loads]
pmax = 1.0
tload = 0.0
[cea]
friction_damping = true
"""


def hoffmann() -> squeal.Scene:
    """The 2-DOF mode-coupling model of pipeline/tests/propensity.rs as arrays: constrained
    stiffness [[k11, k12 − μ k3], [k12, k22]] = 1e4 [[1, 0.3 − μ], [0.3, 1.2]], flutter above
    μc = 1/3 (discriminant 0.4 − 1.2 μ), no damping."""
    s = 1.0e4
    K = s * np.array([[1.0, 0.3, 0.0], [0.3, 0.2, 0.0], [0.0, 0.0, 1.0]])
    M = np.diag([1.0, 1.0 - 1e-6, 1e-6])
    dofs = [dict(component="pad", kind="grid", grid=1, comp=1),
            dict(component="pad", kind="grid", grid=1, comp=3),
            dict(component="rotor", kind="grid", grid=2, comp=3)]
    gaps = [dict(pad_grid=1, rotor_grid=2, x=0.0, y=-1.0, z=0.0, nx=0.0, ny=0.0, nz=1.0, area=1.0, p0=1.0,
                 temperature=0.0)]
    return squeal.Scene.from_arrays(K, M, dofs, gaps=gaps, B=np.zeros((3, 3)), p_brake=np.zeros(3),
                                    toml=HOFFMANN_TOML)


def test_hoffmann_probability_is_the_uniform_fraction(tmp_path):
    # Each replicate's A and B points project to a (0, m, 1)-net in μ: one point per interval of
    # width 1/n_base, so the fraction above μc is within 1/n_base of 5/9.
    r = squeal.propensity(hoffmann(), {"friction.law.mu": "uniform(0.2, 0.5)"}, 512, out=tmp_path)
    exact = 5.0 / 9.0
    lo, hi = r.interval
    assert abs(r.p_unstable - exact) <= 1.0 / r.report["n_base"] + 1e-4
    assert lo <= exact <= hi
    df = r.samples
    assert len(df) == 512 and r.report["stats"]["failed"] == 0
    assert {"friction.law.mu", "max_real_part", "unstable", "kind"} <= set(df.columns)
    # The flag is Re p > 0 of an in-band root: above μc and only there (μc within 1e-5).
    mu = df["friction.law.mu"].to_numpy()
    uns = df["unstable"].astype(bool).to_numpy()
    far = np.abs(mu - 1.0 / 3.0) > 1e-5
    assert np.array_equal(uns[far], mu[far] > 1.0 / 3.0)
    assert (tmp_path / "propensity.json").exists() and (tmp_path / "samples.csv").exists()
    b = r.bands()
    assert abs(b["p"].sum() - r.p_unstable) < 1e-12  # one band holds the 16.7 Hz pair
    fig = r.plot(tmp_path / "propensity.png")
    assert (tmp_path / "propensity.png").stat().st_size > 0
    assert len(fig.axes) == 3


def test_dask_cluster_gives_the_threads_numbers(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    dists = {"friction.law.mu": "uniform(0.2, 0.5)", "loads.pmax": "lognormal(0, 0.3)"}
    scene = hoffmann()
    local = squeal.propensity(scene, dists, 256, out=tmp_path / "local")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        dask = squeal.propensity(scene, dists, 256, client=client, out=tmp_path / "dask", cache=tmp_path / "cache")
    assert dask.p_unstable == local.p_unstable
    # Each chunk ran in its own work folder (chunks that build a model must not share one).
    chunks = sorted(d.name for d in (tmp_path / "dask" / "work").iterdir())
    assert chunks == [f"chunk-{k:03d}" for k in range(4)], chunks
    np.testing.assert_allclose(dask.samples["max_real_part"].to_numpy(), local.samples["max_real_part"].to_numpy(),
                               rtol=1e-12, atol=1e-9)
    s = dask.sobol("unstable")
    # pmax scales a zero brake load: no effect on any root, so its total index is 0.
    assert abs(s.loc["loads.pmax", "ST"]) < 1e-9 and abs(s.loc["friction.law.mu", "ST"] - 1.0) < 0.1


def test_cli_writes_the_same_study(cli, tmp_path):
    d, _ = cli("propensity", str(TINY), "--dist", "friction.law.mu0=uniform(0.3, 0.9)",
               "--dist", "contact.0.p0=normal(1.0, 0.1)", "--samples", "64")
    ref = read_json(d / "propensity.json")
    r = squeal.propensity(squeal.Scene.from_file(TINY),
                          ["friction.law.mu0=uniform(0.3, 0.9)", "contact.0.p0=normal(1.0, 0.1)"], 64,
                          out=tmp_path)
    assert r.report["p_unstable"] == ref["p_unstable"]
    assert r.report["stats"]["evaluations"] == ref["stats"]["evaluations"]
    a = np.array([q[1] for q in r.report["max_real_part"]["quantiles"]])
    b = np.array([q[1] for q in ref["max_real_part"]["quantiles"]])
    np.testing.assert_allclose(a, b, rtol=1e-12)


def test_bad_inputs_name_the_flag():
    scene = squeal.Scene.from_file(TINY)
    with pytest.raises(squeal.SquealError, match=r"--dist friction\.law\.mux=uniform"):
        squeal.propensity(scene, {"friction.law.mux": "uniform(0.3, 0.5)"}, 64)
    with pytest.raises(squeal.SquealError, match="a < b"):
        squeal.propensity(scene, {"friction.law.mu0": "uniform(0.5, 0.3)"}, 64)
    with pytest.raises(squeal.SquealError, match="changes the reduced model"):
        squeal.propensity(scene, {"components.1.material.poisson": "uniform(0.25, 0.35)"}, 64)
    with pytest.raises(squeal.SquealError, match="--samples"):
        squeal.propensity(scene, {"friction.law.mu0": "uniform(0.3, 0.5)", "contact.0.p0": "uniform(0.5, 1.5)"}, 20)
    with pytest.raises(TypeError, match="distributions"):
        squeal.propensity(scene, 0.5, 64)


def test_one_volume_is_checked_against_re_reduction():
    """The sample brake's inboard lining modulus on the one reduced model: before the rows are
    evaluated, squeal.propensity compares it with re-reduction at the input's 0.5 % and
    99.5 % quantiles (``propensity::Evaluator::check_basis``; the Rust test
    ``one_volume_on_the_reduced_model_is_checked_against_re_reduction`` measures 0.15 and
    0.044 /s of 118 and 147 /s) and reports the checks in ``model.basis_checks``, within the
    default tolerance (5 % of |Re λ|, at least 1 /s); the Rust test also checks the refusal
    above the tolerance."""
    scene = squeal.Scene.from_file(EXAMPLES / "sample-brake" / "base.toml")
    key = "components.1.materials.lining.young"
    r = squeal.propensity(scene, {key: "uniform(0.7e6, 1.3e6)"}, 16, replicates=2)
    checks = r.report["model"]["basis_checks"]
    assert [c["key"] for c in checks] == [key, key]
    assert all(c["passed"] and c["real_part_change"] <= c["allowed"] for c in checks)
    assert abs(checks[0]["value"] - 0.703e6) < 1e3 and abs(checks[1]["value"] - 1.297e6) < 1e3
    assert r.report["stats"]["failed"] == 0
