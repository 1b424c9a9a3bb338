#!/bin/sh
# tests/scripts/silo_3d_axisym.sh - issue 16 item 3: silo discharge through
# a circular orifice in 3D (examples/papers/wieckowski1999_silo_discharge
# --geometry 3d: a quarter square silo, the orifice centred on the corner
# where the slip symmetry faces x = 0 and z = 0 meet) against the library's
# own axisymmetric silo of the same D, B, H, cell and points per cell, which
# the example runs after the 3D one in the same process. D = 0.3 m on
# 0.05 m cells (D/6), 2 x 2 (x 2) points per cell, filled to one full width
# (--fill 1, half the example's default) so that it runs in about 2 min of
# one core, the longest of these scripts (a fill of 0.5 widths is no
# Beverloo scene: there the rates fall by half over the window).
#
# Asserts the 3D rate (4 x the quarter's) within 5 % of the axisymmetric
# one, the issue's bound. Measured (docs/3d.md, "Silo discharge through a
# circular orifice"): 56.27 against 56.42 kg/s (-0.27 %). Not a converged
# agreement: at D/8 (too long for make check, 6.5 min of CPU) 70.13 against
# 78.88 kg/s (-11.1 %), where the 3D floor's open area is 4.5 % below the
# axisymmetric one (at D/6 5.5 % above): this test guards the floor and
# sinks at D/6, not the issue's bound on every cell.
# The first 3D floor (every floor point kept whose own centre lies outside
# the circle: 6 open floor nodes in the quarter instead of 8, the nodes of
# every cell the circle cuts held) and its sink below the floor layer gave
# 13.69 kg/s (-76 %), and this test fails on them; the floor alone (with
# the old sink) 47.87 kg/s (-15 %).
# SPDX-License-Identifier: BSD-2-Clause
set -eu
# About 2 min of CPU here, more than 15 under AddressSanitizer (the 3D
# silo alone, 2026-11-28): a slow case (tests/README.md, "Slow cases"),
# skipped when CK_EXCLUDE_TAGS names the tag slow, as the CI's sanitize and
# distcheck stages do (the 3D sinks, rigid points and walls it uses run
# under the sanitizers in test_sources, test_cpdi_3d and test_walls_3d); the
# check stage runs it.
. "$(dirname "$0")/slow_case.sh" # skip if slow is excluded; $scratch
./examples/papers/wieckowski1999_silo_discharge --geometry 3d --cell 0.05 \
  --orifice 0.3 --fill 1 --t-end 0.01 --out '' --quiet >"$scratch/out" 2>&1 ||
  true
awk '
  /^RESULT flow_rate_3d_vs_axisym_kg_s=/ {
    split($2, v, "="); split($3, r, "=")
    rate = v[2]; axisym = r[2]
  }
  END {
    if (rate == "" || axisym <= 0) {
      print "FAIL: the example gave no rate"; exit 1 }
    off = rate / axisym - 1
    printf "3D %.4g kg/s, axisymmetric %.4g kg/s: %+.2f %% (tolerance 5 %%)\n",
      rate, axisym, 100 * off
    exit (off < -0.05 || off > 0.05)
  }' "$scratch/out" || {
  cat "$scratch/out"
  exit 1
}
