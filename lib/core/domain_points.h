/*
 * domain_points.h - the SoA storage of the points (gm_points and its
 * double-buffered gm_point_buffers) that the domain embeds. What works on
 * it is declared in points/points.h. Private to core/: included through
 * core/domain.h.
 */
#ifndef GM_DOMAIN_POINTS_H
#define GM_DOMAIN_POINTS_H

#include "core/core.h"

#define GM_REMOVED_POINT UINT32_MAX

/* ---------------------------------------------------------------- points */
/* Fields a step rewrites are double-buffered: the step reads buffer `cur`
 * and writes buffer `cur ^ 1`; success swaps, failure discards. That makes a
 * step transactional without copying the domain. */
/* Only the components a geometry needs are allocated (dim components of
 * vectors; F_ZZ only in axisymmetry, where the hoop stretch evolves);
 * the others stay NULL. */
typedef struct gm_point_buffers {
  double *position[3];             /* m */
  double *velocity[3];             /* m/s */
  double *stress[GM_STRESS_SLOTS]; /* Pa, xx yy zz xy (yz zx: 3D) */
  double *deformation[GM_F_SLOTS]; /* F components, see F_XX.. */
  /* CPDI only (NULL otherwise): the domain map D, in F's slots (F_XX..
   * F_YY below 3D, all nine F_XX..F_ZY in 3D). The domain's half edges
   * are r_k = D (l_k/2) e_k with l the initial edges (domain_size). D
   * takes the same increments as F (and the same density control), so D
   * = F bitwise until the domain of an over-distorted point is reset
   * (cpdi_reset.c). */
  double *domain_map[GM_F_SLOTS];
  double *volume; /* current volume (units: gm_points_def) */
  double *state;  /* state[i*stride+k]: one pool for all
                     materials, stride = max state_count */
  /* Granular family only (NULL otherwise): gm_point_state and parallel
   * grid label of the step that produced this buffer, as the small
   * integers they are (5 bytes per point instead of two doubles' 16;
   * GM_FIELD_STATE, GM_FIELD_COMPONENT and the checkpoint convert them to
   * doubles, exactly). A label is below the point count < INT_MAX
   * (points.c). */
  uint8_t *granular_state;
  int32_t *component;
  /* GM_TRANSFER_APIC only (NULL otherwise): B_p, m^2/s, row-major dim x
   * dim (transfer.h), written by the velocity pass of G2P. */
  double *affine[GM_AFFINE_STORED];
} gm_point_buffers;

typedef struct gm_points {
  size_t count;
  size_t capacity;
  gm_point_buffers buffer[2];
  int cur; /* index of the committed buffer */
  /* Single-buffered fields (a step never changes them). */
  double *mass;              /* kg */
  double *initial_volume;    /* at creation */
  double *domain_size[3];    /* m, initial particle domain edges */
  double *external_force[3]; /* N, host-supplied, persistent; allocated on
                                first use (NULL = no external force) */
  int64_t *id;               /* stable id */
  int32_t *material;         /* material index */
  /* id -> index for ids 0..next_id-1; GM_REMOVED_POINT once a sink has
   * removed the point (ids are never reused). */
  uint32_t *index_of_id;
  size_t id_capacity;
  /* Block of each point: of the committed positions at binning, of the
   * moved ones after the move pass (right for the next step if it
   * commits). keys_valid: block_key matches the committed positions. */
  int64_t *block_key;
  bool keys_valid;
  /* blocks_kept: the move of the last step left every point in the block
   * it was binned in (grid/move_remap.c), so with keys_valid the next
   * binning would rebuild the same grid, order and point blocks. */
  bool blocks_kept;
  int64_t next_id;
  size_t state_stride; /* doubles of state per point */
  /* Scratch sized with the points (no allocation inside a step). */
  uint32_t *point_block; /* block index of each point this step */
  uint32_t *order;       /* point indices grouped by block */
} gm_points;

#endif
