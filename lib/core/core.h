/*
 * core.h - the small core every file of the library may include: the
 * basic constants and tensor slots, GM_ALWAYS_INLINE, the allocator and
 * error recording. It holds no data layout: the domain behind the opaque
 * handle and the state it embeds are in core/domain.h, what each folder
 * does in that folder's own header (docs/architecture.md). Private to the
 * library.
 */
#ifndef GM_CORE_H
#define GM_CORE_H

#include "granmpm.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define GM_ERROR_MESSAGE_SIZE 512
/* Kernels are written once with constant flags and specialised by forced
 * inlining into one copy per pass kind. */
#if defined(__GNUC__)
#define GM_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define GM_ALWAYS_INLINE inline
#endif
#define GM_PI        3.14159265358979323846
#define GM_MAX_STATE 64
/* Points handed to a material callback at once: large enough to amortise
 * the call, small enough that the batch buffers stay in L1/L2. */
#define GM_BATCH_SIZE 128
/* Stored stress components in 1D and 2D: xx, yy, zz (hoop), xy. 3D adds
 * yz and zx (slots GM_YZ, GM_ZX: the slots are the Voigt order). */
#define GM_STRESS_STORED 4
#define GM_STRESS_SLOTS  6
/* Stored deformation gradient components: xx, xy, yx, yy, zz (hoop). 3D
 * adds xz, yz, zx, zy after them (F_XZ..F_ZY; all nine stored). */
#define GM_F_STORED 5
#define GM_F_SLOTS  9
enum {
  F_XX = 0,
  F_XY = 1,
  F_YX = 2,
  F_YY = 3,
  F_ZZ = 4,
  F_XZ = 5,
  F_YZ = 6,
  F_ZX = 7,
  F_ZY = 8
};
/* Slots of APIC's affine matrix B_p (GM_TRANSFER_APIC), row-major: xx,
 * xy, yx, yy in 2D; xx xy xz yx yy yz zx zy zz in 3D. A domain allocates
 * dim x dim of them (gm_affine_stored: 1 in 1D, 4 in 2D, 9 in 3D); the
 * others stay NULL, so a 2D point costs no more than before 3D APIC. */
#define GM_AFFINE_STORED 9

/* --------------------------------------------------------------- memory */
void *gm_alloc(size_t size);
void *gm_calloc(size_t count, size_t size);
void gm_free(void *pointer);
/* Grows *array (element size elem) from old_count to new_count elements,
 * keeping contents; returns false (array untouched) when out of memory. */
bool gm_grow(void **array, size_t elem, size_t old_count, size_t new_count);

/* -------------------------------------------------------------- errors */
/* Defined in core/domain_workers.h. */
typedef struct gm_worker_scratch gm_worker_scratch;

/* Records the message read by gm_last_create_error() (this thread). */
gm_status gm_set_create_error(gm_status status, const char *format, ...)
    __attribute__((format(printf, 2, 3)));
/* Records an error message on the domain and returns status. */
gm_status gm_set_error(gm_domain *domain, gm_status status, const char *format,
                       ...) __attribute__((format(printf, 3, 4)));
/* The same into a per-worker scratch (keeps the lowest point index). */
void gm_worker_error(gm_worker_scratch *scratch, gm_status status, size_t index,
                     const char *format, ...)
    __attribute__((format(printf, 4, 5)));
/* Moves the lowest-index worker error into the domain; GM_OK if none. */
gm_status gm_collect_worker_errors(gm_domain *domain);
void gm_clear_worker_errors(gm_domain *domain);

#endif
