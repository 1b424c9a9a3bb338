/*
 * domain_workers.h - the per-worker scratch (gm_worker_scratch) the domain
 * holds one of per worker: the batch buffers of the material calls and
 * the first error the worker met. The pool itself is core/threads.h.
 * Private to core/: included through core/domain.h.
 */
#ifndef GM_DOMAIN_WORKERS_H
#define GM_DOMAIN_WORKERS_H

#include "core/core.h"

/* ------------------------------------------------------------- per worker */

/* Bytes of the Mohr-Coulomb constants a worker keeps between the chunks
 * of its fused passes (materials/mohr_coulomb.c checks that they fit). */
#define GM_MOHR_COULOMB_PREPARED_BYTES 1024
struct gm_worker_scratch {
  double strain_increment[6][GM_BATCH_SIZE]; /* yz, zx stay zero */
  double stress[6][GM_BATCH_SIZE];           /* yz, zx rows used */
  double density[GM_BATCH_SIZE];
  uint32_t batch_index[GM_BATCH_SIZE];
  uint32_t identity_rows[GM_BATCH_SIZE]; /* 0, 1, 2, ... */
  double *state_columns[GM_MAX_STATE];
  double *state_storage;       /* GM_MAX_STATE * GM_BATCH_SIZE doubles */
  struct chunk_gather *gather; /* G2P results of the chunk (g2p.c) */
  /* Sub-batch of one material when a chunk mixes materials. */
  double sub_strain_increment[6][GM_BATCH_SIZE];
  double sub_stress[6][GM_BATCH_SIZE];
  double sub_density[GM_BATCH_SIZE];
  int64_t sub_point_id[GM_BATCH_SIZE];
  /* First error met by this worker in the current phase (lowest point
   * index wins, so the message does not depend on the partition). */
  gm_status error_status;
  size_t error_index;
  char error_message[GM_ERROR_MESSAGE_SIZE];
  int callback_result; /* material return code that caused the error */
  bool error_inverted; /* the recorded error is an inverted F (finite
                          det F <= 0): a smaller dt may avoid it */
  double max_wave_speed_squared;  /* m^2/s^2, max c_p^2 of the new state */
  double max_point_speed_squared; /* m^2/s^2, max |v_p|^2 of the new state */
  double density_control_seconds; /* this step, this worker */
  /* The Mohr-Coulomb return's planes, prepared for the last parameters
   * this worker's fused plane pass met (gm_mohr_coulomb_plane_returns):
   * derived once, not per chunk. Zero (calloc): none yet. */
  _Alignas(double) unsigned char mohr_coulomb_prepared
      [GM_MOHR_COULOMB_PREPARED_BYTES];
  char pad[64];
};

#endif
