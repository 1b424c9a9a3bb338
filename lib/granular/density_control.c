/*
 * density_control.c - what the stress_free and granular families do to a
 * point after its stress update (000 sec 3.2), chunk by chunk inside the
 * G2P pass that deforms the points:
 *  - stress_free: a granular point below its critical density carries no
 *    stress (Dunatunga & Kamrin); its F evolves freely.
 *  - granular, disconnected (alone on its parallel grid): stress-free, and
 *    F and the volume stay those of the previous step (density frozen).
 *  - granular, connected, rho < rho_cr - TOL: stress 0 (eq 13), F back to
 *    the previous step's (eq 14) or scaled to V = V_cr (eq 18), and
 *    V = det F V0 (eq 15). The point is then in the moderate state.
 * With CPDI the domain map D (cpdi_reset.c) follows F in each case.
 * The result is written to the step's new buffer, with each point's state.
 */
#include "granular/granular.h"

#include <math.h>

/* sigma = 0 (eq 13): every stored component (six in 3D). */
static void clear_stress(gm_point_buffers *to, size_t p) {
  for (int k = 0; k < GM_STRESS_SLOTS; k++)
    if (to->stress[k])
      to->stress[k][p] = 0.0;
}

/* F and V of the previous step (eq 14 with the exact inverse). */
static void keep_previous_deformation(const gm_point_buffers *from,
                                      gm_point_buffers *to, size_t p) {
  for (int k = 0; k < GM_F_SLOTS; k++) /* nine in 3D */
    if (to->deformation[k])
      to->deformation[k][p] = from->deformation[k][p];
  for (int k = 0; k < GM_F_SLOTS; k++) /* CPDI: the domain goes back with F */
    if (to->domain_map[k])
      to->domain_map[k][p] = from->domain_map[k][p];
  to->volume[p] = from->volume[p];
}

/* Eq 18: F <- (V_cr / V)^(1/d) F, d the dimension F acts in (3 in
 * axisymmetry, where the hoop stretch is part of det F); then eq 15. */
static void scale_to_critical(const gm_domain *domain, gm_point_buffers *to,
                              size_t p, double critical_volume) {
  const gm_points *points = &domain->points;
  if (domain->dim == 3) {
    /* All nine components, then V = det F V0 (eq 15) with the 3 x 3
     * determinant in g2p_3d.c's order. */
    double factor = cbrt(critical_volume / to->volume[p]);
    static const int slot[9] = {F_XX, F_XY, F_XZ, F_YX, F_YY,
                                F_YZ, F_ZX, F_ZY, F_ZZ};
    double f[9];
    for (int c = 0; c < 9; c++) {
      to->deformation[slot[c]][p] *= factor;
      f[c] = to->deformation[slot[c]][p];
      if (to->domain_map[slot[c]]) /* CPDI: the domain scales with F */
        to->domain_map[slot[c]][p] *= factor;
    }
    double jacobian = f[0] * (f[4] * f[8] - f[5] * f[7]) -
                      f[1] * (f[3] * f[8] - f[5] * f[6]) +
                      f[2] * (f[3] * f[7] - f[4] * f[6]);
    to->volume[p] = jacobian * points->initial_volume[p];
    return;
  }
  int dimension = domain->axisymmetric ? 3 : domain->dim;
  double factor = pow(critical_volume / to->volume[p], 1.0 / dimension);
  int components = domain->dim == 1 ? 1 : 4;
  for (int k = 0; k < components; k++) {
    to->deformation[k][p] *= factor;
    if (to->domain_map[k]) /* CPDI: the domain scales with F */
      to->domain_map[k][p] *= factor;
  }
  double jacobian = to->deformation[F_XX][p] * to->deformation[F_YY][p] -
                    to->deformation[F_XY][p] * to->deformation[F_YX][p];
  if (domain->axisymmetric) {
    to->deformation[F_ZZ][p] *= factor;
    jacobian *= to->deformation[F_ZZ][p];
  }
  to->volume[p] = jacobian * points->initial_volume[p];
}

/* The point arrays a disconnected or returned point rewrites, gathered
 * once per chunk: the stored stress components it zeroes, and the stored
 * F components, CPDI domain map and volume it takes from the previous
 * step (clear_stress and keep_previous_deformation without a test per slot
 * and point: about 50 instructions per disconnected point, 15 per
 * point-step of the granular cloud). */
typedef struct rewritten_arrays {
  double *zeroed[GM_STRESS_SLOTS];
  int zeroed_count;
  double *kept[2 * GM_F_SLOTS + 1]; /* F, D (CPDI), V */
  const double *previous[2 * GM_F_SLOTS + 1];
  int kept_count;
} rewritten_arrays;

static void gather_rewritten(const gm_point_buffers *from, gm_point_buffers *to,
                             rewritten_arrays *arrays) {
  arrays->zeroed_count = arrays->kept_count = 0;
  for (int k = 0; k < GM_STRESS_SLOTS; k++)
    if (to->stress[k])
      arrays->zeroed[arrays->zeroed_count++] = to->stress[k];
  for (int k = 0; k < GM_F_SLOTS; k++)
    if (to->deformation[k]) {
      arrays->kept[arrays->kept_count] = to->deformation[k];
      arrays->previous[arrays->kept_count++] = from->deformation[k];
    }
  for (int k = 0; k < GM_F_SLOTS; k++)
    if (to->domain_map[k]) {
      arrays->kept[arrays->kept_count] = to->domain_map[k];
      arrays->previous[arrays->kept_count++] = from->domain_map[k];
    }
  arrays->kept[arrays->kept_count] = to->volume;
  arrays->previous[arrays->kept_count++] = from->volume;
}

/* clear_stress and keep_previous_deformation through the gathered arrays:
 * the same values stored. */
static void clear_stress_of(const rewritten_arrays *arrays, size_t p) {
  for (int k = 0; k < arrays->zeroed_count; k++)
    arrays->zeroed[k][p] = 0.0;
}

static void keep_previous_of(const rewritten_arrays *arrays, size_t p) {
  for (int k = 0; k < arrays->kept_count; k++)
    arrays->kept[k][p] = arrays->previous[k][p];
}

/* The granular family's rules for a chunk whose points are all of one
 * granular material (the common chunk): the branches of the loop below
 * with the material's constants in locals and, where one component holds
 * every point (two or more), no point looked up as disconnected. The
 * same decisions and the same arithmetic, in the same order. */
static void granular_chunk(gm_domain *domain, size_t first, size_t count,
                           const gm_material *material) {
  gm_points *points = &domain->points;
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  const gm_granular_work *work = &domain->granular;
  bool all_connected = work->summary.component_count == 1 && points->count > 1;
  double critical = material->critical_density; /* kg/m^3 */
  double tolerance = material->tolerance;       /* kg/m^3 */
  double loosest = critical - tolerance;        /* kg/m^3 */
  bool keep = material->density_control == GM_DENSITY_CONTROL_RETURN;
  const double *mass = points->mass; /* kg */
  const double *volume = to->volume; /* the updated volume */
  uint8_t *states = to->granular_state;
  rewritten_arrays arrays;
  gather_rewritten(from, to, &arrays);
  for (size_t p = first; p < first + count; p++) {
    bool disconnected =
        !all_connected && work->component_size[work->label[p]] == 1;
    int state = disconnected ? GM_STATE_DISCONNECTED : GM_STATE_QUASI_STATIC;
    double density = mass[p] / volume[p]; /* kg/m^3 */
    if (disconnected) {
      clear_stress_of(&arrays, p);
      keep_previous_of(&arrays, p);
    } else if (density < loosest) {
      clear_stress_of(&arrays, p);
      if (keep)
        keep_previous_of(&arrays, p);
      else
        scale_to_critical(domain, to, p, mass[p] / critical);
      state = GM_STATE_MODERATE;
    } else if (fabs(density - critical) <= tolerance) {
      state = GM_STATE_MODERATE;
    }
    if (states)
      states[p] = (uint8_t)state;
  }
}

/* The material of every point of the chunk, or NULL if they differ. */
static const gm_material *chunk_material(const gm_domain *domain, size_t first,
                                         size_t count) {
  const int32_t *material = domain->points.material + first;
  int32_t differ = 0; /* no early exit: the scan vectorises */
  for (size_t j = 1; j < count; j++)
    differ |= material[j] ^ material[0];
  return count > 0 && !differ ? &domain->materials[material[0]] : NULL;
}

void gm_density_control_chunk(gm_domain *domain, size_t first, size_t count) {
  gm_family family = domain->def.family;
  if (family == GM_FAMILY_PLAIN)
    return;
  const gm_material *uniform = family == GM_FAMILY_GRANULAR
                                   ? chunk_material(domain, first, count)
                                   : NULL;
  if (uniform && uniform->granular) {
    granular_chunk(domain, first, count, uniform);
    return;
  }
  gm_points *points = &domain->points;
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  const gm_granular_work *work = &domain->granular;
  bool granular_family = family == GM_FAMILY_GRANULAR;
  for (size_t p = first; p < first + count; p++) {
    const gm_material *material = &domain->materials[points->material[p]];
    bool disconnected =
        granular_family && work->component_size[work->label[p]] == 1;
    int state = disconnected ? GM_STATE_DISCONNECTED : GM_STATE_QUASI_STATIC;
    if (material->granular) {
      double critical = material->critical_density; /* kg/m^3 */
      double density = points->mass[p] / to->volume[p];
      if (!granular_family) {
        if (density < critical)
          clear_stress(to, p);
      } else if (disconnected) {
        clear_stress(to, p);
        keep_previous_deformation(from, to, p);
      } else if (density < critical - material->tolerance) {
        clear_stress(to, p);
        if (material->density_control == GM_DENSITY_CONTROL_RETURN)
          keep_previous_deformation(from, to, p);
        else
          scale_to_critical(domain, to, p, points->mass[p] / critical);
        state = GM_STATE_MODERATE;
      } else if (fabs(density - critical) <= material->tolerance) {
        state = GM_STATE_MODERATE;
      }
    }
    if (to->granular_state)
      to->granular_state[p] = (uint8_t)state;
  }
}
