"""Symmetric quadrature rules for fe/src/element/rules.rs, solved to double precision.

Each rule is a set of symmetry orbits in barycentric coordinates; the orbit parameters and
weights solve the moment equations (exact integration of every monomial up to the degree) by
least squares (Gauss–Newton), started from the published values (Dunavant 1985, triangle degree 4;
Walkington 2000 / Keast 1986, tetrahedron degree 5, 14 points). The Rust unit tests check
exactness independently (every monomial up to the degree, against i! j! k! / (i+j+k+d)!).

Run: python fe/scripts/quadrature_rules.py
"""
import itertools
from math import factorial

import numpy as np
from scipy.optimize import least_squares


def tri_orbit21(a):
    b = 1 - 2 * a
    return [(a, a), (a, b), (b, a)]


def tet_orbit31(a):
    b = 1 - 3 * a
    return [(a, a, a), (b, a, a), (a, b, a), (a, a, b)]


def tet_orbit22(a):
    b = 0.5 - a
    pts = []
    for i, j in itertools.combinations(range(4), 2):
        lam = [b] * 4
        lam[i] = a
        lam[j] = a
        pts.append(tuple(lam[1:]))
    return pts


def exact(exps, dim):
    num = np.prod([factorial(e) for e in exps])
    return num / factorial(sum(exps) + dim)


def monomials(dim, degree):
    return [e for e in itertools.product(range(degree + 1), repeat=dim) if sum(e) <= degree]


def residual(points, weights, dim, degree):
    r = []
    for e in monomials(dim, degree):
        q = sum(w * np.prod([p[k] ** e[k] for k in range(dim)]) for p, w in zip(points, weights))
        r.append(q - exact(e, dim))
    return np.array(r)


def triangle4():
    def build(v):
        a1, w1, a2, w2 = v
        pts = tri_orbit21(a1) + tri_orbit21(a2)
        return pts, [w1] * 3 + [w2] * 3

    def f(v):
        pts, w = build(v)
        return residual(pts, w, 2, 4)

    v = least_squares(f, [0.445948490915965, 0.111690794839005, 0.091576213509771,
                          0.054975871827661], xtol=1e-15, ftol=1e-15, gtol=1e-15).x
    pts, w = build(v)
    assert np.abs(residual(pts, w, 2, 4)).max() < 1e-15
    return v


def tet5():
    def build(v):
        a1, w1, a2, w2, a3, w3 = v
        pts = tet_orbit31(a1) + tet_orbit31(a2) + tet_orbit22(a3)
        return pts, [w1] * 4 + [w2] * 4 + [w3] * 6

    def f(v):
        pts, w = build(v)
        return residual(pts, w, 3, 5)

    v = least_squares(f, [0.0927352503108912, 0.01224884051939366, 0.3108859192633006,
                          0.01878132095300264, 0.0455037041256496, 0.007091003462846911],
                      xtol=1e-15, ftol=1e-15, gtol=1e-15).x
    pts, w = build(v)
    assert np.abs(residual(pts, w, 3, 5)).max() < 1e-15, residual(pts, w, 3, 5)
    return v


if __name__ == "__main__":
    np.set_printoptions(precision=17)
    print("triangle degree 4 (a1, w1, a2, w2):", [repr(x) for x in triangle4()])
    print("tetrahedron degree 5 (a1, w1, a2, w2, a3, w3):", [repr(x) for x in tet5()])
