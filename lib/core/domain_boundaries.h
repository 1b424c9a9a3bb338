/*
 * domain_boundaries.h - the state of the boundaries (lib/boundaries/) that
 * the domain embeds: force reports, planar walls, sources and sinks. What
 * the boundaries do is declared in boundaries/boundaries.h. Private to
 * core/: included through core/domain.h.
 */
#ifndef GM_DOMAIN_BOUNDARIES_H
#define GM_DOMAIN_BOUNDARIES_H

#include "core/core.h"

#define GM_MAX_WALLS   64
#define GM_MAX_SOURCES 64

/* ------------------------------------------------------- force reports */
/* What a wall or rigid material reports (force_report.c): the last
 * successful gm_domain_step() call and running totals. */
typedef struct gm_force_report {
  double impulse[3];        /* N s, of the last successful call (z: 3D) */
  double force[3];          /* N, impulse / duration */
  double duration;          /* s, that call's dt */
  double total_impulse[3];  /* N s, since the wall or material was added */
  double total_duration;    /* s */
  double smoothed_force[3]; /* N, first-order low-pass of the force */
} gm_force_report;

/* ------------------------------------------------------------------ walls */
typedef struct gm_wall {
  double point[3];         /* m, on the plane (z: 3D, else 0) */
  double normal[3];        /* unit, into the material (z: 3D, else 0) */
  double friction_static;  /* mu_s */
  double friction_kinetic; /* mu_k */
} gm_wall;

/* ------------------------------------------------------ sources and sinks */
typedef struct gm_source {
  int material;
  size_t count;         /* points per injection */
  double *position;     /* m, count * dim, owned */
  double velocity[3];   /* m/s (z: 3D, else 0) */
  double point_size;    /* m */
  double density;       /* kg/m^3 */
  double next_time;     /* s, next injection; INFINITY when done */
  double period;        /* s, 0 = once */
  int injections_left;  /* -1 = no limit */
  double injected_mass; /* kg */
  uint64_t injected_points;
} gm_source;

typedef struct gm_sink {
  double lower[3], upper[3]; /* m; unused axes +-infinity */
  double removed_mass;       /* kg */
  uint64_t removed_points;
} gm_sink;

#endif
