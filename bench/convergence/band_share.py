#!/usr/bin/env python3
"""band_share.py - how concentrated the plastic flow is, for
docs/convergence.md section 19: the share of the plastic shear rate summed
over a window of the column carried by its most active 20 % of points
(0.2 for uniform flow; towards 1 as the flow gathers in thin bands), a
measure that needs no band to be picked out.

usage: band_share.py FILE.csv HEIGHT [X_MIN X_MAX Y_MAX_FRACTION]
  FILE.csv  toe_probe --band output; HEIGHT the column's height H (m)
  window    X_MIN <= x <= X_MAX (m, default 0.06 to 0.14) and
            y <= Y_MAX_FRACTION H (default 0.5): the fan of failure
            surfaces behind the foot
Every point has the same volume at the start (one fill), so a plain sum
over points weights them alike. Prints: points, share of the top 20 %.
"""
import csv
import sys

if len(sys.argv) < 3:
    sys.exit(__doc__)
height = float(sys.argv[2])
x_min, x_max, y_max = ((float(sys.argv[3]), float(sys.argv[4]),
                        float(sys.argv[5])) if len(sys.argv) > 5
                       else (0.06, 0.14, 0.5))
rates = []
with open(sys.argv[1]) as f:
    for r in csv.DictReader(f):
        x, y = float(r["x_m"]), float(r["y_m"])
        if x_min <= x <= x_max and y <= y_max * height:
            rates.append(max(0.0, float(r["plastic_rate"])))
rates.sort(reverse=True)
top = rates[:max(1, len(rates) // 5)]
total = sum(rates)
print("%d,%.3f" % (len(rates), sum(top) / total if total > 0 else 0.0))
