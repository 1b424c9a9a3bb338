/*
 * stress_update.c - the objective stress update around the material call.
 * The library splits L into the rate of deformation D and the spin W,
 * rotates the stress with the Jaumann rate, sigma + (W sigma - sigma W) dt
 * (002 sec 4.1, 004 eqs 3.20-3.21), then hands D dt and the rotated stress
 * to the material, which integrates its own law. Materials thus never see
 * rigid rotations and stay objective without knowing about them.
 */
#include "internal.h"

#include <math.h>
#include <string.h>

enum { L_XX = 0, L_XY = 1, L_YX = 2, L_YY = 3, L_ZZ = 4 };

/* Strain increment and Jaumann-rotated stress of point p into row j. */
static void prepare_row(gm_domain *domain, gm_worker_scratch *scratch,
                        size_t p, size_t j, const double gradient[5],
                        double dt) {
  const gm_points *points = &domain->points;
  const gm_point_buffers *from = &points->buffer[points->cur];
  const gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  double spin = 0.5 * (gradient[L_XY] - gradient[L_YX]) * dt; /* W_xy dt */
  double sxx = from->stress[0][p], syy = from->stress[1][p];
  double szz = from->stress[2][p], sxy = from->stress[3][p];
  scratch->stress[GM_XX][j] = sxx + 2.0 * spin * sxy;
  scratch->stress[GM_YY][j] = syy - 2.0 * spin * sxy;
  scratch->stress[GM_ZZ][j] = szz;
  scratch->stress[GM_XY][j] = sxy + spin * (syy - sxx);
  scratch->stress[GM_YZ][j] = 0.0;
  scratch->stress[GM_ZX][j] = 0.0;
  scratch->strain_increment[GM_XX][j] = gradient[L_XX] * dt;
  scratch->strain_increment[GM_YY][j] = gradient[L_YY] * dt;
  scratch->strain_increment[GM_ZZ][j] = gradient[L_ZZ] * dt;
  scratch->strain_increment[GM_XY][j] =
      0.5 * (gradient[L_XY] + gradient[L_YX]) * dt;
  scratch->strain_increment[GM_YZ][j] = 0.0;
  scratch->strain_increment[GM_ZX][j] = 0.0;
  scratch->density[j] = points->mass[p] / to->volume[p];
  scratch->point_id[j] = points->id[p];
}

/* Calls material m on `count` rows held in the given arrays; rows map to
 * points first + row_point[r]. Returns the callback's code. */
static int call_material(gm_domain *domain, gm_worker_scratch *scratch,
                         int material_index, size_t first,
                         const uint32_t *row_point, size_t count,
                         double (*strain)[GM_BATCH_SIZE],
                         double (*stress)[GM_BATCH_SIZE], double *density,
                         int64_t *point_id, double dt) {
  const gm_material *material = &domain->materials[material_index];
  gm_points *points = &domain->points;
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  size_t stride = points->state_stride, nstate = material->state_count;
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
  int result = material->update(&batch, material->user, message,
                                sizeof message);
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
  for (size_t r = 0; r < count; r++)
    for (size_t k = 0; k < nstate; k++)
      to->state[(first + row_point[r]) * stride + k] =
          scratch->state_columns[k][r];
  return 0;
}

/* Chunk mixing materials: one sub-batch per material present. */
static void update_mixed(gm_domain *domain, gm_worker_scratch *scratch,
                         size_t first, size_t count, double dt) {
  const int32_t *material = domain->points.material + first;
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
        scratch->sub_stress[c][rows] = scratch->stress[c][j];
      }
      scratch->sub_density[rows] = scratch->density[j];
      scratch->sub_point_id[rows] = scratch->point_id[j];
      rows++;
    }
    call_material(domain, scratch, material[seed], first, scratch->batch_index,
                  rows, scratch->sub_strain_increment, scratch->sub_stress,
                  scratch->sub_density, scratch->sub_point_id, dt);
    for (size_t r = 0; r < rows; r++)
      for (int c = 0; c < 6; c++)
        scratch->stress[c][scratch->batch_index[r]] = scratch->sub_stress[c][r];
  }
}

void gm_stress_update_chunk(gm_domain *domain, gm_worker_scratch *scratch,
                            size_t first, size_t count, double dt,
                            const double (*velocity_gradient)[5]) {
  gm_points *points = &domain->points;
  bool uniform = true;
  for (size_t j = 0; j < count; j++) {
    prepare_row(domain, scratch, first + j, j, velocity_gradient[j], dt);
    uniform = uniform && points->material[first + j] == points->material[first];
  }
  if (uniform)
    call_material(domain, scratch, points->material[first], first,
                  scratch->identity_rows, count, scratch->strain_increment,
                  scratch->stress, scratch->density, scratch->point_id, dt);
  else
    update_mixed(domain, scratch, first, count, dt);
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    bool finite = true;
    for (int c = 0; c < GM_STRESS_STORED; c++) {
      to->stress[c][p] = scratch->stress[c][j];
      finite = finite && isfinite(scratch->stress[c][j]);
    }
    if (!finite)
      gm_worker_error(scratch, GM_ERR_NOT_FINITE, p,
                      "step: point id %lld (material %d) got a non-finite "
                      "stress at t = %g s; the step was not taken",
                      (long long)points->id[p], points->material[p],
                      domain->time + dt);
  }
}
