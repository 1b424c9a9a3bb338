#!/usr/bin/env python3
"""band_width.py - the width of the shear bands in a toe_probe --band file,
for docs/convergence.md section 19 (issue 13).

usage: band_width.py FILE.csv CELL PPC HEIGHT [COLUMN] [X_MIN X_MAX]
                     [PROMINENCE]
  FILE.csv  toe_probe --band output (x_m, y_m, shear_rate, plastic_rate)
  CELL      cell size h (m); PPC points per cell per direction
  HEIGHT    the column's height H (m); lines at y = 0.2, 0.3, 0.4, 0.5 H
  COLUMN    plastic_rate (default) or shear_rate
  X_MIN X_MAX  the part of each line searched for bands (m, default 0.06
            to 0.14: the fan of failure surfaces behind the foot, short of
            the face where the foot's flow dominates)
  PROMINENCE  the least prominence of a band, as a fraction of its peak
            (default 0.5)

On each horizontal line the probe's points within half a point spacing
s = h / PPC of the line, sorted by x, give the rate profile (each point's
own value, no smoothing). A band is a local maximum whose prominence (the
peak less the higher of the two minima that bound it) is at least half
the peak (PROMINENCE); its width is the full width at half prominence, the crossings
linearly interpolated between points. The band's inclination theta is
taken from the nearest peak on the line two point spacings higher (tan
theta = 2 s / |dx|), and its width normal to itself is the horizontal
width times sin theta. Prints one row per line: y/H, bands found, the
median horizontal width (m and cells), the median inclination (deg) and
the median normal width (m and cells) and the median peak rate (1/s); then
the medians over all lines.
"""
import csv
import math
import statistics
import sys


def profile(points, y_line, spacing, column, x_min, x_max):
    row = [(x, v[column]) for (x, y), v in points
           if abs(y - y_line) < 0.5 * spacing and x_min <= x <= x_max]
    row.sort()
    return row


def peaks(row, prominence):
    """(peak rate, half-prominence width in m, peak x) of each band."""
    found = []
    for k in range(1, len(row) - 1):
        v = row[k][1]
        if not (v > row[k - 1][1] and v >= row[k + 1][1]):
            continue
        # the minima that bound the peak: walk down until the rate rises
        # above the peak (another, higher band) or the line ends
        left = k
        low_left = v
        j = k
        while j > 0 and row[j - 1][1] <= v:
            j -= 1
            low_left = min(low_left, row[j][1])
        right_low = v
        j = k
        while j < len(row) - 1 and row[j + 1][1] <= v:
            j += 1
            right_low = min(right_low, row[j][1])
        base = max(low_left, right_low)
        if v - base < prominence * v or v <= 0.0:
            continue
        half = base + 0.5 * (v - base)
        # crossings of the half level either side
        j = k
        while j > 0 and row[j - 1][1] > half:
            j -= 1
        if j == 0:
            continue
        x0, v0 = row[j - 1]
        x1, v1 = row[j]
        x_left = x0 + (half - v0) / (v1 - v0) * (x1 - x0)
        j = k
        while j < len(row) - 1 and row[j + 1][1] > half:
            j += 1
        if j == len(row) - 1:
            continue
        x0, v0 = row[j]
        x1, v1 = row[j + 1]
        x_right = x0 + (v0 - half) / (v0 - v1) * (x1 - x0)
        found.append((v, x_right - x_left, row[k][0]))
    return found


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    path, cell, ppc, height = (sys.argv[1], float(sys.argv[2]),
                               int(sys.argv[3]), float(sys.argv[4]))
    column = 1 if len(sys.argv) > 5 and sys.argv[5] == "shear_rate" else 0
    x_min, x_max = ((float(sys.argv[6]), float(sys.argv[7]))
                    if len(sys.argv) > 7 else (0.06, 0.14))
    prominence = float(sys.argv[8]) if len(sys.argv) > 8 else 0.5
    spacing = cell / ppc
    points = []
    with open(path) as f:
        for r in csv.DictReader(f):
            points.append(((float(r["x_m"]), float(r["y_m"])),
                           (float(r["plastic_rate"]), float(r["shear_rate"]))))
    all_h, all_n, all_r = [], [], []
    print("y/H,bands,width_h_m,width_h_cells,theta_deg,width_n_m,"
          "width_n_cells,peak_rate")
    for fraction in (0.2, 0.3, 0.4, 0.5):
        y = fraction * height
        row = profile(points, y, spacing, column, x_min, x_max)
        above = profile(points, y + 2 * spacing, spacing, column,
                        x_min - 0.05, x_max + 0.05)
        upper = [x for _, _, x in peaks(above, prominence)]
        widths, normals, angles, rates = [], [], [], []
        for rate, width, x in peaks(row, prominence):
            rates.append(rate)
            widths.append(width)
            if upper:
                dx = min(abs(u - x) for u in upper)
                theta = math.atan2(2 * spacing, dx)
                angles.append(math.degrees(theta))
                normals.append(width * math.sin(theta))
        all_h += widths
        all_n += normals
        all_r += rates
        if widths:
            wh = statistics.median(widths)
            th = statistics.median(angles) if angles else float("nan")
            wn = statistics.median(normals) if normals else float("nan")
            print("%.1f,%d,%.4f,%.2f,%.0f,%.4f,%.2f,%.1f" %
                  (fraction, len(widths), wh, wh / cell, th, wn, wn / cell,
                   statistics.median(rates)))
        else:
            print("%.1f,0,,,,,," % fraction)
    if all_h:
        wh = statistics.median(all_h)
        wn = statistics.median(all_n) if all_n else float("nan")
        print("all,%d,%.4f,%.2f,,%.4f,%.2f,%.1f" %
              (len(all_h), wh, wh / cell, wn, wn / cell,
               statistics.median(all_r)))


main()
