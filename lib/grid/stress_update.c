/*
 * stress_update.c - the objective stress update around the material call.
 * The library splits L into the rate of deformation D and the spin W,
 * rotates the stress with the Jaumann rate, sigma + (W sigma - sigma W) dt
 * (002 sec 4.1, 004 eqs 3.20-3.21), then hands D dt and the rotated stress
 * to the material, which integrates its own law. Materials thus never see
 * rigid rotations and stay objective without knowing about them.
 */
#include "grid/grid.h"

#include <math.h>
#include <string.h>

enum { L_XX = 0, L_XY = 1, L_YX = 2, L_YY = 3, L_ZZ = 4 };

/* Strain increments of the chunk into scratch rows, the Jaumann-rotated
 * stress straight into the next buffer (where the material updates it in
 * place), densities into scratch. */
static void prepare_rows(gm_domain *domain, gm_worker_scratch *scratch,
                         size_t first, size_t count,
                         const double *const gradient[5], double dt,
                         bool in_place) {
  gm_points *points = &domain->points;
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  const gm_point_buffers *from = in_place ? to : &points->buffer[points->cur];
  /* In place, the rotated stress overwrites the stress it comes from: each
   * row is read whole before it is written, and nothing is restrict. */
  const double *sxx = from->stress[0] + first, *syy = from->stress[1] + first;
  const double *szz = from->stress[2] + first, *sxy = from->stress[3] + first;
  double *rxx = to->stress[0] + first, *ryy = to->stress[1] + first;
  double *rzz = to->stress[2] + first, *rxy = to->stress[3] + first;
  const double *restrict mass = points->mass + first;
  const double *restrict volume = to->volume + first;
  const double *restrict l_xx = gradient[L_XX], *restrict l_xy = gradient[L_XY];
  const double *restrict l_yx = gradient[L_YX], *restrict l_yy = gradient[L_YY];
  const double *restrict l_zz = gradient[L_ZZ];
  double *restrict e_xx = scratch->strain_increment[GM_XX];
  double *restrict e_yy = scratch->strain_increment[GM_YY];
  double *restrict e_zz = scratch->strain_increment[GM_ZZ];
  double *restrict e_xy = scratch->strain_increment[GM_XY];
  double *restrict density = scratch->density;
  for (size_t j = 0; j < count; j++) {
    double spin = 0.5 * (l_xy[j] - l_yx[j]) * dt; /* W_xy dt */
    double s_xx = sxx[j], s_yy = syy[j], s_zz = szz[j], s_xy = sxy[j];
    rxx[j] = s_xx + 2.0 * spin * s_xy;
    ryy[j] = s_yy - 2.0 * spin * s_xy;
    rzz[j] = s_zz;
    rxy[j] = s_xy + spin * (s_yy - s_xx);
    e_xx[j] = l_xx[j] * dt;
    e_yy[j] = l_yy[j] * dt;
    e_zz[j] = l_zz[j] * dt;
    e_xy[j] = 0.5 * (l_xy[j] + l_yx[j]) * dt;
    density[j] = mass[j] / volume[j];
  }
  /* yz and zx are zero in 1D and 2D; a material may still write them. */
  for (size_t j = 0; j < count; j++)
    scratch->stress[GM_YZ][j] = scratch->stress[GM_ZX][j] = 0.0;
}

/* The same in 3D: the full Jaumann spin and D dt of materials/jaumann.c
 * (002 sec 4.1, 004 eqs 3.20-3.21) on the six stored components. L is
 * row-major (xx xy xz yx yy yz zx zy zz), one array per component. */
static void prepare_rows_3d(gm_domain *domain, gm_worker_scratch *scratch,
                            size_t first, size_t count,
                            const double *const gradient[9], double dt,
                            bool in_place) {
  gm_points *points = &domain->points;
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  const gm_point_buffers *from = in_place ? to : &points->buffer[points->cur];
  const double *restrict mass = points->mass + first;
  const double *restrict volume = to->volume + first;
  for (size_t j = 0; j < count; j++) {
    double l[9], stress[6], increment[6];
    for (int c = 0; c < 9; c++)
      l[c] = gradient[c][j];
    for (int c = 0; c < 6; c++) /* read whole before written (in place) */
      stress[c] = from->stress[c][first + j];
    gm_jaumann_rotate(l, dt, stress);
    gm_strain_increment(l, dt, increment);
    for (int c = 0; c < 6; c++) {
      to->stress[c][first + j] = stress[c];
      scratch->strain_increment[c][j] = increment[c];
    }
    scratch->density[j] = mass[j] / volume[j];
  }
}

/* target[r * target_stride] = source[r * source_stride], r < count. */
static void copy_strided(double *restrict target, size_t target_stride,
                         const double *restrict source, size_t source_stride,
                         size_t count) {
  for (size_t r = 0; r < count; r++)
    target[r * target_stride] = source[r * source_stride];
}

/* Calls material m on `count` rows; rows map to points first + row[r].
 * Returns the callback's code. */
static int call_material(gm_domain *domain, gm_worker_scratch *scratch,
                         int material_index, size_t first,
                         const uint32_t *row_point, size_t count,
                         const double *const strain[6], double *const stress[6],
                         const double *density, const int64_t *point_id,
                         double dt, bool in_place) {
  const gm_material *material = &domain->materials[material_index];
  gm_points *points = &domain->points;
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  /* In place is safe: the state goes through the scratch columns. */
  const gm_point_buffers *from = in_place ? to : &points->buffer[points->cur];
  size_t stride = points->state_stride, nstate = material->state_count;
  /* A uniform chunk's rows are its points in order: one strided column
   * copy per state variable, without the row map (the same values). */
  bool identity = row_point == scratch->identity_rows;
  if (identity)
    for (size_t k = 0; k < nstate; k++)
      copy_strided(scratch->state_columns[k], 1,
                   from->state + first * stride + k, stride, count);
  else
    for (size_t r = 0; r < count; r++)
      for (size_t k = 0; k < nstate; k++)
        scratch->state_columns[k][r] =
            from->state[(first + row_point[r]) * stride + k];
  gm_material_batch batch;
  memset(&batch, 0, sizeof batch);
  batch.struct_size = sizeof batch;
  batch.count = count;
  batch.worker = (int)(scratch - domain->scratch);
  batch.material = material_index;
  batch.geometry = domain->def.geometry;
  batch.dt = dt;
  for (int c = 0; c < 6; c++) {
    batch.strain_increment[c] = strain[c];
    batch.stress[c] = stress[c];
  }
  batch.density = density;
  batch.state = scratch->state_columns;
  batch.state_count = nstate;
  batch.point_id = point_id;
  char message[256] = "";
  int result =
      material->update(&batch, material->user, message, sizeof message);
  if (result != 0) {
    message[sizeof message - 1] = '\0';
    gm_worker_error(scratch, GM_ERR_CALLBACK, first + row_point[0],
                    "step: material %d (%s) returned %d (%s) for a batch "
                    "starting at point id %lld: %s",
                    material_index, material->name, result,
                    result > 0 ? "recoverable" : "fatal",
                    (long long)point_id[0], message[0] ? message : "-");
    if (result < 0 || scratch->callback_result >= 0)
      scratch->callback_result = result < 0 ? result : 1;
    return result;
  }
  if (identity)
    for (size_t k = 0; k < nstate; k++)
      copy_strided(to->state + first * stride + k, stride,
                   scratch->state_columns[k], 1, count);
  else
    for (size_t r = 0; r < count; r++)
      for (size_t k = 0; k < nstate; k++)
        to->state[(first + row_point[r]) * stride + k] =
            scratch->state_columns[k][r];
  return 0;
}

/* Chunk mixing materials: one gathered sub-batch per material present. */
static void update_mixed(gm_domain *domain, gm_worker_scratch *scratch,
                         size_t first, size_t count, double dt, bool in_place) {
  gm_points *points = &domain->points;
  int stored = gm_stress_stored(domain); /* 4, or 6 in 3D */
  const int32_t *material = points->material + first;
  double *const *next_stress = points->buffer[points->cur ^ 1].stress;
  const double *sub_strain[6];
  double *sub_stress[6];
  for (int c = 0; c < 6; c++) {
    sub_strain[c] = scratch->sub_strain_increment[c];
    sub_stress[c] = scratch->sub_stress[c];
  }
  bool done[GM_BATCH_SIZE] = {false};
  for (size_t seed = 0; seed < count; seed++) {
    if (done[seed])
      continue;
    size_t rows = 0;
    for (size_t j = seed; j < count; j++) {
      if (done[j] || material[j] != material[seed])
        continue;
      done[j] = true;
      scratch->batch_index[rows] = (uint32_t)j;
      for (int c = 0; c < 6; c++) {
        scratch->sub_strain_increment[c][rows] =
            scratch->strain_increment[c][j];
        scratch->sub_stress[c][rows] =
            c < stored ? next_stress[c][first + j] : 0.0;
      }
      scratch->sub_density[rows] = scratch->density[j];
      scratch->sub_point_id[rows] = points->id[first + j];
      rows++;
    }
    call_material(domain, scratch, material[seed], first, scratch->batch_index,
                  rows, sub_strain, sub_stress, scratch->sub_density,
                  scratch->sub_point_id, dt, in_place);
    for (size_t r = 0; r < rows; r++)
      for (int c = 0; c < stored; c++)
        next_stress[c][first + scratch->batch_index[r]] =
            scratch->sub_stress[c][r];
  }
}

/* Names the first point of the chunk with a non-finite new stress. */
void gm_check_stress_chunk(gm_domain *domain, gm_worker_scratch *scratch,
                           size_t first, size_t count, double dt) {
  const gm_points *points = &domain->points;
  double *const *stress = points->buffer[points->cur ^ 1].stress;
  int stored = gm_stress_stored(domain); /* 4, or 6 in 3D */
  double screen = 0.0; /* x * 0 is NaN exactly when x is not finite */
  for (int c = 0; c < stored; c++)
    for (size_t j = 0; j < count; j++)
      screen += stress[c][first + j] * 0.0;
  if (screen == 0.0)
    return;
  for (size_t p = first; p < first + count; p++) {
    bool finite = true;
    for (int c = 0; c < stored; c++)
      finite = finite && isfinite(stress[c][p]);
    if (!finite)
      gm_worker_error(scratch, GM_ERR_NOT_FINITE, p,
                      "step: point id %lld (material %d) got a non-finite "
                      "stress at t = %g s; the step was not taken",
                      (long long)points->id[p], points->material[p],
                      domain->time + dt);
  }
}

/* The material call of a chunk whose rows are prepared, and the check. */
static void call_chunk(gm_domain *domain, gm_worker_scratch *scratch,
                       size_t first, size_t count, double dt, bool in_place);

void gm_stress_update_chunk(gm_domain *domain, gm_worker_scratch *scratch,
                            size_t first, size_t count, double dt,
                            const double *const velocity_gradient[5],
                            bool in_place) {
  prepare_rows(domain, scratch, first, count, velocity_gradient, dt, in_place);
  call_chunk(domain, scratch, first, count, dt, in_place);
}

void gm_stress_update_chunk_3d(gm_domain *domain, gm_worker_scratch *scratch,
                               size_t first, size_t count, double dt,
                               const double *const velocity_gradient[9],
                               bool in_place) {
  prepare_rows_3d(domain, scratch, first, count, velocity_gradient, dt,
                  in_place);
  call_chunk(domain, scratch, first, count, dt, in_place);
}

static void call_chunk(gm_domain *domain, gm_worker_scratch *scratch,
                       size_t first, size_t count, double dt, bool in_place) {
  gm_points *points = &domain->points;
  int stored = gm_stress_stored(domain); /* 4, or 6 in 3D */
  const int32_t *material = points->material + first;
  bool uniform = true;
  for (size_t j = 1; j < count; j++)
    uniform = uniform && material[j] == material[0];
  if (uniform) { /* the common case: the material works on the buffers */
    double *const *next_stress = points->buffer[points->cur ^ 1].stress;
    const double *strain[6];
    double *stress[6];
    for (int c = 0; c < 6; c++) {
      strain[c] = scratch->strain_increment[c];
      stress[c] = c < stored ? next_stress[c] + first : scratch->stress[c];
    }
    call_material(domain, scratch, material[0], first, scratch->identity_rows,
                  count, strain, stress, scratch->density, points->id + first,
                  dt, in_place);
  } else {
    update_mixed(domain, scratch, first, count, dt, in_place);
  }
  gm_check_stress_chunk(domain, scratch, first, count, dt);
}
