/*
 * collapse_scene.h - the planar column collapse of examples/column_collapse
 * (size_scene and build_scene, the built-in floors), shared by
 * the convergence probes energy_budget.c and toe_probe.c so that the scene
 * they study is built in one place: the grid box, the floor, the back wall,
 * the fill and the connected deposit's front.
 *
 * The scene: a column L0 wide and H = a L0 high against a frictionless back
 * wall at x = 0, on a floor that is the grid's bottom face. The material is
 * the caller's (registered between collapse_scene_domain_def's
 * gm_domain_create and collapse_scene_add_walls, as the example does).
 *
 * Compile it with the probe:
 *   gcc -std=c11 -O2 -Iinclude -Iexamples bench/convergence/toe_probe.c \
 *     bench/convergence/collapse_scene.c -Lbuild/lib/.libs -lgranmpm -lm
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef BENCH_COLLAPSE_SCENE_H
#define BENCH_COLLAPSE_SCENE_H

#include <granmpm.h>

#include <stddef.h>

#define COLLAPSE_PI      3.14159265358979323846
#define COLLAPSE_GRAVITY 9.81   /* m/s^2 */
#define COLLAPSE_DENSITY 1800.0 /* kg/m^3, the example's dry sand */
/* rho_c / rho of the granular family, 000 Table 1 */
#define COLLAPSE_CRITICAL_RATIO (2235.0 / 2250.0)

typedef struct collapse_scene {
  double cell;       /* m */
  int ppc;           /* points per cell per direction */
  gm_shape shape;    /* shape functions */
  gm_family family;  /* plain | stress_free | granular */
  int workers;       /* worker threads */
  double cfl;        /* Courant number, <= 0: the library's */
  double aspect;     /* a = H / L0, > 0 */
  double length;     /* L0, m */
  const char *floor; /* "wall": a Coulomb wall of friction floor_mu;
                        "face": the no-slip box face; "slip": the
                        frictionless box face */
  double floor_mu;   /* friction of the "wall" floor (-) */
} collapse_scene;

/* H = a L0 (m) and tau_c = sqrt(H / g) (s). */
double collapse_scene_height(const collapse_scene *scene);
double collapse_scene_tau(const collapse_scene *scene);

/* Lube et al.'s (2005) planar law as examples/column_collapse has it: the
 * run-out (L_inf - L0) / L0 and the final height H_inf / L0 (secondary,
 * /work/shared/references.md; between a = 1.8 and 2.8 the run-out is
 * interpolated, indicative only). */
double collapse_scene_law_runout(double aspect);
double collapse_scene_law_height(double aspect);

/* gm_domain_def_default() with the scene's cell, shapes, family, workers,
 * CFL, grid box (2 + 2 x Lube's run-out law wide, 1.25 H + 4 cells high),
 * gravity and box-face floor. */
gm_domain_def collapse_scene_domain_def(const collapse_scene *scene);

/* Sets the granular family's critical density on material (no-op for the
 * plain family). */
gm_status collapse_scene_set_granular(gm_domain *domain,
                                      const collapse_scene *scene,
                                      int material);

/* Adds the Coulomb floor wall (floor "wall" only; its id in *floor_wall,
 * else -1) and then the frictionless back wall at x = 0. */
gm_status collapse_scene_add_walls(gm_domain *domain,
                                   const collapse_scene *scene,
                                   int *floor_wall);

/* Fills the column [0, L0] x [0, H] with material, ppc^2 points per cell. */
gm_status collapse_scene_fill(gm_domain *domain, const collapse_scene *scene,
                              int material);

/* Cell columns of the grid box (+2), the size of the occupancy scratch of
 * collapse_scene_connected_limit. */
size_t collapse_scene_columns(const collapse_scene *scene);

/* x (m) of the first empty cell column walked from the back wall: points
 * at or beyond it flew off the connected deposit. positions holds 2 per
 * point; occupied is scratch of collapse_scene_columns bytes. */
double collapse_scene_connected_limit(const collapse_scene *scene,
                                      const double *positions, size_t count,
                                      unsigned char *occupied);

/* The right edge of the deposit connected to the back wall (m), as the
 * example measures it: half a point spacing beyond the outermost centre
 * short of collapse_scene_connected_limit. */
double collapse_scene_front(const collapse_scene *scene,
                            const double *positions, size_t count,
                            unsigned char *occupied);

/* The friction angle (rad) of a Drucker-Prager cone with g = q (psi = 0)
 * that flows in plane strain at the same friction as Mohr-Coulomb of angle
 * friction (rad) with psi = 0 (see collapse_scene.c). */
double collapse_scene_dp_friction(double friction);

/* Prints "what: status (the domain's or the creation's message)" on stderr
 * and returns 1. */
int collapse_scene_fail(const gm_domain *domain, const char *what,
                        gm_status status);

/* Returns collapse_scene_fail's 1 from the calling function when call does
 * not give GM_OK. */
#define COLLAPSE_CHECK(domain, call)                                           \
  do {                                                                         \
    gm_status collapse_status_ = (call);                                       \
    if (collapse_status_ != GM_OK)                                             \
      return collapse_scene_fail((domain), #call, collapse_status_);           \
  } while (0)

#endif /* BENCH_COLLAPSE_SCENE_H */
