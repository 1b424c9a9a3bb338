/*
 * silo_slice_3d.h - a vertical slice through the axis of the 3D silo of
 * wieckowski1999_silo_discharge, as CSV and as a PNG drawn by gnuplot
 * (issue 16 item 4: a picture a person can read).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef SILO_SLICE_3D_H
#define SILO_SLICE_3D_H

#include <granmpm.h>

/* Writes <dir>/slice.csv (x, y in m, speed in m/s, material index) with
 * the points whose z lies below `thickness` (m: the layer of points next to
 * the symmetry face z = 0, a slice through the orifice's axis) and draws
 * <dir>/slice.png from it, the quarter mirrored about x = 0, coloured by
 * speed. `orifice` (m) marks the hole, `time` (s) is the title's. Without
 * gnuplot only the CSV. Returns GM_OK or the status of a failed read. */
gm_status silo3d_write_slice(const gm_domain *domain, const char *dir,
                             double thickness, double orifice, double time);

#endif
