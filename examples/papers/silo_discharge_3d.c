/*
 * silo_discharge_3d.c - the orifice of wieckowski1999_silo_discharge on the
 * grid (silo_discharge_3d.h).
 *
 * The rigid floor holds every node its points touch (lib/boundaries/rigid.c;
 * linear shapes: the nodes of the point's cell), so the orifice the
 * material sees is the set of open floor nodes, not the hole cut in the
 * layer of points. In the planar and axisymmetric silos the orifice edge
 * lies on a node line, r = D/2, which the floor holds: the open nodes are
 * r = 0, h, ..., D/2 - h, and the velocity falls linearly to 0 over the
 * last cell, an open radius of about D/2 - h/2 (at D/6 the shape
 * functions' sum over the open nodes covers 19.9 h^2, the disc of radius
 * 2.5 h 19.6 h^2). A circle cannot lie on the node lines of a square grid:
 * the 3D floor opens the nodes within that radius, r < D/2 - h/2 (in
 * integers 4 (a^2 + b^2) < (2 D/2h - 1)^2, exact), the same rule as the
 * planar and axisymmetric floors on their line (every threshold in
 * (D/2 - h, D/2] gives their nodes). Measured in docs/3d.md: keeping the
 * floor points whose own centre lies outside r = D/2, the first version,
 * held every node of the cells the circle cuts (6 open nodes at D/6
 * instead of 8, 13 h^2 against the axisymmetric 19.9 h^2).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "silo_discharge_3d.h"

static const double PI = 3.14159265358979323846;

int silo3d_open_node(long a, long b, long holes) {
  return 4 * (a * a + b * b) < (2 * holes - 1) * (2 * holes - 1);
}

/* The corner nearest the axis opens first (openness falls with the
 * radius), so a cell is rigid exactly when its corner (i, k) is held; the
 * open nodes are then exactly those of silo3d_open_node (each of a node's
 * cells has a corner at least as near the axis). */
int silo3d_rigid_cell(long i, long k, long holes) {
  return !silo3d_open_node(i, k, holes);
}

double silo3d_open_area(int dim3, long holes, long *nodes) {
  double area = 0.0; /* h^2 */
  *nodes = 0;
  if (!dim3) { /* the rings r = a h: hat(r) 2 pi r integrated */
    for (long a = 0; a < holes; a++, ++*nodes)
      area += a == 0 ? PI / 3.0 : 2.0 * PI * (double)a;
    return area;
  }
  for (long a = 0; a < holes; a++)
    for (long b = 0; b < holes; b++)
      if (silo3d_open_node(a, b, holes)) {
        /* a node on a symmetry face has half its support in the quarter */
        area += 4.0 * (a == 0 ? 0.5 : 1.0) * (b == 0 ? 0.5 : 1.0);
        ++*nodes;
      }
  return area;
}
