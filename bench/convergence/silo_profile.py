"""Readers of the --profile output of wieckowski1999_silo_discharge, shared
by silo_stresses.py, silo_decompose.py and silo_inertial.py
(docs/convergence.md sec. 25-27): PROFILE holds the bands (one row per
band height and bin in x), PROFILE_axis.csv the column x < D/12 in bins
in y. Every row is read as floats, in the example's column order (its
header lines, '#' and 'height' / 'y', are skipped)."""

D = 0.3  # m, the example's orifice
G = 9.81  # m/s^2


def read_bands(path):
    """{band height (m): [row, ...] sorted by x (column 1)}."""
    bands = {}
    for line in open(path):
        if line.startswith(("#", "height")):
            continue
        row = [float(t) for t in line.split(",")]
        bands.setdefault(row[0], []).append(row)
    for rows in bands.values():
        rows.sort(key=lambda r: r[1])
    return bands


def read_axis(path):
    """The rows of PROFILE_axis.csv, from the orifice up (column 0: y)."""
    return [[float(t) for t in line.split(",")]
            for line in open(path + "_axis.csv") if not line.startswith("y")]
