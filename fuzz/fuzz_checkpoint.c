/*
 * fuzz/fuzz_checkpoint.c - libFuzzer harness for checkpoint loading
 * (gm_domain_load). The input is a checkpoint file; before it is written
 * to disk the harness makes its header consistent (the payload size, and
 * the FNV-1a 64 checksum of lib/io/checkpoint_format.h recomputed), so that
 * mutations get past the checksum and reach the parser of the payload,
 * where a hostile file could do harm. Besides the sanitizers' findings,
 * it aborts where a promise of gm_checkpoint(3) breaks: a refused file
 * leaves a message and the domain as it was (time, step count, points,
 * positions); an accepted one gives a domain that can step or refuses to
 * with a message.
 *
 * The seed corpus is generated, not stored (a checkpoint holds the
 * writer's byte order and the format version): run the harness with
 * GM_FUZZ_WRITE_SEED=<file> and it saves the checkpoint of its own scene
 * there and exits (`make fuzz` does this).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>
#include <granmpm/mohr_coulomb.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { HEADER_SIZE = 32 }; /* bytes, lib/io/checkpoint_format.h */
static const uint64_t FNV_OFFSET = 0xcbf29ce484222325ull;
static const uint64_t FNV_PRIME = 0x100000001b3ull;

static uint64_t fnv1a64(const uint8_t *bytes, size_t size, uint64_t hash) {
  for (size_t i = 0; i < size; i++)
    hash = (hash ^ bytes[i]) * FNV_PRIME;
  return hash;
}

static void broken(const char *promise, const gm_domain *domain) {
  fprintf(stderr, "broken promise: %s (%s)\n", promise,
          domain ? gm_domain_last_error(domain) : "");
  abort();
}

/* The scene every input is loaded into: granular Mohr-Coulomb with CPDI
 * domains, an elastic block and a frictional wall, so that the file has
 * point states, domain maps and force reports to parse. */
static gm_domain *make_scene(void) {
  gm_domain_def def = gm_domain_def_default();
  def.extent[0] = 1.0;
  def.extent[1] = 1.0;
  def.cell_size = 0.1;
  def.gravity[1] = -9.81;
  def.walls[GM_FACE_XMIN] = def.walls[GM_FACE_XMAX] = GM_WALL_SLIP;
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  def.shape = GM_SHAPE_CPDI;
  def.family = GM_FAMILY_GRANULAR;
  gm_domain *domain = NULL;
  if (gm_domain_create(&def, &domain) != GM_OK)
    return NULL;
  gm_mohr_coulomb_def sand = gm_mohr_coulomb_def_default();
  sand.youngs_modulus = 1e6;
  gm_elastic_def block = gm_elastic_def_default();
  block.youngs_modulus = 1e6;
  int sand_id = -1, block_id = -1, wall_id = -1;
  gm_wall_def wall = gm_wall_def_default();
  wall.point[1] = 0.05;
  wall.friction_static = wall.friction_kinetic = 0.4;
  gm_fill_def fill = gm_fill_def_default();
  fill.upper[0] = 0.3;
  fill.upper[1] = 0.4;
  fill.lower[1] = 0.05;
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = 0.95 * sand.density; /* kg/m^3 */
  gm_status status = gm_domain_add_mohr_coulomb(domain, &sand, &sand_id);
  if (status == GM_OK)
    status = gm_domain_add_elastic(domain, &block, &block_id);
  if (status == GM_OK)
    status = gm_domain_set_granular(domain, sand_id, &granular);
  if (status == GM_OK)
    status = gm_domain_add_wall(domain, &wall, &wall_id);
  fill.material = sand_id;
  if (status == GM_OK)
    status = gm_domain_fill_box(domain, &fill, NULL, NULL);
  fill.material = block_id;
  fill.lower[0] = 0.6;
  fill.upper[0] = 0.8;
  if (status == GM_OK)
    status = gm_domain_fill_box(domain, &fill, NULL, NULL);
  if (status != GM_OK) {
    fprintf(stderr, "fuzz_checkpoint: the scene does not build: %s\n",
            gm_domain_last_error(domain));
    gm_domain_destroy(domain);
    return NULL;
  }
  return domain;
}

/* The 3D scene (GM_GEOMETRY_3D: linear shapes, plain family): an elastic
 * block on a fixed floor, so that 3D files (six stresses, nine components
 * of F, z positions) reach their own parser. */
static gm_domain *make_scene_3d(void) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = GM_SHAPE_LINEAR;
  def.family = GM_FAMILY_PLAIN;
  def.extent[0] = def.extent[1] = def.extent[2] = 0.6;
  def.cell_size = 0.1;
  def.gravity[2] = -9.81;
  def.walls[GM_FACE_ZMIN] = GM_WALL_FIXED;
  gm_domain *domain = NULL;
  if (gm_domain_create(&def, &domain) != GM_OK)
    return NULL;
  gm_elastic_def block = gm_elastic_def_default();
  block.youngs_modulus = 1e6;
  int block_id = -1;
  gm_fill_def fill = gm_fill_def_default();
  fill.lower[0] = fill.lower[1] = 0.1;
  fill.upper[0] = fill.upper[1] = 0.3;
  fill.upper[2] = 0.2;
  gm_status status = gm_domain_add_elastic(domain, &block, &block_id);
  fill.material = block_id;
  if (status == GM_OK)
    status = gm_domain_fill_box(domain, &fill, NULL, NULL);
  if (status != GM_OK) {
    fprintf(stderr, "fuzz_checkpoint: the 3D scene does not build: %s\n",
            gm_domain_last_error(domain));
    gm_domain_destroy(domain);
    return NULL;
  }
  return domain;
}

/* Writes the checkpoint of a scene after five steps to `path`; 0 on
 * success. */
static int write_seed(gm_domain *domain, const char *path) {
  int failed = !domain;
  for (int i = 0; !failed && i < 5; i++)
    failed = gm_domain_step(domain, 0.0) != GM_OK;
  failed = failed || gm_domain_save(domain, path) != GM_OK;
  if (failed && domain)
    fprintf(stderr, "fuzz_checkpoint: %s\n", gm_domain_last_error(domain));
  gm_domain_destroy(domain);
  fprintf(stderr, "%s seed checkpoint %s\n",
          failed ? "could not write" : "wrote", path);
  return failed;
}

static char file_path[64];

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  snprintf(file_path, sizeof file_path, "/tmp/gm-fuzz-%ld.ckpt",
           (long)getpid());
  /* GM_FUZZ_WRITE_SEED=<file>: the 2D scene's checkpoint there, and the
   * 3D scene's in <file>.3d. */
  const char *seed = getenv("GM_FUZZ_WRITE_SEED");
  if (!seed)
    return 0;
  char seed_3d[512];
  snprintf(seed_3d, sizeof seed_3d, "%s.3d", seed);
  int failed = write_seed(make_scene(), seed);
  failed = write_seed(make_scene_3d(), seed_3d) || failed;
  exit(failed);
}

/* A digest of what a refused load must leave alone. */
static uint64_t domain_digest(const gm_domain *domain) {
  double time = 0.0;
  uint64_t steps = 0;
  gm_domain_get_time(domain, &time, &steps);
  uint64_t hash = fnv1a64((const uint8_t *)&time, sizeof time, FNV_OFFSET);
  hash = fnv1a64((const uint8_t *)&steps, sizeof steps, hash);
  size_t count = gm_domain_point_count(domain);
  hash = fnv1a64((const uint8_t *)&count, sizeof count, hash);
  for (size_t k = 0; k < 3; k++) { /* z is refused in 2D: skipped */
    const double *x = NULL;
    if (count &&
        gm_domain_view_field(domain, GM_FIELD_POSITION, k, &x) == GM_OK)
      hash = fnv1a64((const uint8_t *)x, count * sizeof *x, hash);
  }
  return hash;
}

static void load_into(gm_domain *domain);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  uint8_t *file = malloc(size ? size : 1);
  if (!file)
    return 0;
  memcpy(file, data, size);
  if (size >= HEADER_SIZE) {
    uint64_t payload = size - HEADER_SIZE;
    memcpy(file + 16, &payload, sizeof payload);
    uint64_t hash = fnv1a64(file, 24, FNV_OFFSET);
    hash = fnv1a64(file + HEADER_SIZE, size - HEADER_SIZE, hash);
    memcpy(file + 24, &hash, sizeof hash);
  }
  FILE *out = fopen(file_path, "wb");
  if (!out || fwrite(file, 1, size, out) != size) {
    if (out)
      fclose(out);
    free(file);
    return 0;
  }
  fclose(out);
  free(file);
  /* Every input is loaded into both scenes: a file of the other geometry
   * must be refused as cleanly as a damaged one. */
  load_into(make_scene());
  load_into(make_scene_3d());
  remove(file_path);
  return 0;
}

/* Loads the input file into the scene and checks gm_checkpoint(3)'s
 * promises; destroys the scene. */
static void load_into(gm_domain *domain) {
  if (!domain)
    broken("the harness's scene builds", NULL);
  uint64_t before = domain_digest(domain);
  gm_status status = gm_domain_load(domain, file_path);
  if (status != GM_OK) {
    const char *message = gm_domain_last_error(domain);
    if (!message || !message[0])
      broken("a refused checkpoint leaves a message", domain);
    if (domain_digest(domain) != before)
      broken("a refused checkpoint leaves the domain as it was", domain);
  } else {
    for (int i = 0; i < 2; i++) {
      status = gm_domain_step(domain, 0.0);
      if (status != GM_OK && !gm_domain_last_error(domain)[0])
        broken("a failed step after a load leaves a message", domain);
    }
  }
  gm_domain_destroy(domain);
}
