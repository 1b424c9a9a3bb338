#!/usr/bin/env python3
"""The flat slot silo's funnel under refinement, from the --profile output of
wieckowski1999_silo_discharge (docs/convergence.md sec. 33).

usage: silo_funnel.py LABEL PROFILE [LABEL PROFILE ...]

Per profile and band height (y = 0, 0.15, 0.3, 0.6 m):
  flux   the mass flux integrated across the silo, both halves, kg/(m s):
         it must equal the sinks' rate in a steady window;
  v_y    the point velocity averaged over 0.05 m bins from the axis, m/s;
  p      the mean pressure over the same bins, Pa;
  alt    the cell-scale alternation of v_y, the mean over bins of
         |v_i - (v_(i-1) + v_(i+1)) / 2| (m/s) for 0.15 <= x < 0.3 m: FLIP's
         null-space pattern, visible only where the bins are one cell wide.
"""
import csv
import sys

BIN = 0.05  # m, the coarse bins of the table


def load(path):
    """Rows of a profile CSV grouped by band height."""
    with open(path) as f:
        lines = [line for line in f if not line.startswith('#')]
    bands = {}
    for row in csv.DictReader(lines):
        values = {k: float(v) for k, v in row.items()}
        bands.setdefault(values['height_m'], []).append(values)
    return bands


def coarse(rows, key):
    """The mean of key over BIN-wide bins from the axis."""
    sums, counts = {}, {}
    for r in rows:
        k = int(r['x_m'] / BIN)
        sums[k] = sums.get(k, 0.0) + r[key]
        counts[k] = counts.get(k, 0) + 1
    return [sums[k] / counts[k] for k in sorted(sums)]


def alternation(rows, low=0.15, high=0.3):
    v = [r['vy_m_s'] for r in rows]
    x = [r['x_m'] for r in rows]
    a = [abs(v[i] - 0.5 * (v[i - 1] + v[i + 1]))
         for i in range(1, len(v) - 1) if low <= x[i] < high]
    return sum(a) / len(a) if a else float('nan')


def main(argv):
    if len(argv) < 3 or len(argv) % 2 == 0:
        sys.exit(__doc__)
    profiles = [(argv[i], load(argv[i + 1])) for i in range(1, len(argv), 2)]
    for height in sorted(profiles[0][1]):
        print(f"y = {height} m")
        for label, bands in profiles:
            rows = bands.get(height, [])
            if len(rows) < 2:
                continue
            width = rows[1]['x_m'] - rows[0]['x_m']  # m, the profile's bin
            flux = 2.0 * width * sum(r['flux_kg_m2_s'] for r in rows)
            vy = ' '.join(f"{v:7.3f}" for v in coarse(rows, 'vy_m_s'))
            p = ' '.join(f"{v:7.0f}" for v in coarse(rows, 'pressure_Pa'))
            print(f"  {label:12s} flux {-flux:7.1f}  alt {alternation(rows):.3f}")
            print(f"  {'':12s} v_y {vy}")
            print(f"  {'':12s} p   {p}")


if __name__ == '__main__':
    main(sys.argv)
