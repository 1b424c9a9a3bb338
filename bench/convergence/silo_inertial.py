#!/usr/bin/env python3
"""Inertial number I = gammadot d / sqrt(p / rho_s) estimated from the
--profile output of wieckowski1999_silo_discharge --grain d
(docs/convergence.md sec. 27): the profiles hold bin means, not the
points' own I (the library keeps I as a material state the API does not
read), so this is an estimate from the mean velocity field.

usage: silo_inertial.py GRAIN_M LABEL PROFILE [LABEL PROFILE ...]

Bands y = 0, D/2, D (0.025 m high, bins in x): gammadot = |d v_y / dx|
(central differences of the bin means; the shear across the core's
edge), p = the bin's mean pressure over its share of points with p > 0
(the stress-free points carry none). Axis column x < D/12 (bins 0.0125 m
in y): gammadot = 2 |d v_y / dy| (the planar extension along the axis,
sqrt(2 D':D') with d v_x/dx = -d v_y/dy). Printed per profile and band:
the largest I where p > 50 Pa and v_y > 10 % of the centre's, where it
is, and the mass-free estimate at the core edge (x50). Jop's curve of the
example (mu_s = sin 25 deg, mu_2 = mu_s + 0.2616, I_0 = 0.279) is well
posed (Barker & Gray 2017 eq 3.9, C(I) < 0, lib/materials/mu_i.c) only
for I_1 < I < I_2; both are printed (found here by bisection)."""
import math
import sys

from silo_profile import D, read_axis, read_bands

RHO_S = 2650.0
MU_S = math.sin(math.radians(25.0))
MU_2, I_0 = MU_S + (0.6435 - 0.3819), 0.279


def posedness(i):
    mu = MU_S + (MU_2 - MU_S) / (I_0 / i + 1.0)
    c = i * I_0 * (MU_2 - MU_S) / (I_0 + i) ** 2 / mu
    return 4 * c * c - 4 * c + mu * mu * (1 - 0.5 * c) ** 2


def root(lo, hi):
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        if (posedness(mid) > 0) == (posedness(lo) > 0):
            lo = mid
        else:
            hi = mid
    return hi


I1, I2 = root(1e-6, 0.1), root(0.1, 100.0)
grain = float(sys.argv[1])
args = sys.argv[2:]
print(f"# well posed for {I1:.4f} < I < {I2:.4f}; d = {grain} m")
print("label,band_y,I_max,x_at_max,gammadot_at_max,p_at_max,I_at_x50,x50")
for label, path in zip(args[0::2], args[1::2]):
    bands = read_bands(path)
    for h in sorted(bands):
        if h > D + 1e-9:
            continue
        rows = bands[h]
        v_c = -rows[0][4]
        best, x50 = None, None
        for a, b, c in zip(rows, rows[1:], rows[2:]):
            rate = abs((c[4] - a[4]) / (c[1] - a[1]))
            share = 1.0 - b[12]
            p = b[10] / share if share > 0 else 0.0
            if p > 50.0 and -b[4] > 0.1 * v_c:
                i = rate * grain / math.sqrt(p / RHO_S)
                if best is None or i > best[0]:
                    best = (i, b[1], rate, p)
                if x50 is None and -c[4] < 0.5 * v_c:
                    x50 = (i, b[1])
        print(",".join([label, f"{h:g}"] + [f"{v:.4g}" for v in best] +
                       [f"{v:.4g}" for v in (x50 or (0, 0))]))
    axis = read_axis(path)
    out = []
    for a, b, c in zip(axis, axis[1:], axis[2:]):
        if b[0] > D:
            break
        rate = 2 * abs((c[3] - a[3]) / (c[0] - a[0]))
        share = 1.0 - b[10]
        p = b[5] / share if share > 0 else 0.0
        if p > 50.0:
            out.append((rate * grain / math.sqrt(p / RHO_S), b[0], rate, p))
    best = max(out)
    print(",".join([label, "axis"] + [f"{v:.4g}" for v in best] +
                   [f"{out[0][0]:.4g}", f"{out[0][1]:.4g}"]))
