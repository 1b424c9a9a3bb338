/*
 * silo_slice_3d.c - a vertical slice through the 3D silo's axis
 * (silo_slice_3d.h). The quarter silo lies in x, z >= 0 with the slip
 * symmetry faces x = 0 and z = 0; its first layer of points in z (the
 * points' centres at z = h / (2 ppc)) is a section through the orifice's
 * axis, drawn mirrored about x = 0 so that the whole orifice shows.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#define _POSIX_C_SOURCE 200809L /* popen, pclose */

#include "silo_slice_3d.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* slice.csv: the points of the slice, x, y (m), speed (m/s), material. */
static gm_status write_csv(const gm_domain *domain, const char *path,
                           double thickness) {
  size_t count = gm_domain_point_count(domain);
  double *fields = malloc(7 * (count + 1) * sizeof *fields);
  if (!fields)
    return GM_ERR_NO_MEMORY;
  double *x = fields, *v = fields + 3 * count, *id = v + 3 * count;
  gm_status status =
      gm_domain_get_field(domain, GM_FIELD_POSITION, x, 3 * count);
  if (status == GM_OK)
    status = gm_domain_get_field(domain, GM_FIELD_VELOCITY, v, 3 * count);
  if (status == GM_OK)
    status = gm_domain_get_field(domain, GM_FIELD_MATERIAL, id, count);
  FILE *csv = status == GM_OK ? fopen(path, "w") : NULL;
  if (csv) {
    fprintf(csv, "x_m,y_m,speed_m_s,material\n");
    for (size_t i = 0; i < count; i++) {
      const double *p = x + 3 * i, *u = v + 3 * i; /* m, m/s */
      if (p[2] < thickness)
        fprintf(csv, "%.6g,%.6g,%.6g,%.0f\n", p[0], p[1],
                sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]), id[i]);
    }
    fclose(csv);
  } else if (status == GM_OK) {
    fprintf(stderr, "cannot write %s\n", path);
  }
  free(fields);
  return status;
}

gm_status silo3d_write_slice(const gm_domain *domain, const char *dir,
                             double thickness, double orifice, double time) {
  char csv[1200];
  snprintf(csv, sizeof csv, "%s/slice.csv", dir);
  gm_status status = write_csv(domain, csv, thickness);
  if (status != GM_OK || system("command -v gnuplot > /dev/null 2>&1") != 0) {
    if (status == GM_OK)
      fprintf(stderr, "gnuplot not found: no slice.png (apt-get install "
                      "gnuplot-nox)\n");
    return status;
  }
  FILE *plot = popen("gnuplot", "w");
  if (!plot)
    return GM_OK;
  /* Material 0 is the fill, the others the rigid floor (and gate). */
  fprintf(plot, "set terminal pngcairo size 900,800 font 'sans,11'\n");
  fprintf(plot, "set output '%s/slice.png'\n", dir);
  fprintf(plot,
          "set title \"3D silo, vertical slice through the orifice's axis "
          "(z < %.3g m,\\nmirrored about x = 0) at t = %.2f s; orifice D = "
          "%g m\"\n",
          thickness, time, orifice);
  fprintf(plot, "set xlabel 'x (m)'\nset ylabel 'height y (m)'\n"
                "set size ratio -1\nset datafile separator ','\n");
  fprintf(plot, "set cblabel 'speed (m/s)'\nset cbrange [0:*]\n"
                "set palette rgb 33,13,10\nset key top center\n");
  fprintf(plot, "set arrow from %g,0 to %g,0 nohead lw 3 lc rgb 'red' front\n",
          -0.5 * orifice, 0.5 * orifice);
  fprintf(plot,
          "plot '%s' every ::1 using ($4 == 0 ? $1 : 1/0):2:3 with points "
          "pt 5 ps 0.5 lc palette notitle, "
          "'' every ::1 using ($4 == 0 ? -$1 : 1/0):2:3 with points pt 5 "
          "ps 0.5 lc palette notitle, "
          "'' every ::1 using ($4 != 0 ? $1 : 1/0):2 with points pt 5 ps 0.5 "
          "lc rgb 'gray40' title 'rigid floor (one cell)', "
          "'' every ::1 using ($4 != 0 ? -$1 : 1/0):2 with points pt 5 ps "
          "0.5 lc rgb 'gray40' notitle, "
          "1/0 with lines lw 3 lc rgb 'red' title 'orifice'\n",
          csv);
  if (pclose(plot) != 0)
    fprintf(stderr, "gnuplot failed on slice.png\n");
  return GM_OK;
}
