"""Derives the symmetric triangle quadrature rules of `src/quadrature/table.rs` to 30 digits.

Each rule is a union of symmetry orbits in barycentric coordinates (l1, l2, l3):
  S3   the centroid (1/3, 1/3, 1/3)              1 point,  unknown: weight
  S21  (a, a, 1 - 2a) and its permutations       3 points, unknowns: weight, a
  S111 (a, b, 1 - a - b) and its permutations    6 points, unknowns: weight, a, b
A fully symmetric rule is exact for all polynomials of degree <= d iff it is exact for the invariant
polynomials s2^i s3^j (s2 = l1 l2 + l2 l3 + l3 l1, s3 = l1 l2 l3) with 2i + 3j <= d. The orbit structures
below give square systems, solved by Newton's method (mpmath.findroot) from the published approximate
values of Strang & Fix (1973) and Dunavant (1985), "High degree efficient symmetrical Gaussian quadrature
rules for the triangle", IJNME 21, 1129-1148. Exact mean values come from
  mean(l1^a l2^b l3^c) = 2 a! b! c! / (a + b + c + 2)!.
Values are printed as the nearest f64 (shortest round-trip form) followed by 30 digits.
Weights are printed normalised to the reference-triangle area 1/2; points as (xi1, xi2) = (l2, l3).

Run: python3 derive_quadrature.py  (needs sympy and mpmath).
"""

import itertools
from math import factorial

import mpmath as mp
import sympy as sp

mp.mp.dps = 40
l1, l2, l3 = sp.symbols("l1 l2 l3")


def exact_mean(poly):
    p = sp.Poly(sp.expand(poly), l1, l2, l3)
    total = sp.Integer(0)
    for (a, b, c), coeff in p.terms():
        total += coeff * sp.Rational(2 * factorial(a) * factorial(b) * factorial(c), factorial(a + b + c + 2))
    return total


def invariants(degree):
    s2 = l1 * l2 + l2 * l3 + l3 * l1
    s3 = l1 * l2 * l3
    return [s2**i * s3**j for i in range(degree // 2 + 1) for j in range(degree // 3 + 1) if 2 * i + 3 * j <= degree]


def orbit_points(kind, params):
    if kind == "S3":
        return [(mp.mpf(1) / 3,) * 3]
    if kind == "S21":
        (a,) = params
        c = 1 - 2 * a
        return [(a, a, c), (a, c, a), (c, a, a)]
    a, b = params
    c = 1 - a - b
    return sorted(set(itertools.permutations((a, b, c))), key=lambda t: (t[1], t[2]))


def n_params(kind):
    return {"S3": 0, "S21": 1, "S111": 2}[kind]


def solve(name, degree, orbits, guess):
    """orbits: list of kinds; guess: flat list [w, params...] per orbit (weights normalised to sum 1)."""
    polys = invariants(degree)
    targets = [mp.mpf(sp.Rational(exact_mean(q)).p) / sp.Rational(exact_mean(q)).q for q in polys]
    funcs = [sp.lambdify((l1, l2, l3), q, "mpmath") for q in polys]
    assert len(polys) == len(guess), (name, len(polys), len(guess))

    def unpack(x):
        out, k = [], 0
        for kind in orbits:
            w = x[k]
            params = x[k + 1 : k + 1 + n_params(kind)]
            k += 1 + n_params(kind)
            out.append((kind, w, params))
        return out

    def residual(*x):
        res = []
        for f, t in zip(funcs, targets):
            s = mp.mpf(0)
            for kind, w, params in unpack(x):
                pts = orbit_points(kind, params)
                s += w / len(pts) * sum(f(*p) for p in pts)
            res.append(s - t)
        return res

    x = mp.findroot(residual, [mp.mpf(g) for g in guess], tol=mp.mpf(10) ** -35, maxsteps=100)
    x = list(x) if len(guess) > 1 else [x]
    print(f"// {name}: degree {degree}, residual {mp.nstr(max(abs(r) for r in residual(*x)), 2)}")
    for kind, w, params in unpack(x):
        pts = orbit_points(kind, params)
        for p in pts:
            print(f"    ([{float(p[1])!r}, {float(p[2])!r}], {float(w / len(pts) / 2)!r}),  # {mp.nstr(p[1], 30)}, {mp.nstr(p[2], 30)}, {mp.nstr(w / len(pts) / 2, 30)}")


# Strang & Fix degree-3 rule: one S111 orbit, equal weights.
solve("strang_fix_p3", 3, ["S111"], [1.0, 0.659027622374092, 0.231933368553031])
# Dunavant degree 4: two S21 orbits.
solve("dunavant_p4", 4, ["S21", "S21"], [3 * 0.223381589678011, 0.445948490915965, 3 * 0.109951743655322, 0.091576213509771])
# Degree 5 (Radon): centroid and two S21 orbits.
solve("dunavant_p5", 5, ["S3", "S21", "S21"], [0.225, 3 * 0.132394152788506, 0.470142064105115, 3 * 0.125939180544827, 0.101286507323456])
# Dunavant degree 6: two S21 orbits and one S111 orbit.
solve(
    "dunavant_p6",
    6,
    ["S21", "S21", "S111"],
    [3 * 0.116786275726379, 0.249286745170910, 3 * 0.050844906370207, 0.063089014491502, 6 * 0.082851075618374, 0.053145049844817, 0.310352451033784],
)
# Dunavant degree 8: centroid, three S21 orbits and one S111 orbit.
solve(
    "dunavant_p8",
    8,
    ["S3", "S21", "S21", "S21", "S111"],
    [
        0.144315607677787,
        3 * 0.095091634267285, 0.459292588292723,
        3 * 0.103217370534718, 0.170569307751760,
        3 * 0.032458497623198, 0.050547228317031,
        6 * 0.027230314174435, 0.008394777409958, 0.263112829634638,
    ],
)
