"""SUNDIALS IDA beside squeal's BDF on the same BSQL DAE (issue 13, item 3: step counts at equal
error). Not run by CI.

What it does, for the study brake (paper case 2, `examples/sample-brake/base.toml` with the
paper's rigid contact: `normal_stiffness` removed, as `bench_step` runs it):

1. `squeal transient --export-dae DIR` at each RTOL1 (ATOL1 = RTOL1, ATOL2 = 1e20, MAXORD 2;
   at RTOL1 1e-4 under the band step bound h <= 2.5e-6 s as `reproduce` runs it, below that
   with the bound off): squeal's steps, Newton iterations, set-ups and CPU seconds
   (`summary.json`) and its final state (`restart.json`).
2. The same DAE in numpy from the exported files: F(t, y, y') of the export's README (friction
   of paper eqs. 1-7 with the arctangent regularisation of `squeal-contact`), its Jacobian
   dF/dy + cj dF/dy' (with the friction damping C_f = dF_f/dv and D = dF_f/dlambda'), the
   steady sliding state and y'(0).
3. IDA (scikit-sundae, SUNDIALS 7) on it: (a) the full (2n + ng) DAE with IDA's dense LU
   ('dense'; 'lapackdense' = OpenBLAS with --lapack), and (b) with squeal's u-eliminated
   (n + ng) Newton matrix: IDA's Newton with GMRES preconditioned by the exact inverse of the
   iteration matrix, applied through the u-eliminated LU (scipy), so that each Newton
   iteration is one preconditioned solve; same tolerances and weights as squeal (rtol =
   RTOL1, atol = ATOL1 on v and u, 1e20 on lambda), MAXORD 2, the same step bound.
4. A tight reference (IDA, MAXORD 5, rtol 1e-11) evaluated at each run's final time; error =
   max |v - v_ref| / max |v_ref| over the n velocities. The reference is checked against squeal
   at RTOL1 1e-10.

IDA's own work is timed apart from the Python callbacks: CPU seconds of the whole step loop
minus those spent inside the residual, Jacobian and preconditioner callbacks (so it also holds
the loop's Python overhead: an upper bound; `wrapper_us_per_step` is that overhead with IDA's
own work on a scalar ODE, measured by the same loop).

Install (one command, a venv of its own): `python -m pip install scikit-sundae numpy scipy`.

    python python/bench/bench_ida.py --squeal target/release/squeal [--out docs/bench/ida_peer.json]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import tempfile
import time
from pathlib import Path

# One thread for numpy's BLAS: squeal runs on one core, and process CPU time would otherwise
# count the BLAS threads' spinning.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import scipy.linalg as sla  # noqa: E402
from sksundae.ida import IDA, IDAPrecond  # noqa: E402

ATAN_10 = np.arctan(10.0)


def cpu() -> float:
    return time.process_time()


class Bsql:
    """The exported BSQL DAE: y = [v (n), lambda (ng), u (n)]."""

    def __init__(self, d: Path):
        self.M = np.load(d / "M.npy")
        self.B = np.load(d / "B.npy")
        self.K = np.load(d / "K.npy")
        self.G = np.load(d / "G.npy")
        self.p_pre = np.load(d / "p_pre.npy").ravel()
        self.p_brake = np.load(d / "p_brake.npy").ravel()
        opts = json.loads((d / "solver_options.json").read_text())
        self.opts = opts
        self.t_load = opts["t_load"]
        self.step_load = opts["step_load"]
        gaps = json.loads((d / "gaps.json").read_text())
        self.law = gaps["law"]
        self.vtol = gaps["vtol"]
        g = gaps["gaps"]
        n, ng = self.M.shape[0], len(g)
        self.n, self.ng = n, ng
        # S (3 ng x n): dv_g = S_g v + v_slide_g (rotor point minus pad point).
        S = np.zeros((3 * ng, n))
        for k, gap in enumerate(g):
            for c in range(3):
                if gap["pad_dofs"][c] is not None:
                    S[3 * k + c, gap["pad_dofs"][c]] -= 1.0
            terms = (
                [(w, dofs) for w, dofs in zip(gap["tie"]["weights"], gap["tie"]["dofs"])]
                if gap.get("tie")
                else [(1.0, gap["rotor_dofs"])]
            )
            for w, dofs in terms:
                for c in range(3):
                    if dofs[c] is not None:
                        S[3 * k + c, dofs[c]] += w
        self.S = S
        self.normal = np.array([gp["normal"] for gp in g])
        self.area = np.array([gp["area"] for gp in g])
        self.v_slide = np.array([gp["v_slide"] for gp in g])
        self.p0 = np.array([gp["p0"] for gp in g])
        self.temp = np.array([gp["temperature"] for gp in g])
        self.N = 2 * n + ng

    def load(self, t: float) -> np.ndarray:
        r = 1.0 if self.step_load else min(t / self.t_load, 1.0) if self.t_load > 0 else 1.0
        return self.p_pre + r * self.p_brake

    def mu(self, p, s):
        law = self.law
        kind = law["kind"]
        z = np.zeros_like(p)
        if kind == "constant":
            return law["mu"] + z, z, z
        if kind == "linear_speed":
            return law["mu0"] + law["slope"] * s, z, law["slope"] + z
        if kind == "equation":
            fp = 1.0 + law.get("a", 0.0) * p
            fv = 1.0 + law.get("b", 0.0) * s
            ft = 1.0 + law.get("c", 0.0) * (self.temp - law.get("t0", 0.0))
            m0 = law["mu0"]
            return m0 * fp * fv * ft, m0 * law.get("a", 0.0) * fv * ft, m0 * fp * law.get("b", 0.0) * ft
        raise ValueError(f"friction law {kind!r} not supported by this driver")

    def reg(self, s):
        """phi(s) = r(s)/s and phi'(s)/s of squeal-contact's regularisation."""
        vt = self.vtol
        phi = np.empty_like(s)
        psi = np.empty_like(s)
        out = s >= 10 * vt
        phi[out] = 1.0 / s[out]
        psi[out] = -1.0 / s[out] ** 3
        x = s[~out] / vt
        small = x < 1e-3
        g = np.where(small, 1 - x**2 / 3 + x**4 / 5, np.arctan(np.where(small, 1, x)) / np.where(small, 1, x))
        xs = np.where(small, 1, x)
        h = np.where(
            small,
            -2 / 3 + 4 * x**2 / 5 - 6 * x**4 / 7,
            (xs / (1 + xs * xs) - np.arctan(xs)) / xs**3,
        )
        phi[~out] = g / (vt * ATAN_10)
        psi[~out] = h / (vt**3 * ATAN_10)
        return phi, psi

    def gap_terms(self, v, lamp, tangents=False):
        ng = self.ng
        nrm = self.normal
        dv = (self.S @ v).reshape(ng, 3) + self.v_slide
        dn = np.einsum("gi,gi->g", dv, nrm)
        vt = dv - dn[:, None] * nrm
        s = np.sqrt(np.einsum("gi,gi->g", vt, vt))
        p = -lamp / self.area + self.p0
        mu, dmu_dp, dmu_ds = self.mu(p, s)
        ft = mu * self.area * p
        phi, psi = self.reg(s)
        c = ft * phi
        f = c[:, None] * vt  # force on the pad
        if not tangents:
            return f, None, None
        # df/dlambda' and df/d(dv) per gap.
        dft_dp = self.area * (mu + dmu_dp * p)
        df_dl = (-dft_dp / self.area * phi)[:, None] * vt
        P = np.eye(3)[None] - nrm[:, :, None] * nrm[:, None, :]
        dft_ds = dmu_ds * self.area * p
        coef = np.where(s > 0, dft_ds * phi / np.where(s > 0, s, 1), 0.0) + ft * psi
        df_ddv = c[:, None, None] * P + coef[:, None, None] * vt[:, :, None] * vt[:, None, :]
        return f, df_dl, df_ddv

    def friction(self, v, lamp):
        f, _, _ = self.gap_terms(v, lamp)
        return -self.S.T @ f.ravel()

    def tangents(self, v, lamp):
        """D = dF_f/dlambda' (n x ng), C_f = dF_f/dv (n x n)."""
        ng = self.ng
        _, df_dl, df_ddv = self.gap_terms(v, lamp, True)
        D = np.zeros((self.n, ng))
        for k in range(ng):
            D[:, k] = -self.S[3 * k : 3 * k + 3].T @ df_dl[k]
        blk = sla.block_diag(*df_ddv)
        Cf = -self.S.T @ blk @ self.S
        return D, Cf

    def residual(self, t, y, yp, r):
        n, ng = self.n, self.ng
        v, u = y[:n], y[n + ng :]
        vp, lamp, up = yp[:n], yp[n : n + ng], yp[n + ng :]
        r[:n] = self.M @ vp + self.B @ v + self.K @ u + self.G.T @ lamp - self.load(t) - self.friction(v, lamp)
        r[n : n + ng] = self.G @ vp
        r[n + ng :] = up - v

    def jacobian(self, t, y, yp, cj, J):
        n, ng = self.n, self.ng
        D, Cf = self.tangents(y[:n], yp[n : n + ng])
        J[:, :] = 0.0
        J[:n, :n] = cj * self.M + self.B - Cf
        J[:n, n : n + ng] = cj * (self.G.T - D)
        J[:n, n + ng :] = self.K
        J[n : n + ng, :n] = cj * self.G
        J[n + ng :, :n] = -np.eye(n)
        J[n + ng :, n + ng :] = cj * np.eye(n)

    def start(self):
        """Steady sliding state before the brake load (v = 0), lambda = 0, and y'(0)."""
        n, ng = self.n, self.ng
        u = np.zeros(n)
        lamp = np.zeros(ng)
        v0 = np.zeros(n)
        p = self.load(0.0)
        for _ in range(50):
            r = np.concatenate([self.K @ u + self.G.T @ lamp - p - self.friction(v0, lamp), self.G @ u])
            D, _ = self.tangents(v0, lamp)
            A = np.block([[self.K, self.G.T - D], [self.G, np.zeros((ng, ng))]])
            dx = np.linalg.solve(A, -r)
            u += dx[:n]
            lamp += dx[n:]
            if np.max(np.abs(dx)) <= 1e-13 * max(1.0, np.max(np.abs(np.concatenate([u, lamp])))):
                break
        y0 = np.concatenate([v0, np.zeros(ng), u])
        yp0 = np.concatenate([np.zeros(n), lamp, np.zeros(n)])
        r = np.zeros(self.N)
        self.residual(0.0, y0, yp0, r)
        return y0, yp0, float(np.max(np.abs(r)))


class Timed:
    """Callbacks with their CPU time summed."""

    def __init__(self, sys: Bsql):
        self.sys = sys
        self.cb_s = 0.0
        self.nres = 0
        self.njac = 0
        self.npset = 0
        self.npsol = 0
        self.lu = None

    def res(self, t, y, yp, r):
        c = cpu()
        self.sys.residual(t, y, yp, r)
        self.nres += 1
        self.cb_s += cpu() - c

    def jac(self, t, y, yp, r, cj, J):
        c = cpu()
        self.sys.jacobian(t, y, yp, cj, J)
        self.njac += 1
        self.cb_s += cpu() - c

    # (b): squeal's u-eliminated Newton matrix as an exact preconditioner.
    def psetup(self, t, y, yp, r, cj):
        c = cpu()
        s = self.sys
        n, ng = s.n, s.ng
        D, Cf = s.tangents(y[:n], yp[n : n + ng])
        A = np.block(
            [
                [cj * s.M + s.B - Cf + s.K / cj, cj * (s.G.T - D)],
                [cj * s.G, np.zeros((ng, ng))],
            ]
        )
        self.lu = (sla.lu_factor(A), cj)
        self.npset += 1
        self.cb_s += cpu() - c

    def psolve(self, t, y, yp, r, rv, zv, cj, delta):
        c = cpu()
        s = self.sys
        n, ng = s.n, s.ng
        lu, cj0 = self.lu
        # The iteration matrix at cj0 with the u-row eliminated: du = (r_u + dv)/cj0.
        r_v, r_l, r_u = rv[:n], rv[n : n + ng], rv[n + ng :]
        x = sla.lu_solve(lu, np.concatenate([r_v - s.K @ r_u / cj0, r_l]))
        zv[:n] = x[:n]
        zv[n : n + ng] = x[n:]
        zv[n + ng :] = (r_u + x[:n]) / cj0
        self.npsol += 1
        self.cb_s += cpu() - c


def run_ida(sys: Bsql, y0, yp0, t_end, rtol, atol_v, max_order, h_max, mode, tout=()):
    cb = Timed(sys)
    atol = np.concatenate([np.full(sys.n, atol_v), np.full(sys.ng, 1e20), np.full(sys.n, atol_v)])
    opts = dict(
        rtol=rtol,
        atol=atol,
        max_order=max_order,
        max_num_steps=10**7,
        max_step=h_max or 0.0,
    )
    if mode in ("dense", "lapackdense"):
        opts.update(linsolver=mode, jacfn=cb.jac)
    else:
        opts.update(
            linsolver="gmres",
            krylov_dim=5,
            precond=IDAPrecond(cb.psetup, cb.psolve),
        )
    solver = IDA(cb.res, **opts)
    c0 = cpu()
    w0 = time.perf_counter()
    solver.init_step(0.0, y0, yp0)
    steps = 0
    t = 0.0
    outs = {}
    pending = sorted(tout)
    y_end = None
    while t < t_end:
        res = solver.step(t_end, method="onestep", tstop=t_end)
        if not res.success:
            raise RuntimeError(f"IDA failed at t = {t}: {res.message}")
        t_new = float(res.t[-1] if np.ndim(res.t) else res.t)
        steps += 1
        while pending and pending[0] <= t_new:
            tp = pending.pop(0)
            outs[tp] = np.array(solver.step(tp).y).ravel() if tp < t_new else np.array(res.y).ravel()
        t = t_new
        y_end = np.array(res.y).ravel()
    total = cpu() - c0
    wall = time.perf_counter() - w0
    return {
        "mode": mode,
        "rtol": rtol,
        "max_order": max_order,
        "h_max": h_max,
        "steps": steps,
        "residual_evals": cb.nres,
        "jacobian_evals": cb.njac,
        "precond_setups": cb.npset,
        "precond_solves": cb.npsol,
        "cpu_s": total,
        "wall_s": wall,
        "callbacks_s": cb.cb_s,
        "ida_own_s": total - cb.cb_s,
        "ida_own_us_per_step": 1e6 * (total - cb.cb_s) / max(steps, 1),
    }, y_end, outs


def wrapper_us_per_step(steps=20000):
    """CPU us per step of IDA on a scalar ODE (y' = -y) driven by the same one-step loop, minus
    its callbacks: the Python wrapper's cost per step, included in `ida_own_us_per_step`."""
    cb_s = [0.0]

    def res(t, y, yp, r):
        c = cpu()
        r[0] = yp[0] + y[0]
        cb_s[0] += cpu() - c

    t_end = 1.0
    solver = IDA(res, rtol=1e-6, atol=1e-12, max_order=2, max_num_steps=10**7, max_step=t_end / steps)
    c0 = cpu()
    solver.init_step(0.0, np.array([1.0]), np.array([-1.0]))
    t, n = 0.0, 0
    while t < t_end:
        res_ = solver.step(t_end, method="onestep", tstop=t_end)
        t = float(res_.t[-1] if np.ndim(res_.t) else res_.t)
        n += 1
    return 1e6 * (cpu() - c0 - cb_s[0]) / n


def rel_err(v, vref):
    return float(np.max(np.abs(v - vref)) / np.max(np.abs(vref)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--squeal", default="target/release/squeal")
    ap.add_argument("--scene", default="examples/sample-brake/base.toml")
    ap.add_argument("--rtols", type=float, nargs="+", default=[1e-4, 1e-6, 1e-8])
    ap.add_argument("--ref-rtol", type=float, default=1e-11)
    ap.add_argument("--lapack", action="store_true", help="also IDA with 'lapackdense'")
    ap.add_argument("--no-precond", action="store_true", help="skip (b)")
    ap.add_argument("--out", default="docs/bench/ida_peer.json")
    a = ap.parse_args()
    work = Path(tempfile.mkdtemp(prefix="squeal-ida-"))
    scene = work / "rigid.toml"
    scene.write_text(
        "".join(l for l in Path(a.scene).read_text().splitlines(True) if not l.strip().startswith("normal_stiffness"))
    )
    rows = []
    squeal_runs = {}
    for rtol in a.rtols + [1e-10]:
        out = work / f"run_{rtol:g}"
        sets = ["transient.nrstrt=0", f"transient.rtol1={rtol}", f"transient.atol1={rtol}"]
        if rtol < 1e-4:
            sets.append("transient.band_step_bound=false")
        cmd = [a.squeal, "-q", "transient", str(scene), "--out", str(out), "--export-dae", str(work / f"dae_{rtol:g}")]
        for s in sets:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True)
        summ = json.loads((out / "summary.json").read_text())
        rst = json.loads((out / "restart.json").read_text())
        squeal_runs[rtol] = (summ, rst)
        print(f"squeal RTOL1 {rtol:g}: {summ['steps']} steps, {summ['cpu_s']:.3f} s")
    sys = Bsql(work / f"dae_{a.rtols[0]:g}")
    n = sys.n
    y0, yp0, r0 = sys.start()
    print(f"n = {n}, ng = {sys.ng}; start residual {r0:.2e}")
    t_ends = sorted({rst["t"] for _, rst in squeal_runs.values()})
    t_end = max(t_ends + [sys.opts["tfinal"]])
    ref, yref, refs = run_ida(sys, y0, yp0, t_end, a.ref_rtol, a.ref_rtol, 5, None, "dense", t_ends)
    refs[t_end] = yref
    print(f"reference: IDA MAXORD 5 rtol {a.ref_rtol:g}: {ref['steps']} steps, {ref['cpu_s']:.1f} s")
    sq_ref = squeal_runs[1e-10]
    ref_check = rel_err(np.array(sq_ref[1]["state"]["phi"][0][:n]), refs[sq_ref[1]["t"]][:n])
    print(f"squeal RTOL1 1e-10 against the reference: {ref_check:.2e}")
    for rtol in a.rtols:
        summ, rst = squeal_runs[rtol]
        h_max = summ["step_bound"]["h_max"] if rtol >= 1e-4 else None
        te = rst["t"]
        sq_err = rel_err(np.array(rst["state"]["phi"][0][:n]), refs[te][:n])
        bdf = summ["bdf_stats"]
        row = {
            "rtol1": rtol,
            "h_max": h_max,
            "t_end": te,
            "squeal": {
                "steps": summ["steps"],
                "newton_iterations": bdf["newton_iterations"],
                "jacobian_setups": bdf["jacobian_setups"],
                "error_test_failures": bdf["error_test_failures"],
                "convergence_failures": bdf["convergence_failures"],
                "order_histogram": bdf["order_histogram"],
                "cpu_s": summ["cpu_s"],
                "bookkeeping_s": summ.get("bookkeeping_s"),
                "us_per_step": 1e6 * summ["cpu_s"] / summ["steps"],
                "error": sq_err,
            },
        }
        modes = ["dense"] + (["lapackdense"] if a.lapack else []) + ([] if a.no_precond else ["u_eliminated"])
        for mode in modes:
            st, y_end, _ = run_ida(sys, y0, yp0, te, rtol, rtol, 2, h_max, mode)
            st["error"] = rel_err(y_end[:n], refs[te][:n])
            row[f"ida_{mode}"] = st
            print(
                f"RTOL1 {rtol:g} {mode}: IDA {st['steps']} steps, {st['residual_evals']} res, "
                f"{st['jacobian_evals'] + st['precond_setups']} set-ups, err {st['error']:.2e}, "
                f"own {st['ida_own_us_per_step']:.0f} us/step (callbacks {st['callbacks_s']:.2f} s); "
                f"squeal {summ['steps']} steps, err {sq_err:.2e}"
            )
        rows.append(row)
    wrapper = wrapper_us_per_step()
    print(f"one-step loop on a scalar ODE: {wrapper:.1f} us per step outside the callbacks")
    doc = {
        "wrapper_us_per_step": wrapper,
        "case": "study brake, paper case 2, rigid contact (244 DOFs, 20 gaps), BDF MAXORD 2",
        "reference": {**ref, "squeal_rtol1_1e-10_vs_reference": ref_check},
        "start_residual": r0,
        "runs": rows,
    }
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(doc, indent=2))
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
