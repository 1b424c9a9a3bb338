#!/usr/bin/env python3
"""The stresses that hold the slot silo's flowing core back, from the
--profile output of wieckowski1999_silo_discharge (docs/convergence.md
sec. 27).

usage: silo_stresses.py LABEL PROFILE [LABEL PROFILE ...]

Part 1, the core's edge: for the bands at y = D/2 and y = D, one row per
profile with the centre's downward velocity v_c (x < D/12), the half-width
x50 where v_y falls to half of v_c, and at the bin nearest x50 and at the
bin of the largest |sigma_xy| inside x < D: sigma_xy (Pa), the mean
pressure p (Pa), |sigma_xy| / p and the mobilised share q / (m p) of the
Drucker-Prager cone (1 at yield; at yield in pure shear |sigma_xy| / p =
m / sqrt(3) = 0.498 for phi = 25 deg).

Part 2, the vertical momentum balance of the axis column x < D/12 (bins
0.0125 m high; PROFILE_axis.csv), per unit mass, integrated from y = D
down to the lowest bin:
  KE    (v_0^2 - v_D^2) / 2, the kinetic energy gained, J/kg;
  G     g (y_D - y_0), what gravity gives;
  P     -int (1/rho) d sigma_yy/dy dy (y_0 .. y_D): what the vertical
        normal stress gives (> 0: pushes the core down, the pressure
        falling toward the orifice);
  S     -int (1/rho) d sigma_xy/dx dy, with d sigma_xy/dx on the axis from
        the two columns x < D/12 and D/12 <= x < D/6: (sigma_xy(next) -
        sigma_xy(axis)) / (D/12) (< 0: the slower sides hold the core
        back);
(the balance is printed from the lowest bin to y = D and to y = 2D;)
  R     KE - (G + P + S), the residual: the steady Eulerian balance
        v dv/dy = -g + (1/rho)(d sigma_yy/dy + d sigma_xy/dx) closes
        only as well as bin means of point stresses stand for the grid's
        divergence (and the flow is not exactly steady).
Shares are of G = g (top - y_0).

Part 3, the stress-free zone above the orifice (profiles that have the
stress-free column): in the axis column, the mass share of points with
p <= 0 in the lowest bin, its mass-weighted mean below D/2, and the
highest y below 2D where it (mean of two bins) exceeds 10 %, in m and
in cells."""
import math
import sys

from silo_profile import D, G, read_axis, read_bands


def edge(rows):
    dx = rows[1][1] - rows[0][1]
    centre = [r for r in rows if r[1] - 0.5 * dx < D / 12 - 1e-9]
    v_c = -sum(r[4] * r[3] for r in centre) / sum(r[3] for r in centre)
    x50 = None
    for a, b in zip(rows, rows[1:]):
        if -a[4] >= 0.5 * v_c > -b[4]:
            x50 = a[1] + (b[1] - a[1]) * (-a[4] - 0.5 * v_c) / (b[4] - a[4])
            break
    near = min(rows, key=lambda r: abs(r[1] - x50))
    inner = [r for r in rows if r[1] < D and r[10] > 0]
    peak = max(inner, key=lambda r: abs(r[9]))

    def cols(r):
        return [r[1], r[9], r[10], abs(r[9]) / r[10], r[11], -r[4]]
    loose = [sum(r[12] * r[3] for r in centre) / sum(r[3] for r in centre),
             near[12]] if len(near) > 12 else [-1, -1]
    return [v_c, x50] + cols(near) + cols(peak) + loose


def balance(path, top):
    rows = read_axis(path)
    rows = [r for r in rows if r[2] > 0 and r[0] <= top + 1e-9]
    ke = 0.5 * (rows[0][3] ** 2 - rows[-1][3] ** 2)
    g = G * (rows[-1][0] - rows[0][0])
    p = s = 0.0
    for a, b in zip(rows, rows[1:]):
        rho = 0.5 * (a[2] + b[2])
        dy = b[0] - a[0]
        p -= (b[6] - a[6]) / rho
        grad_a = (a[9] - a[7]) / (D / 12)
        grad_b = (b[9] - b[7]) / (D / 12)
        s -= 0.5 * (grad_a + grad_b) / rho * dy
    return [ke, g, p, s, ke - g - p - s, -rows[0][3], -rows[-1][3],
            rows[-1][6], rows[0][6]]


args = sys.argv[1:]
runs = list(zip(args[0::2], args[1::2]))
print("# part 1: core edge; label,y,v_c,x50,[x,sxy,p,|sxy|/p,mobilised,v]"
      " at x50 then at max |sxy|, then the stress-free mass share in the"
      " centre x < D/12 and at x50 (-1: profile without it)")
for label, path in runs:
    b = read_bands(path)
    for h in sorted(b):
        if 0 < h <= D + 1e-9:
            print(",".join([label, f"{h:g}"] + [f"{v:.4g}" for v in edge(b[h])]))
print("# part 2: axis column balance y_0..top (D, 2D), J/kg and shares of"
      " g (top - y_0); label@top,KE,G,P,S,R,KE/G,P/G,S/G,R/G,v_0,v_top,"
      "syy_top,syy_0")
for label, path in runs:
    for top in (D, 2 * D):
        ke, g, p, s, r, v0, vd, syd, sy0 = balance(path, top)
        print(",".join([label + f"@{top / D:g}D"] +
                       [f"{v:.4g}" for v in (ke, g, p, s, r)] +
                       [f"{v / g:.3f}" for v in (ke, p, s, r)] +
                       [f"{v:.4g}" for v in (v0, vd, syd, sy0)]))
print("# part 3: stress-free points (p <= 0) in the axis column x < D/12;"
      " label,share in the lowest 0.0125 m,mean share over 0..D/2,"
      "y where the share (mean of two bins) last exceeds 10 % (m),"
      "same in cells")
for label, path in runs:
    rows = read_axis(path)
    if len(rows[0]) < 11:
        continue
    low = [r for r in rows if r[0] < D / 2 and r[2] > 0]
    mean = sum(r[10] * r[2] for r in low) / sum(r[2] for r in low)
    top = 0.0
    for a, b in zip(rows, rows[1:]):
        if b[0] < 2 * D and 0.5 * (a[10] + b[10]) > 0.1:
            top = b[0]
    with open(path) as f:
        cell = float(f.readline().split()[2])
    print(",".join([label, f"{rows[0][10]:.3f}", f"{mean:.3f}",
                    f"{top:.4g}", f"{top / cell:.3g}"]))
