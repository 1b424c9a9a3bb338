/*
 * silo_discharge_3d.h - the orifice of wieckowski1999_silo_discharge on the
 * grid: which floor cells of the 3D quarter silo are rigid, and the open
 * (not held) floor nodes of the orifice in 3D and in axisymmetry, with the
 * area they open (docs/3d.md, "Silo discharge through a circular orifice").
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef SILO_DISCHARGE_3D_H
#define SILO_DISCHARGE_3D_H

/* Whether floor node (a, b) (at x = a h, z = b h) of the 3D quarter silo
 * is open, the orifice being `holes` = D / 2h cells in radius about the
 * corner x = z = 0. */
int silo3d_open_node(long a, long b, long holes);

/* Whether floor cell (i, k) (x in [i h, (i + 1) h), z likewise) is rigid:
 * none of its corner nodes open. */
int silo3d_rigid_cell(long i, long k, long holes);

/* The open floor nodes of the orifice (3D: in the quarter; axisymmetric:
 * on the radius) into *nodes, and the area they open in units of h^2 for
 * the full orifice: the integral of the shape functions' sum over the open
 * nodes (the flow through the floor plane of a uniform nodal velocity),
 * to compare with pi D^2 / 4. */
double silo3d_open_area(int dim3, long holes, long *nodes);

#endif
