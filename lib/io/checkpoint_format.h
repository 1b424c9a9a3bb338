/*
 * checkpoint_format.h - the byte level of checkpoint files (checkpoint.c
 * decides what goes in): a growable output buffer, a bounds-checked
 * reader, the FNV-1a 64 checksum, named setup records and their
 * comparison (checkpoint_format.c); the file header, the atomic write and
 * the whole-file read (checkpoint_file.c).
 *
 * File layout (all integers and doubles in the writer's byte order):
 *   offset  0  magic "\x89GMCKPT\n"         8 bytes
 *           8  format version                u32
 *          12  byte-order marker 0x0A0B0C0D  u32
 *          16  payload size in bytes         u64
 *          24  FNV-1a 64 of bytes 0..23 and of the payload   u64
 *          32  payload
 * A file whose byte-order marker reads reversed came from a machine of the
 * other endianness and is refused: restarts are bitwise only on the same
 * kind of machine anyway.
 */
#ifndef GM_CHECKPOINT_FORMAT_H
#define GM_CHECKPOINT_FORMAT_H

#include "io/io.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Version 2 added the force reports of walls and rigid materials (their
 * impulses) and the 2D CPDI domain map (cpdi_reset.c) to the point
 * arrays; version 3 the 3D CPDI domain map (nine arrays after F), the
 * only change: a version-2 file loads as before, a 3D CPDI one with
 * D = F, which is what its domains were then. Version 1 files are refused
 * with a message that says so. */
#define GM_CHECKPOINT_VERSION     3u
#define GM_CHECKPOINT_OLDEST      2u /* the oldest version read */
#define GM_CHECKPOINT_3D_MAP      3u /* the first with the 3D domain map */
#define GM_CHECKPOINT_HEADER_SIZE 32u

/* ------------------------------------------------------------- writing */
typedef struct gm_byte_writer {
  unsigned char *data;
  size_t size, capacity; /* bytes */
  bool failed;           /* out of memory: every later put is ignored */
} gm_byte_writer;

void gm_writer_bytes(gm_byte_writer *writer, const void *bytes, size_t size);
void gm_writer_u8(gm_byte_writer *writer, uint8_t value);
void gm_writer_u32(gm_byte_writer *writer, uint32_t value);
void gm_writer_u64(gm_byte_writer *writer, uint64_t value);
void gm_writer_i64(gm_byte_writer *writer, int64_t value);
void gm_writer_f64(gm_byte_writer *writer, double value);
/* An array: its size in bytes (u64), then the bytes (data may be NULL
 * when size is 0). */
void gm_writer_array(gm_byte_writer *writer, const void *data, size_t size);
void gm_writer_free(gm_byte_writer *writer);

/* ------------------------------------------------------------- reading */
typedef struct gm_byte_reader {
  const unsigned char *data;
  size_t size, offset; /* bytes */
  bool failed;         /* read past the end or a size mismatch */
} gm_byte_reader;

uint8_t gm_reader_u8(gm_byte_reader *reader);
uint32_t gm_reader_u32(gm_byte_reader *reader);
uint64_t gm_reader_u64(gm_byte_reader *reader);
int64_t gm_reader_i64(gm_byte_reader *reader);
double gm_reader_f64(gm_byte_reader *reader);
/* An array written by gm_writer_array that must hold exactly `size`
 * bytes: returns where they start (unaligned: copy them out with memcpy),
 * or NULL and marks the reader failed. */
const unsigned char *gm_reader_array(gm_byte_reader *reader, size_t size);
/* The same for an array of any size: *size receives it. */
const unsigned char *gm_reader_any_array(gm_byte_reader *reader, size_t *size);

/* FNV-1a 64 of size bytes, continuing from hash (start with
 * GM_FNV_OFFSET). Any single changed byte changes the result: each step
 * (xor a byte, multiply by an odd prime modulo 2^64) is a bijection. */
#define GM_FNV_OFFSET 0xcbf29ce484222325ull
uint64_t gm_fnv1a64(const void *bytes, size_t size, uint64_t hash);

/* -------------------------------------------------------- setup records */
/* The setup a checkpoint belongs to is stored as named records so that a
 * mismatch can be reported by name: u16 name length, the name, u8 kind,
 * u64 element count, the elements (8 bytes each for reals and integers, 1
 * for text and bytes). */
typedef enum gm_record_kind {
  GM_RECORD_REALS = 0,
  GM_RECORD_INTEGERS = 1,
  GM_RECORD_TEXT = 2,
  GM_RECORD_BYTES = 3
} gm_record_kind;

void gm_record_reals(gm_byte_writer *writer, const char *name,
                     const double *values, size_t count);
void gm_record_integer(gm_byte_writer *writer, const char *name, int64_t value);
void gm_record_text(gm_byte_writer *writer, const char *name, const char *text);
void gm_record_bytes(gm_byte_writer *writer, const char *name,
                     const void *bytes, size_t size);
/* Compares two record sequences; on the first difference writes a message
 * naming the record (and the values, for numbers) and returns false. */
bool gm_records_equal(const unsigned char *file, size_t file_size,
                      const unsigned char *domain, size_t domain_size,
                      char *message, size_t message_size);

/* ----------------------------------------------------------- the file */
/* Starts a writer with room for the header. */
void gm_checkpoint_begin(gm_byte_writer *writer);
/* Fills in the header (size, checksum) once the payload is complete. */
void gm_checkpoint_seal(gm_byte_writer *writer);
/* Writes the sealed bytes to "<path>.tmp", flushes, syncs and renames it
 * over path; on any failure removes the temporary file and leaves path
 * alone. Errors are recorded on domain (GM_ERR_IO, naming the path). */
gm_status gm_checkpoint_write_file(gm_domain *domain, const char *path,
                                   const gm_byte_writer *writer);
/* Reads path whole and checks magic, byte order, version (from
 * GM_CHECKPOINT_OLDEST to GM_CHECKPOINT_VERSION), size and checksum; on
 * success *file holds the file (free with gm_free), *payload reads its
 * payload and *version is the file's format version. */
gm_status gm_checkpoint_read_file(gm_domain *domain, const char *path,
                                  unsigned char **file, gm_byte_reader *payload,
                                  uint32_t *version);

/* ------------------------------------------- shared by save and load */
/* Appends the setup records of domain (checkpoint.c). */
void gm_checkpoint_describe_setup(const gm_domain *domain, gm_byte_writer *out);

/* What load checks in an array before accepting it. */
typedef enum gm_array_check {
  GM_CHECK_NONE,        /* material state: its meaning is the material's */
  GM_CHECK_FINITE,      /* stress, F */
  GM_CHECK_DEFORMATION, /* F_XX: with the next three slots (and F_ZZ in
                           axisymmetry; the next eight in 3D) finite,
                           det F > 0 */
  GM_CHECK_DOMAIN_MAP,  /* CPDI's D_XX: with the next three slots (the
                           next eight in 3D) finite, det D > 0 */
  GM_CHECK_POSITIVE,    /* finite and > 0: volumes, masses, domain sizes */
  GM_CHECK_POSITION,    /* finite and inside the grid box */
  GM_CHECK_INPUT, /* velocities: host-written ones are screened by the step */
  GM_CHECK_ID,    /* ids against the id map */
  GM_CHECK_MATERIAL,       /* a registered material */
  GM_CHECK_GRANULAR_STATE, /* a gm_point_state value */
  GM_CHECK_LABEL           /* a parallel-grid label: an integer in
                              [0, point count) */
} gm_array_check;

/* How an array is held in memory, against the file's bytes. */
typedef enum gm_array_form {
  GM_FORM_RAW,   /* the same bytes (doubles, int64 ids, int32 materials) */
  GM_FORM_BYTE,  /* uint8_t in memory, a double in the file */
  GM_FORM_INT32, /* int32_t in memory, a double in the file */
} gm_array_form;

typedef struct gm_array_slot {
  void *data;
  size_t bytes_per_point; /* in the file */
  gm_array_check check;
  gm_array_form form;
} gm_array_slot;

/* 30 in 3D (positions 3, velocities 3, stress 6, F 9, volume, state,
 * mass, initial volume, domain sizes 3, id, material), plus the granular
 * family's 2, APIC's 9 affine components and CPDI's 9 of the domain map:
 * 50 with all three; at most 31 in 2D (CPDI, granular, APIC,
 * axisymmetry). */
#define GM_CHECKPOINT_MAX_ARRAYS 52

/* The per-point arrays of the committed state, in the file order of
 * format `version` (GM_CHECKPOINT_VERSION to save), into slots (at most
 * GM_CHECKPOINT_MAX_ARRAYS); returns their number. The list depends only
 * on the setup and the version, so the saving and the loading domain
 * agree. */
size_t gm_checkpoint_point_arrays(const gm_domain *domain, uint32_t version,
                                  gm_array_slot *slots);

#endif
