"""Kirchhoff frequencies of an annular plate clamped at r = b, free at r = a.

Run with the repository's virtualenv:  .venv/bin/python fe/scripts/annular_plate_kirchhoff.py
Solves the 4x4 Bessel determinant (Leissa, Vibration of Plates, NASA SP-160, sec. 2.3) for
n = 0..4 nodal diameters and prints the lowest frequencies in Hz.
"""
import numpy as np
from scipy import special as sp
from scipy.optimize import brentq

E, nu, rho, h = 200e9, 0.3, 8000.0, 0.004
b, a = 0.08, 0.16
D = E * h**3 / (12 * (1 - nu**2))


def funcs(n, k, r):
    """Rows: value, d/dr, d2/dr2, d/dr(laplacian) for J, Y, I, K of order n at k r."""
    x = k * r
    out = []
    for kind in "JYIK":
        if kind == "J":
            f, fp = sp.jv(n, x), sp.jvp(n, x)
            fpp = -fp / x - (1 - n * n / x**2) * f
            lap = -k * k
        elif kind == "Y":
            f, fp = sp.yv(n, x), sp.yvp(n, x)
            fpp = -fp / x - (1 - n * n / x**2) * f
            lap = -k * k
        elif kind == "I":
            f, fp = sp.iv(n, x), sp.ivp(n, x)
            fpp = -fp / x + (1 + n * n / x**2) * f
            lap = k * k
        else:
            f, fp = sp.kv(n, x), sp.kvp(n, x)
            fpp = -fp / x + (1 + n * n / x**2) * f
            lap = k * k
        out.append((f, k * fp, k * k * fpp, lap * k * fp))
    return out


def det(n, k):
    rows = []
    fb = funcs(n, k, b)
    rows.append([c[0] for c in fb])  # w(b) = 0
    rows.append([c[1] for c in fb])  # w'(b) = 0
    fa = funcs(n, k, a)
    # M_r = w'' + nu (w'/r - n^2 w / r^2) = 0
    rows.append([c[2] + nu * (c[1] / a - n * n * c[0] / a**2) for c in fa])
    # V_r = d/dr lap w - (1 - nu) n^2 / r^2 (w' - w / r) = 0
    rows.append([c[3] - (1 - nu) * n * n / a**2 * (c[1] - c[0] / a) for c in fa])
    m = np.array(rows)
    m /= np.abs(m).max(axis=0)
    return np.linalg.det(m)


freqs = []
for n in range(0, 6):
    ks = np.linspace(1.0, 120.0, 6000)
    vals = [det(n, k) for k in ks]
    for i in range(len(ks) - 1):
        if np.sign(vals[i]) != np.sign(vals[i + 1]):
            k = brentq(lambda kk: det(n, kk), ks[i], ks[i + 1])
            if abs(det(n, k)) < 1e-6:
                f = k * k * np.sqrt(D / (rho * h)) / (2 * np.pi)
                freqs.append((f, n))
freqs.sort()
for f, n in freqs[:8]:
    print(f"n = {n}: {f:.2f} Hz  (lambda^2 = k^2 a^2 = {(2*np.pi*f/np.sqrt(D/(rho*h)))*a*a:.4f})")
