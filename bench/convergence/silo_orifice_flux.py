#!/usr/bin/env python3
"""Cumulative discharge rate across the orifice band from the silo
example's --profile CSVs (docs/convergence.md sec. 37).

For each file: the band at height 0 (the orifice), the flux density summed
from the axis outwards, W(x) = sum over bins with x_bin < f R of
(-flux) * bin width, printed at f = 0.25, 0.5, 0.75, 0.9, 1.0, 1.2 of
R = D/2, and the mass-weighted v_y at f = 0.05, 0.5, 0.9. In the plane
W is kg/(m s) for the half silo (x >= 0); in axisymmetry a point's mass
is its whole ring's, so W is the ring's rate in kg/s and W(1.2 R) is the
sinks' rate (to the band average). Comparing grids shows where a rate
grows: in a band of fixed cells at the edge, or across the jet.

usage: silo_orifice_flux.py PROFILE.csv [PROFILE.csv ...]
"""
import sys

FRACTIONS = (0.25, 0.5, 0.75, 0.9, 1.0, 1.2)


def orifice_band(path):
    """(cell m, D m, [(x m, flux kg/(m^2 s), v_y m/s)]) of the band y = 0."""
    cell = orifice = None
    rows = []
    with open(path) as csv:
        for line in csv:
            if line.startswith('#'):  # "# cell C m, ppc N, D D m, ..."
                words = line.replace(',', ' ').split()
                cell = float(words[2])
                orifice = float(words[words.index('D') + 1])
                continue
            if line.startswith('height'):
                continue
            v = line.strip().split(',')
            if float(v[0]) == 0.0:
                rows.append((float(v[1]), float(v[5]), float(v[4])))
    return cell, orifice, rows


def main(paths):
    print('file, cell (m): W at x/R =', ', '.join(map(str, FRACTIONS)),
          '| v_y (m/s) at x/R = 0.05, 0.5, 0.9')
    for path in paths:
        cell, orifice, rows = orifice_band(path)
        radius = 0.5 * orifice
        width = rows[1][0] - rows[0][0]  # m, bin width
        cumulative = [sum(-q * width for x, q, _ in rows
                          if x < f * radius + 1e-12) for f in FRACTIONS]

        def speed(f):
            return min(rows, key=lambda r: abs(r[0] - f * radius))[2]

        print(path.split('/')[-1], cell, ' '.join('%.2f' % w for w in cumulative),
              '| %.3f %.3f %.3f' % (speed(0.05), speed(0.5), speed(0.9)))


if __name__ == '__main__':
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
