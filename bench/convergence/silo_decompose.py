#!/usr/bin/env python3
"""Decomposes the slot-silo discharge rate into centre velocity, centre
density and effective width, from the --profile output of
wieckowski1999_silo_discharge (docs/convergence.md sec. 25).

usage: silo_decompose.py LABEL PROFILE [LABEL PROFILE ...]

For each profile (one grid or setting) and each band (y = 0, D/2, D, the
bands of --profile, 0.025 m high) it prints one CSV row:
  Q        the full slot's mass flux through the band, 2 sum(-flux) dx,
           kg/(m s);
  Q_J      the same with each bin's points at their own density rho0/J
           (flux / filled): the rate the material's volume carries,
           without the mass of overlapping points, kg/(m s);
  rho_c    the areal density in the centre, x < D/12 (the first bin
           where it is wider), kg/m^3 (mass over
           area: plain points that overlap count twice);
  filled_c the points' current volume over the area there (1 where they
           tile the plane; > 1 where they overlap), and J_c = V / V0 of
           those points: rho_c = rho0 filled_c / J_c;
  v_c      the mass-weighted downward velocity there, m/s;
  W_eff    Q / (rho_c v_c), m: the width a plug of the centre's flux
           density would need (a half-ellipse velocity over the opening
           and a uniform density would give pi/4 D = 0.236 m);
  W_v      2 sum(v / v_c) dx, m: the same with the density taken uniform
           (the velocity profile's own width), and c_rho = W_eff / W_v,
           the flux-weighted density relative to the centre's;
  x50, x10 the half-widths, m, where the flux density falls to 50 % and
           10 % of the centre's (linear between bin centres);
  Q_in, Q_out  the flux through |x| < D/4 and D/4 <= |x| < D/2, kg/(m s).
Then for successive rows of the same band: the change of ln Q and its
shares ln(rho_c), ln(v_c), ln(W_eff) (they add up to ln Q exactly).
Last, from PROFILE_axis.csv (the column x < D/12 in bins 0.0125 m high),
one row per profile: the downward velocity in the lowest bin (v_0) and at
y = D/2 and D, h_a = v_0^2 / (2 g) (the height of a free fall from rest
that gives v_0), the share of the free fall g D gained between y = D and
the orifice, (v_0^2 - v_D^2) / (2 g D), and the mean pressure at y = D/4,
D/2 and D (Pa)."""
import math
import sys

from silo_profile import D, G, read_axis, read_bands


def read(path):
    """Bands {height: [(x, rho, vy, flux, filled, ratio), ...]} by x."""
    return {h: [(r[1], r[3], r[4], r[5], r[6], r[7]) for r in rows]
            for h, rows in read_bands(path).items()}


def crossing(rows, level):
    """The outermost x where -flux falls below level (linear between bin
    centres, scanning from the wall inwards)."""
    pairs = list(zip(rows, rows[1:]))
    for (x0, _, _, f0, _, _), (x1, _, _, f1, _, _) in reversed(pairs):
        if -f1 < level <= -f0:
            return x0 + (x1 - x0) * (-f0 - level) / (f0 - f1 + 1e-300)
    return float("nan")


def measures(rows):
    dx = rows[1][0] - rows[0][0]  # m, bin width
    centre = [r for r in rows if r[0] - 0.5 * dx < D / 12 - 1e-9]
    rho_c = sum(r[1] for r in centre) / len(centre)
    flux_c = -sum(r[3] for r in centre) / len(centre)
    v_c = flux_c / rho_c
    filled_c = sum(r[4] for r in centre) / len(centre)
    j_c = filled_c / sum(r[4] / r[5] for r in centre) * len(centre)
    q = -2 * sum(r[3] for r in rows) * dx
    q_vol = -2 * sum(r[3] / r[4] for r in rows if r[4] > 0) * dx
    q_in = -2 * sum(r[3] for r in rows if r[0] < D / 4) * dx
    q_out = -2 * sum(r[3] for r in rows if D / 4 <= r[0] < D / 2) * dx
    w_v = 2 * sum(max(-r[2], 0.0) for r in rows) * dx / v_c
    w_eff = q / (rho_c * v_c)
    return dict(Q=q, Q_J=q_vol, rho_c=rho_c, filled_c=filled_c, J_c=j_c, v_c=v_c, W_eff=w_eff, W_v=w_v,
                c_rho=w_eff / w_v, x50=crossing(rows, 0.5 * flux_c),
                x10=crossing(rows, 0.1 * flux_c), Q_in=q_in, Q_out=q_out)


KEYS = ["Q", "Q_J", "rho_c", "filled_c", "J_c", "v_c", "W_eff", "W_v", "c_rho", "x50", "x10", "Q_in",
        "Q_out"]
args = sys.argv[1:]
runs = [(label, read(path)) for label, path in zip(args[0::2], args[1::2])]
print("label,height_m," + ",".join(KEYS) +
      ",dlnQ,share_rho_c,share_v_c,share_W_eff")
for height in (0.0, 0.5 * D, D):
    previous = None
    for label, bands in runs:
        m = measures(bands[height])
        tail = ["", "", "", ""]
        if previous:
            dq = math.log(m["Q"] / previous["Q"])
            tail = [dq] + [math.log(m[k] / previous[k]) / dq
                           for k in ("rho_c", "v_c", "W_eff")]
        print(",".join([label, f"{height:g}"] +
                       [f"{m[k]:.4g}" for k in KEYS] +
                       [f"{v:.3f}" if v != "" else "" for v in tail]))
        previous = m


def axis_row(label, path):
    rows = read_axis(path)

    def at(y, k):  # the bin whose centre is nearest y
        return min(rows, key=lambda r: abs(r[0] - y))[k]
    v0, vh, vd = -rows[0][3], -at(D / 2, 3), -at(D, 3)
    # pressure: mean over the bins within 0.025 m of the height (noisy)
    def p(y):
        near = [r[5] for r in rows if abs(r[0] - y) <= 0.025]
        return sum(near) / len(near)
    return [label, v0, vh, vd, v0 * v0 / (2 * G),
            (v0 * v0 - vd * vd) / (2 * G * D), p(D / 4), p(D / 2), p(D)]


print("label,axis_v0_m_s,axis_v_half_D,axis_v_D,h_a_m,free_fall_share_D_to_0,"
      "p_quarter_D_Pa,p_half_D_Pa,p_D_Pa")
for (label, _), path in zip(runs, args[1::2]):
    print(",".join(f"{v:.4g}" if isinstance(v, float) else v
                   for v in axis_row(label, path)))
