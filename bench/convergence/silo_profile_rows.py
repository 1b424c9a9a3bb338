#!/usr/bin/env python3
"""CSV rows of bench/convergence/silo_orifice_profile.csv from the
--profile output of wieckowski1999_silo_discharge (docs/convergence.md
sec. 14, 'Why the rate grows'). usage: silo_profile_rows.py LOG PROFILE ...
(pairs: the run's stdout and its --profile path; the axis file is
PROFILE_axis.csv)."""
import re
import sys

D, G = 0.3, 9.81  # m, m/s^2


def bands(path):
    rows = [l.split(",") for l in open(path)
            if not l.startswith(("#", "height"))]
    rows = [[float(v) for v in r] for r in rows]
    cell = float(open(path).readline().split()[2])
    out = {}
    for r in rows:
        out.setdefault(r[0], []).append(r)
    return cell, out


def row(log, path):
    text = open(log).read()
    rate = float(re.search(r"flow_rate_kg_m_s=([0-9.e+-]+)", text).group(1))
    win = re.search(r"10-25 %: ([0-9.e+-]+), 25-40 %: ([0-9.e+-]+)", text)
    cell, b = bands(path)
    orifice = b[0.0]
    w = orifice[1][1] - orifice[0][1]
    flux = {h: -2 * sum(r[5] * w for r in b[h]) for h in b}
    inner = -2 * sum(r[5] * w for r in orifice if r[2] < 0.25)
    outer = -2 * sum(r[5] * w for r in orifice if 0.25 <= r[2] < 0.5)
    per_volume = -2 * sum(r[5] / r[6] * w for r in orifice if r[6] > 0)
    inside = [r for r in orifice if r[2] < 0.5]
    filled = sum(r[6] for r in inside) / len(inside)
    rho_axis, v_axis = orifice[0][3], -orifice[0][4]
    missing = D - flux[0.0] / (rho_axis * v_axis)  # m
    at_d = b[D]
    axis_d = at_d[0][4]
    x90 = next(r[1] for r in at_d if r[4] > 0.9 * axis_d)
    x10 = next(r[1] for r in at_d if r[4] > 0.1 * axis_d)
    axis = [[float(v) for v in l.split(",")]
            for l in open(path + "_axis.csv") if not l.startswith("y_m")]
    low = axis[0][3]
    high = next(r[3] for r in axis if abs(r[0] - 0.50625) < 1e-6)
    share = (low ** 2 - high ** 2) / (2 * G * 0.5)
    return [cell, rate, win.group(1), win.group(2), flux[0.0], flux[0.15],
            flux[0.3], flux[0.6], inner, outer, v_axis, rho_axis, missing,
            missing / cell, filled, per_volume, x10 - x90, (x10 - x90) / cell,
            -high, share]


print("cell_m,rate_sink_kg_m_s,rate_10_25,rate_25_40,flux_y0,flux_y_half_D,"
      "flux_y_D,flux_y_2D,flux_inner_half,flux_outer_half,vy_axis_orifice_m_s,"
      "areal_density_axis_kg_m3,missing_width_m,missing_width_cells,"
      "filled_orifice,flux_rho0_over_J,transition_at_D_m,transition_at_D_cells,"
      "vy_axis_at_0.5m,free_fall_share_axis")
args = sys.argv[1:]
for log, path in zip(args[0::2], args[1::2]):
    print(",".join(f"{v:.4g}" if isinstance(v, float) else str(v)
                   for v in row(log, path)))
