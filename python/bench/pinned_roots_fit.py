"""How well does a transient window pin a root's growth rate? (docs/verdict.md, issue 11)

Fits the response's velocity channels (response.npy of `squeal transient`: column 0 is t,
then the recorded velocities, then their derivatives) on a window by least squares on the
exponentials of the CEA's roots (cea.json of `squeal cea` at the same state: every root below
`cea.max_frequency_hz`, with its conjugate, plus a constant), with the roots *fixed*. The
residual says how much of the response is not a sum of those roots, and its change as the
most unstable root's Re p is scaled says how strongly the window constrains that Re p.
Then the residual's spectrum, and the same scan with further roots fitted to the residual
(a matrix pencil of the residual, orders 20/40/60), in case what is left over is a sum of
exponentials outside the CEA's list.

    python pinned_roots_fit.py RESPONSE.npy CEA.json T0 T1 [NCHANNELS]
"""
import json
import sys

import numpy as np
from scipy.interpolate import CubicHermiteSpline


def main():
    resp, cea, t0, t1 = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
    nch = int(sys.argv[5]) if len(sys.argv) > 5 else 9
    r = np.load(resp)
    t, v, dv = r[:, 0], r[:, 1 : 1 + nch], r[:, 1 + nch : 1 + 2 * nch]
    modes = json.load(open(cea))["modes"]
    s = []
    for m in modes:
        f, re = m["frequency_hz"], m["real_part"]
        s += [complex(re, 2 * np.pi * f), complex(re, -2 * np.pi * f)] if f > 0 else [complex(re, 0)]
    s = np.array(s)
    # Uniform samples, 1 us apart, by cubic Hermite interpolation with the derivative.
    dt = 1e-6
    tt = np.arange(t0, t1, dt)
    y = np.array([CubicHermiteSpline(t, v[:, c], dv[:, c])(tt) for c in range(nch)]).T
    tt = tt - t0

    def fit(roots):
        z = np.hstack([np.exp(np.outer(tt, roots)), np.ones((len(tt), 1))])
        a = np.linalg.lstsq(z, y, rcond=None)[0]
        res = (z @ a).real - y
        return res, np.linalg.norm(res) / np.linalg.norm(y)

    k = int(np.argmax(s.real * (s.imag > 0)))

    def scaled(scale):
        s2 = s.copy()
        s2[k] = complex(s[k].real * scale, s[k].imag)
        j = int(np.argmin(abs(s2 - s[k].conjugate())))
        s2[j] = s2[k].conjugate()
        return s2

    print(f"window [{t0}, {t1}] s, {len(tt)} samples, {nch} channels, {len(s)} CEA roots")
    print(f"most unstable CEA root: Re p = {s[k].real:+.3f} /s at {s[k].imag / 2 / np.pi:.2f} Hz")
    scales = [0.94, 0.98, 1.0, 1.02, 1.06]
    for scale in scales:
        print(f"  Re p x {scale:.2f}: relative residual {fit(scaled(scale))[1]:.5f}")
    res, _ = fit(s)
    spec = (np.abs(np.fft.rfft(res * np.hanning(len(tt))[:, None], axis=0)) ** 2).sum(1)
    fr = np.fft.rfftfreq(len(tt), dt)
    print("residual energy by band:")
    for lo, hi in [(0, 5e3), (5e3, 10e3), (10e3, 20e3), (20e3, 50e3), (50e3, 5e5)]:
        m = (fr >= lo) & (fr < hi)
        print(f"  {lo / 1e3:.0f}-{hi / 1e3:.0f} kHz: {spec[m].sum() / spec.sum():.3f}")
    # Further roots: a matrix pencil of the residual at 2.5 us.
    step = 5 if len(tt) > 5 * 64 else 1
    rs, dtp = res[::step], dt * step
    n, l = len(rs), len(rs) // 3
    h = np.vstack([np.lib.stride_tricks.sliding_window_view(rs[:, c], l + 1) for c in range(nch)])
    vh = np.linalg.svd(h, full_matrices=False)[2]
    for order in [20, 40, 60]:
        vm = vh[:order].conj().T
        extra = np.log(np.linalg.eigvals(np.linalg.pinv(vm[:-1]) @ vm[1:])) / dtp
        row = ", ".join(
            f"x{sc:.2f}: {fit(np.concatenate([scaled(sc), extra]))[1]:.5f}" for sc in scales
        )
        print(f"  with {order} further roots: {row}")


if __name__ == "__main__":
    main()
