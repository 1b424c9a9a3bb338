/*
 * test_vtu.c - VTU and PVD output. Writes a small plane-strain domain,
 * parses the file back (XML header offsets + raw appended data) and checks
 * that every value read equals, bit for bit, what the public field
 * accessors return; the same for the point-domain polygons (quads in 2D,
 * lines in 1D, hexahedra in 3D against the closed form x_p + F r and the
 * point's volume); checks I/O error reporting and the time series, with
 * and without domains, in 2D and 3D.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#define _POSIX_C_SOURCE 200809L

#include <dirent.h>
#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test_util.h"

enum { POINT_COUNT = 5 };

/* ------------------------------------------------------------ temp dirs */

static char temp_dir[256];

static void make_temp_dir(void) {
  const char *base = getenv("TMPDIR");
  snprintf(temp_dir, sizeof temp_dir, "%s/gm_vtu_XXXXXX",
           base && base[0] ? base : "/tmp");
  ck_assert_ptr_nonnull(mkdtemp(temp_dir));
}

/* Removes the files in temp_dir (it has no subdirectories) and the dir. */
static void remove_temp_dir(void) {
  DIR *dir = opendir(temp_dir);
  ck_assert_ptr_nonnull(dir);
  struct dirent *entry;
  char path[512];
  while ((entry = readdir(dir)) != NULL) {
    if (strcmp(entry->d_name, ".") == 0 || strcmp(entry->d_name, "..") == 0)
      continue;
    snprintf(path, sizeof path, "%s/%s", temp_dir, entry->d_name);
    ck_assert_int_eq(remove(path), 0);
  }
  closedir(dir);
  ck_assert_int_eq(rmdir(temp_dir), 0);
}

/* Number of entries in temp_dir other than "." and "..". */
static int temp_dir_entry_count(void) {
  DIR *dir = opendir(temp_dir);
  ck_assert_ptr_nonnull(dir);
  int count = 0;
  struct dirent *entry;
  while ((entry = readdir(dir)) != NULL)
    if (strcmp(entry->d_name, ".") != 0 && strcmp(entry->d_name, "..") != 0)
      count++;
  closedir(dir);
  return count;
}

/* Whole file, NUL-terminated (the binary part may hold more NULs). */
static char *read_whole_file(const char *path, size_t *size) {
  FILE *file = fopen(path, "rb");
  ck_assert_msg(file != NULL, "cannot open %s", path);
  ck_assert_int_eq(fseek(file, 0, SEEK_END), 0);
  long length = ftell(file);
  ck_assert_int_ge(length, 0);
  rewind(file);
  char *data = malloc((size_t)length + 1);
  ck_assert_ptr_nonnull(data);
  ck_assert_uint_eq(fread(data, 1, (size_t)length, file), (size_t)length);
  fclose(file);
  data[length] = '\0';
  *size = (size_t)length;
  return data;
}

/* ------------------------------------------------------------ the domain */

/* Five points at scattered positions (m), plane strain, elastic, with
 * the given shape functions. Values are arbitrary but distinct per point so
 * a shuffled or shifted array in the file cannot match by accident. The
 * initial stresses differ from point to point, so the first step deforms
 * the points (F != I) through their internal forces. */
static gm_domain *make_shaped_domain(gm_shape shape) {
  gm_domain_def def = gm_domain_def_default();
  def.shape = shape;
  def.extent[0] = 2.0;    /* m */
  def.extent[1] = 1.0;    /* m */
  def.cell_size = 0.25;   /* m */
  def.gravity[1] = -9.81; /* m/s^2, so the series frames differ */
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, 1000.0);
  const double position[POINT_COUNT * 2] = {1.55, 0.40, 0.30, 0.20, 0.90,
                                            0.65, 0.12, 0.37, 1.21, 0.83};
  const double velocity[POINT_COUNT * 2] = {0.1, -0.2, 0.0,  0.3,  -0.05,
                                            0.0, 0.7,  0.25, -0.4, 0.125};
  const double volume[POINT_COUNT] = {0.01, 0.02, 0.015, 0.0125, 0.03};
  const double mass[POINT_COUNT] = {10.5, 19.0, 16.25, 12.0, 31.5};
  double stress[POINT_COUNT * 6] = {0};
  for (int i = 0; i < POINT_COUNT; i++) {
    stress[i * 6 + GM_XX] = -1000.0 - 17.0 * i; /* Pa */
    stress[i * 6 + GM_YY] = -2000.0 + 3.5 * i;
    stress[i * 6 + GM_ZZ] = -900.0 - 0.25 * i;
    stress[i * 6 + GM_XY] = 40.0 * i - 60.0;
  }
  gm_points_def points = gm_points_def_default();
  points.count = POINT_COUNT;
  points.material = material;
  points.position = position;
  points.velocity = velocity;
  points.volume = volume;
  points.mass = mass;
  points.stress = stress;
  int64_t first_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, &first_id));
  return domain;
}

static gm_domain *make_domain(void) {
  return make_shaped_domain(GM_SHAPE_LINEAR);
}

/* The same five points in 3D (linear MPM, the only 3D shape so far), at
 * scattered x, y, z, each with all six stress components distinct and
 * nonzero, so that the first step shears every point in every plane (F
 * off the diagonal in all six places, checked by the test). */
static gm_domain *make_domain_3d(void) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.extent[0] = 2.0;    /* m */
  def.extent[1] = 1.0;    /* m */
  def.extent[2] = 1.0;    /* m */
  def.cell_size = 0.25;   /* m */
  def.gravity[2] = -9.81; /* m/s^2 */
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, 1000.0);
  const double position[POINT_COUNT * 3] = {1.55, 0.40, 0.55, 0.30, 0.20, 0.45,
                                            0.90, 0.65, 0.35, 0.12, 0.37, 0.62,
                                            1.21, 0.83, 0.41}; /* m */
  const double velocity[POINT_COUNT * 3] = {
      0.1, -0.2, 0.05, 0.0,  0.3,  -0.15, -0.05, 0.0,
      0.2, 0.7,  0.25, -0.1, -0.4, 0.125, 0.3}; /* m/s */
  const double volume[POINT_COUNT] = {0.01, 0.02, 0.015, 0.0125, 0.03};
  double stress[POINT_COUNT * 6];
  for (int i = 0; i < POINT_COUNT; i++)
    for (int k = 0; k < 6; k++) /* Pa: distinct, nonzero */
      stress[i * 6 + k] =
          k < 3 ? -1000.0 * (k + 1) - 17.0 * i : 40.0 * (k - 2) * (i + 1);
  gm_points_def points = gm_points_def_default();
  points.count = POINT_COUNT;
  points.material = material;
  points.position = position;
  points.velocity = velocity;
  points.volume = volume;
  points.stress = stress;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
  TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
  return domain;
}

/* ---------------------------------------------------------- VTU parsing */

typedef struct parsed_vtu {
  char *data;                 /* whole file */
  size_t size;                /* bytes */
  char *header;               /* copy of the XML before the '_' marker */
  const unsigned char *block; /* first byte after '_' */
} parsed_vtu;

static parsed_vtu parse_vtu(const char *path) {
  parsed_vtu vtu = {0};
  vtu.data = read_whole_file(path, &vtu.size);
  char *appended = strstr(vtu.data, "<AppendedData encoding=\"raw\">");
  ck_assert_ptr_nonnull(appended);
  char *marker = strchr(appended, '_');
  ck_assert_ptr_nonnull(marker);
  size_t header_length = (size_t)(marker - vtu.data);
  vtu.header = malloc(header_length + 1);
  ck_assert_ptr_nonnull(vtu.header);
  memcpy(vtu.header, vtu.data, header_length);
  vtu.header[header_length] = '\0';
  vtu.block = (const unsigned char *)marker + 1;
  return vtu;
}

static void free_vtu(parsed_vtu *vtu) {
  free(vtu->data);
  free(vtu->header);
}

/* Value of attribute `name` in the tag that contains `where`. */
static unsigned long long tag_attribute(const char *where, const char *name) {
  char pattern[64];
  snprintf(pattern, sizeof pattern, " %s=\"", name);
  const char *tag_end = strchr(where, '>');
  const char *found = strstr(where, pattern);
  ck_assert_msg(found && tag_end && found < tag_end, "no %s attribute", name);
  return strtoull(found + strlen(pattern), NULL, 10);
}

/* Payload of the DataArray called name: checks type, components and the
 * UInt64 size prefix; returns a pointer to the raw values. */
static const unsigned char *find_array(const parsed_vtu *vtu, const char *name,
                                       const char *type, size_t components,
                                       size_t value_size, size_t tuples) {
  char pattern[128];
  snprintf(pattern, sizeof pattern, "<DataArray type=\"%s\" Name=\"%s\"", type,
           name);
  const char *tag = strstr(vtu->header, pattern);
  ck_assert_msg(tag != NULL, "no %s array of type %s", name, type);
  ck_assert_uint_eq(tag_attribute(tag, "NumberOfComponents"), components);
  unsigned long long offset = tag_attribute(tag, "offset");
  uint64_t bytes = 0;
  const unsigned char *prefix = vtu->block + offset;
  ck_assert_msg(prefix + sizeof bytes <=
                    (const unsigned char *)vtu->data + vtu->size,
                "array %s starts past the end of the file", name);
  memcpy(&bytes, prefix, sizeof bytes);
  ck_assert_uint_eq(bytes, tuples * components * value_size);
  ck_assert(prefix + sizeof bytes + bytes <=
            (const unsigned char *)vtu->data + vtu->size);
  return prefix + sizeof bytes;
}

/* Reads the array and compares it bit for bit with the field padded to
 * `padded` components (zeros in the padding). */
static void check_field(const parsed_vtu *vtu, const gm_domain *domain,
                        const char *name, gm_field field, size_t padded) {
  size_t components = 0;
  TEST_ASSERT_OK(domain,
                 gm_domain_field_components(domain, field, &components));
  double expected[POINT_COUNT * 9];
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, field, expected,
                                             POINT_COUNT * components));
  const unsigned char *raw =
      find_array(vtu, name, "Float64", padded, sizeof(double), POINT_COUNT);
  for (size_t i = 0; i < POINT_COUNT; i++)
    for (size_t k = 0; k < padded; k++) {
      double value;
      memcpy(&value, raw + (i * padded + k) * sizeof value, sizeof value);
      double want = k < components ? expected[i * components + k] : 0.0;
      /* Exact: the file holds the same doubles, not a printed rounding. */
      ck_assert_msg(value == want, "%s[%zu][%zu] = %.17g, expected %.17g", name,
                    i, k, value, want);
    }
}

static const char *host_byte_order(void) {
  const uint16_t probe = 1;
  unsigned char first;
  memcpy(&first, &probe, 1);
  return first == 1 ? "LittleEndian" : "BigEndian";
}

/* ----------------------------------------------------------------- tests */

START_TEST(test_vtu_round_trip) {
  make_temp_dir();
  gm_domain *domain = make_domain();
  char path[512];
  snprintf(path, sizeof path, "%s/points.vtu", temp_dir);
  TEST_ASSERT_OK(domain, gm_domain_write_vtu(domain, path));
  /* Only the final file: the temporary one was renamed. */
  ck_assert_int_eq(temp_dir_entry_count(), 1);

  parsed_vtu vtu = parse_vtu(path);
  ck_assert_ptr_nonnull(strstr(vtu.header, "type=\"UnstructuredGrid\""));
  ck_assert_ptr_nonnull(strstr(vtu.header, "header_type=\"UInt64\""));
  char order[64];
  snprintf(order, sizeof order, "byte_order=\"%s\"", host_byte_order());
  ck_assert_ptr_nonnull(strstr(vtu.header, order));
  const char *piece = strstr(vtu.header, "<Piece");
  ck_assert_ptr_nonnull(piece);
  ck_assert_uint_eq(tag_attribute(piece, "NumberOfPoints"), POINT_COUNT);
  ck_assert_uint_eq(tag_attribute(piece, "NumberOfCells"), POINT_COUNT);

  check_field(&vtu, domain, "Points", GM_FIELD_POSITION, 3);
  check_field(&vtu, domain, "velocity", GM_FIELD_VELOCITY, 3);
  check_field(&vtu, domain, "mass", GM_FIELD_MASS, 1);
  check_field(&vtu, domain, "stress", GM_FIELD_STRESS, 6);
  check_field(&vtu, domain, "deformation_gradient",
              GM_FIELD_DEFORMATION_GRADIENT, 9);

  int64_t ids[POINT_COUNT];
  TEST_ASSERT_OK(domain, gm_domain_get_ids(domain, ids, POINT_COUNT));
  const unsigned char *raw =
      find_array(&vtu, "id", "Int64", 1, sizeof(int64_t), POINT_COUNT);
  for (size_t i = 0; i < POINT_COUNT; i++) {
    int64_t id;
    memcpy(&id, raw + i * sizeof id, sizeof id);
    ck_assert_int_eq(id, ids[i]);
  }
  /* One VTK_VERTEX (type 1) cell per point. */
  raw = find_array(&vtu, "types", "UInt8", 1, 1, POINT_COUNT);
  for (size_t i = 0; i < POINT_COUNT; i++)
    ck_assert_uint_eq(raw[i], 1);
  /* Point i in cell i, each cell ending one entry after the previous. */
  const unsigned char *connectivity = find_array(
      &vtu, "connectivity", "Int64", 1, sizeof(int64_t), POINT_COUNT);
  const unsigned char *offsets =
      find_array(&vtu, "offsets", "Int64", 1, sizeof(int64_t), POINT_COUNT);
  for (size_t i = 0; i < POINT_COUNT; i++) {
    int64_t point, offset;
    memcpy(&point, connectivity + i * sizeof point, sizeof point);
    memcpy(&offset, offsets + i * sizeof offset, sizeof offset);
    ck_assert_int_eq(point, (int64_t)i);
    ck_assert_int_eq(offset, (int64_t)i + 1);
  }
  /* The closing tags follow the last array: the file is complete. */
  const char *tail = "</AppendedData>\n</VTKFile>\n";
  ck_assert_uint_gt(vtu.size, strlen(tail));
  ck_assert_str_eq(vtu.data + vtu.size - strlen(tail), tail);
  free_vtu(&vtu);
  gm_domain_destroy(domain);
  remove_temp_dir();
}
END_TEST

START_TEST(test_vtu_missing_directory) {
  make_temp_dir();
  gm_domain *domain = make_domain();
  char path[512];
  snprintf(path, sizeof path, "%s/no-such-dir/points.vtu", temp_dir);
  ck_assert_int_eq(gm_domain_write_vtu(domain, path), GM_ERR_IO);
  const char *message = gm_domain_last_error(domain);
  ck_assert_msg(strstr(message, path) != NULL,
                "message '%s' does not name '%s'", message, path);
  ck_assert_int_eq(temp_dir_entry_count(), 0);
  ck_assert_int_eq(gm_domain_write_vtu(domain, NULL), GM_ERR_NULL);
  ck_assert_int_eq(gm_domain_write_vtu(NULL, path), GM_ERR_NULL);
  gm_domain_destroy(domain);
  remove_temp_dir();
}
END_TEST

/* Timesteps of the DataSets in a .pvd, in file order; returns the count
 * and checks each file name is stem_NNNNNN.vtu with N its position. */
static int read_pvd(const char *path, double *timesteps, int capacity) {
  size_t size = 0;
  char *text = read_whole_file(path, &size);
  ck_assert_ptr_nonnull(strstr(text, "</Collection>\n</VTKFile>"));
  int count = 0;
  for (const char *tag = strstr(text, "<DataSet"); tag;
       tag = strstr(tag + 1, "<DataSet")) {
    ck_assert_int_lt(count, capacity);
    const char *time = strstr(tag, "timestep=\"");
    ck_assert_ptr_nonnull(time);
    timesteps[count] = strtod(time + strlen("timestep=\""), NULL);
    char file[64];
    snprintf(file, sizeof file, "file=\"bar_%06d.vtu\"", count);
    const char *end = strchr(tag, '>');
    const char *found = strstr(tag, file);
    ck_assert_msg(found && found < end, "DataSet %d does not list %s", count,
                  file);
    count++;
  }
  free(text);
  return count;
}

START_TEST(test_series_three_frames) {
  make_temp_dir();
  gm_domain *domain = make_domain();
  char pvd[512];
  snprintf(pvd, sizeof pvd, "%s/bar.pvd", temp_dir);
  gm_series *series = NULL;
  ck_assert_int_eq(gm_series_create(pvd, &series), GM_OK);
  double times[3];
  for (int frame = 0; frame < 3; frame++) {
    if (frame > 0)
      TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
    TEST_ASSERT_OK(domain, gm_domain_get_time(domain, &times[frame], NULL));
    TEST_ASSERT_OK(domain, gm_series_write(series, domain));
    /* The .pvd is complete after every frame. */
    double listed[8];
    ck_assert_int_eq(read_pvd(pvd, listed, 8), frame + 1);
  }
  gm_series_destroy(series);

  double listed[8];
  ck_assert_int_eq(read_pvd(pvd, listed, 8), 3);
  for (int frame = 0; frame < 3; frame++) {
    /* %.17g round-trips a double exactly. */
    ck_assert_double_eq(listed[frame], times[frame]);
    if (frame > 0)
      ck_assert_double_gt(listed[frame], listed[frame - 1]);
    char path[512];
    snprintf(path, sizeof path, "%s/bar_%06d.vtu", temp_dir, frame);
    parsed_vtu vtu = parse_vtu(path);
    const char *piece = strstr(vtu.header, "<Piece");
    ck_assert_ptr_nonnull(piece);
    ck_assert_uint_eq(tag_attribute(piece, "NumberOfPoints"), POINT_COUNT);
    free_vtu(&vtu);
  }
  /* 3 frames + the .pvd, no temporary files left behind. */
  ck_assert_int_eq(temp_dir_entry_count(), 4);
  gm_domain_destroy(domain);
  remove_temp_dir();
}
END_TEST

START_TEST(test_series_bad_arguments) {
  make_temp_dir();
  gm_series *series = NULL;
  ck_assert_int_eq(gm_series_create(NULL, &series), GM_ERR_NULL);
  ck_assert_ptr_null(series);
  ck_assert_int_eq(gm_series_create("x.pvd", NULL), GM_ERR_NULL);
  char path[512];
  snprintf(path, sizeof path, "%s/", temp_dir);
  ck_assert_int_eq(gm_series_create(path, &series), GM_ERR_INVALID_ARGUMENT);
  snprintf(path, sizeof path, "%s/.pvd", temp_dir);
  ck_assert_int_eq(gm_series_create(path, &series), GM_ERR_INVALID_ARGUMENT);
  snprintf(path, sizeof path, "%s/missing/bar.pvd", temp_dir);
  ck_assert_int_eq(gm_series_create(path, &series), GM_ERR_IO);
  ck_assert_ptr_null(series);
  ck_assert_int_eq(temp_dir_entry_count(), 0);
  gm_series_destroy(NULL); /* a no-op */
  remove_temp_dir();
}
END_TEST

/* ------------------------------------------------------ domain polygons */

/* True when the DataArray called name lies inside the section `tag`
 * ("CellData", "PointData", ...) of the header. */
static bool array_in_section(const parsed_vtu *vtu, const char *name,
                             const char *tag) {
  char open[64], close[64], pattern[96];
  snprintf(open, sizeof open, "<%s", tag);
  snprintf(close, sizeof close, "</%s>", tag);
  snprintf(pattern, sizeof pattern, "Name=\"%s\"", name);
  const char *begin = strstr(vtu->header, open);
  const char *end = begin ? strstr(begin, close) : NULL;
  const char *array = strstr(vtu->header, pattern);
  return begin && end && array && begin < array && array < end;
}

/* Checks the cells of a domains file: `vertices` VTK points per material
 * point, numbered in file order, each cell of type cell_type. */
static void check_domain_cells(const parsed_vtu *vtu, size_t vertices,
                               unsigned cell_type) {
  const char *piece = strstr(vtu->header, "<Piece");
  ck_assert_ptr_nonnull(piece);
  ck_assert_uint_eq(tag_attribute(piece, "NumberOfPoints"),
                    vertices * POINT_COUNT);
  ck_assert_uint_eq(tag_attribute(piece, "NumberOfCells"), POINT_COUNT);
  const unsigned char *connectivity = find_array(
      vtu, "connectivity", "Int64", 1, sizeof(int64_t), vertices * POINT_COUNT);
  for (size_t v = 0; v < vertices * POINT_COUNT; v++) {
    int64_t point;
    memcpy(&point, connectivity + v * sizeof point, sizeof point);
    ck_assert_int_eq(point, (int64_t)v);
  }
  const unsigned char *offsets =
      find_array(vtu, "offsets", "Int64", 1, sizeof(int64_t), POINT_COUNT);
  const unsigned char *types =
      find_array(vtu, "types", "UInt8", 1, 1, POINT_COUNT);
  for (size_t i = 0; i < POINT_COUNT; i++) {
    int64_t offset;
    memcpy(&offset, offsets + i * sizeof offset, sizeof offset);
    ck_assert_int_eq(offset, (int64_t)((i + 1) * vertices));
    ck_assert_uint_eq(types[i], cell_type);
  }
}

/* Reads the VTK points of a domains file into points[v][3] (x, y, z) and
 * checks them bit for bit against GM_FIELD_DOMAIN_CORNERS: vertex c of
 * point i is corner c, padded with zeros. */
static void check_domain_points(const parsed_vtu *vtu, const gm_domain *domain,
                                size_t vertices, double points[][3]) {
  size_t components = 0;
  TEST_ASSERT_OK(domain, gm_domain_field_components(
                             domain, GM_FIELD_DOMAIN_CORNERS, &components));
  ck_assert_uint_eq(components, vertices == 8 ? 24 : vertices == 4 ? 8 : 2);
  size_t per_vertex = components / vertices; /* coordinates of a corner */
  double corners[POINT_COUNT * 24];
  TEST_ASSERT_OK(domain,
                 gm_domain_get_field(domain, GM_FIELD_DOMAIN_CORNERS, corners,
                                     POINT_COUNT * components));
  const unsigned char *raw = find_array(vtu, "Points", "Float64", 3,
                                        sizeof(double), vertices * POINT_COUNT);
  memcpy(points, raw, vertices * POINT_COUNT * 3 * sizeof(double));
  for (size_t v = 0; v < vertices * POINT_COUNT; v++)
    for (size_t k = 0; k < 3; k++) {
      double want = k < per_vertex ? corners[v * per_vertex + k] : 0.0;
      /* Exact: the file holds the same doubles. */
      ck_assert_msg(points[v][k] == want,
                    "vertex %zu coordinate %zu = %.17g, expected %.17g", v, k,
                    points[v][k], want);
    }
}

/* The fields are CellData of the domains file (one tuple per cell) and
 * equal the accessors' values bit for bit. */
static void check_domain_fields(const parsed_vtu *vtu,
                                const gm_domain *domain) {
  ck_assert_ptr_null(strstr(vtu->header, "<PointData"));
  const char *names[] = {"id",     "material", "velocity",
                         "volume", "density",  "stress"};
  for (size_t a = 0; a < sizeof names / sizeof names[0]; a++)
    ck_assert_msg(array_in_section(vtu, names[a], "CellData"),
                  "array %s is not CellData", names[a]);
  check_field(vtu, domain, "velocity", GM_FIELD_VELOCITY, 3);
  check_field(vtu, domain, "volume", GM_FIELD_VOLUME, 1);
  check_field(vtu, domain, "density", GM_FIELD_DENSITY, 1);
  check_field(vtu, domain, "stress", GM_FIELD_STRESS, 6);
  check_field(vtu, domain, "deformation_gradient",
              GM_FIELD_DEFORMATION_GRADIENT, 9);
  int64_t ids[POINT_COUNT];
  TEST_ASSERT_OK(domain, gm_domain_get_ids(domain, ids, POINT_COUNT));
  const unsigned char *raw =
      find_array(vtu, "id", "Int64", 1, sizeof(int64_t), POINT_COUNT);
  for (size_t i = 0; i < POINT_COUNT; i++) {
    int64_t id;
    memcpy(&id, raw + i * sizeof id, sizeof id);
    ck_assert_int_eq(id, ids[i]);
  }
}

/* Signed area (m^2) of the quadrilateral whose four vertices (x, y, z
 * each) start at quad, by the shoelace formula, taken relative to the
 * first vertex to limit cancellation. */
static double quad_area(const double *quad) {
  double area = 0.0;
  for (int c = 0; c < 4; c++) {
    const double *a = quad + 3 * c, *b = quad + 3 * ((c + 1) % 4);
    area += (a[0] - quad[0]) * (b[1] - quad[1]) -
            (b[0] - quad[0]) * (a[1] - quad[1]);
  }
  return 0.5 * area;
}

START_TEST(test_domains_round_trip_cpdi) {
  make_temp_dir();
  gm_domain *domain = make_shaped_domain(GM_SHAPE_CPDI);
  for (int step = 0; step < 2; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
  /* The domains must have sheared, or the parallelograms are untested. */
  double deformation[POINT_COUNT * 9];
  TEST_ASSERT_OK(domain,
                 gm_domain_get_field(domain, GM_FIELD_DEFORMATION_GRADIENT,
                                     deformation, POINT_COUNT * 9));
  double largest_shear = 0.0;
  for (size_t i = 0; i < POINT_COUNT; i++)
    largest_shear = fmax(largest_shear, fabs(deformation[i * 9 + 1]) +
                                            fabs(deformation[i * 9 + 3]));
  ck_assert_double_gt(largest_shear, 0.0);

  char path[512];
  snprintf(path, sizeof path, "%s/domains.vtu", temp_dir);
  TEST_ASSERT_OK(domain, gm_domain_write_domains_vtu(domain, path));
  ck_assert_int_eq(temp_dir_entry_count(), 1); /* no temporary file */
  parsed_vtu vtu = parse_vtu(path);
  ck_assert_ptr_nonnull(strstr(vtu.header, "type=\"UnstructuredGrid\""));
  check_domain_cells(&vtu, 4, 9); /* VTK_QUAD */
  double points[POINT_COUNT * 4][3];
  check_domain_points(&vtu, domain, 4, points);
  check_domain_fields(&vtu, domain);

  /* Closed form: a CPDI domain is the parallelogram spanned by F r1, F r2,
   * so its area is det F times the initial domain's, Lx Ly = V0 (the
   * default edges are sqrt(V0)); in plane strain F_zz = 1, so that is the
   * current volume V = det F V0. Counter-clockwise corners give a
   * positive area. Tolerance: the shoelace sum and sqrt(V0)^2 each round
   * a few times at coordinates ~1.5 m against areas ~0.01 m^2, so ~1e-14
   * relative; 1e-12 leaves room without hiding a wrong corner. */
  double volume[POINT_COUNT];
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_VOLUME, volume,
                                             POINT_COUNT));
  for (size_t i = 0; i < POINT_COUNT; i++) {
    double area = quad_area(points[4 * i]);
    ck_assert_msg(fabs(area - volume[i]) <= 1e-12 * volume[i],
                  "point %zu: quad area %.17g, volume %.17g", i, area,
                  volume[i]);
  }

  /* The corners are computed, never stored: copy only. */
  const double *view = NULL;
  ck_assert_int_eq(
      gm_domain_view_field(domain, GM_FIELD_DOMAIN_CORNERS, 0, &view),
      GM_ERR_UNSUPPORTED);
  free_vtu(&vtu);
  gm_domain_destroy(domain);
  remove_temp_dir();
}
END_TEST

/* 3D points file: the same checks as the plane one, on three-component
 * positions and velocities and a stress with all six components. */
START_TEST(test_vtu_round_trip_3d) {
  make_temp_dir();
  gm_domain *domain = make_domain_3d();
  char path[512];
  snprintf(path, sizeof path, "%s/points.vtu", temp_dir);
  TEST_ASSERT_OK(domain, gm_domain_write_vtu(domain, path));
  ck_assert_int_eq(temp_dir_entry_count(), 1);
  parsed_vtu vtu = parse_vtu(path);
  ck_assert_ptr_nonnull(strstr(vtu.header, "type=\"UnstructuredGrid\""));
  const char *piece = strstr(vtu.header, "<Piece");
  ck_assert_ptr_nonnull(piece);
  ck_assert_uint_eq(tag_attribute(piece, "NumberOfPoints"), POINT_COUNT);
  ck_assert_uint_eq(tag_attribute(piece, "NumberOfCells"), POINT_COUNT);
  check_field(&vtu, domain, "Points", GM_FIELD_POSITION, 3);
  check_field(&vtu, domain, "velocity", GM_FIELD_VELOCITY, 3);
  check_field(&vtu, domain, "stress", GM_FIELD_STRESS, 6);
  check_field(&vtu, domain, "deformation_gradient",
              GM_FIELD_DEFORMATION_GRADIENT, 9);
  check_field(&vtu, domain, "domain_size", GM_FIELD_DOMAIN_SIZE, 3);
  const unsigned char *types =
      find_array(&vtu, "types", "UInt8", 1, 1, POINT_COUNT);
  for (size_t i = 0; i < POINT_COUNT; i++)
    ck_assert_uint_eq(types[i], 1); /* VTK_VERTEX */
  const char *tail = "</AppendedData>\n</VTKFile>\n";
  ck_assert_str_eq(vtu.data + vtu.size - strlen(tail), tail);
  free_vtu(&vtu);
  gm_domain_destroy(domain);
  remove_temp_dir();
}
END_TEST

/* Volume (m^3) of the hexahedron whose 8 vertices (x, y, z each) start at
 * hex, in VTK_HEXAHEDRON order, by the divergence theorem: the sum over
 * its six faces, each split into two triangles, of (a . (b x c)) / 6 with
 * a, b, c taken relative to vertex 0 (limits cancellation). The faces are
 * VTK's, listed so that their normals point outwards: a hexahedron with
 * its vertices in VTK's order has a positive volume, a mirrored or
 * scrambled one does not. */
static double hexahedron_volume(const double *hex) {
  static const int face[6][4] = {{0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4},
                                 {3, 7, 6, 2}, {0, 3, 2, 1}, {4, 5, 6, 7}};
  double volume = 0.0;
  for (int f = 0; f < 6; f++)
    for (int t = 0; t < 2; t++) {
      int corner[3] = {face[f][0], face[f][1 + t], face[f][2 + t]};
      double r[3][3];
      for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++)
          r[c][k] = hex[3 * corner[c] + k] - hex[k];
      volume += (r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                 r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                 r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0])) /
                6.0;
    }
  return volume;
}

/* 3D domains: one VTK_HEXAHEDRON (type 12) per point, its vertices the
 * point's 8 corners. Closed form (gm_fields(3)): corner c is x_p + F (s_x
 * l_x/2, s_y l_y/2, s_z l_z/2) with l the initial edges (cbrt(V0) each by
 * default) and the signs s in VTK's order, lower face (s_z = -1)
 * counter-clockwise from (-, -) seen from +z, then the upper face. The
 * points were sheared by a step in all six off-diagonal places of F. */
START_TEST(test_domains_3d_hexahedra) {
  make_temp_dir();
  gm_domain *domain = make_domain_3d();
  double f[POINT_COUNT * 9], x[POINT_COUNT * 3], size[POINT_COUNT * 3];
  double volume[POINT_COUNT];
  TEST_ASSERT_OK(domain,
                 gm_domain_get_field(domain, GM_FIELD_DEFORMATION_GRADIENT, f,
                                     POINT_COUNT * 9));
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION, x,
                                             POINT_COUNT * 3));
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_DOMAIN_SIZE, size,
                                             POINT_COUNT * 3));
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_VOLUME, volume,
                                             POINT_COUNT));
  /* Every component of F sheared or stretched at some point by more than
   * 1e-5 (measured: 1.5e-4 to 2.1e-3), so each term of the closed form
   * moves some corner by more than 1e-6 m (l/2 >= 0.1 m here). */
  for (int k = 0; k < 9; k++) {
    double moved = 0.0;
    for (size_t i = 0; i < POINT_COUNT; i++)
      moved = fmax(moved, fabs(f[i * 9 + k] - (k % 4 == 0 ? 1.0 : 0.0)));
    ck_assert_msg(moved > 1e-5, "F component %d moved only %g", k, moved);
  }
  char path[512];
  snprintf(path, sizeof path, "%s/domains.vtu", temp_dir);
  TEST_ASSERT_OK(domain, gm_domain_write_domains_vtu(domain, path));
  ck_assert_int_eq(temp_dir_entry_count(), 1);
  parsed_vtu vtu = parse_vtu(path);
  check_domain_cells(&vtu, 8, 12); /* VTK_HEXAHEDRON */
  double points[POINT_COUNT * 8][3];
  check_domain_points(&vtu, domain, 8, points);
  check_domain_fields(&vtu, domain);
  static const double sign[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1},
                                    {-1, 1, -1},  {-1, -1, 1}, {1, -1, 1},
                                    {1, 1, 1},    {-1, 1, 1}};
  for (size_t i = 0; i < POINT_COUNT; i++) {
    for (int c = 0; c < 8; c++)
      for (int r = 0; r < 3; r++) {
        double want = x[i * 3 + r];
        for (int a = 0; a < 3; a++)
          want += f[i * 9 + 3 * r + a] * sign[c][a] * 0.5 * size[i * 3 + a];
        /* Measured: equal bitwise (the library sums the same products
         * in this order). 1e-13 m allows another order (a few roundings
         * at ~1.5 m) and still fails a term of F dropped or misplaced
         * (above 1e-6 m at some corner, see above). */
        ck_assert_msg(fabs(points[8 * i + (size_t)c][r] - want) <= 1e-13,
                      "point %zu corner %d coordinate %d: %.17g, closed form "
                      "%.17g",
                      i, c, r, points[8 * i + (size_t)c][r], want);
      }
    /* det F l_x l_y l_z = det F V0 = V (l = cbrt(V0)): to round-off.
     * Measured relative differences 1.2e-16 to 1.2e-15 (the face sums
     * cancel at coordinates ~1 m against volumes ~0.01 m^3); 1e-12 still
     * fails a wrong vertex order (negative or another volume) or a
     * domain not carried by F (det F differs from 1 by up to 1e-3 here). */
    double hexahedron = hexahedron_volume(points[8 * i]);
    ck_assert_msg(fabs(hexahedron - volume[i]) <= 1e-12 * volume[i],
                  "point %zu: hexahedron volume %.17g, point volume %.17g", i,
                  hexahedron, volume[i]);
  }
  free_vtu(&vtu);
  gm_domain_destroy(domain);
  remove_temp_dir();
}
END_TEST

/* A 3D series with domains: each frame has its points file and its
 * hexahedra, both listed at the frame's time. */
START_TEST(test_series_3d) {
  make_temp_dir();
  gm_domain *domain = make_domain_3d();
  char pvd[512];
  snprintf(pvd, sizeof pvd, "%s/bar.pvd", temp_dir);
  gm_series *series = NULL;
  ck_assert_int_eq(gm_series_create(pvd, &series), GM_OK);
  ck_assert_int_eq(gm_series_set_domains(series, 1), GM_OK);
  for (int frame = 0; frame < 2; frame++) {
    if (frame > 0)
      TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
    TEST_ASSERT_OK(domain, gm_series_write(series, domain));
  }
  gm_series_destroy(series);
  for (int frame = 0; frame < 2; frame++)
    for (int part = 0; part < 2; part++) {
      char path[512];
      snprintf(path, sizeof path, "%s/bar%s_%06d.vtu", temp_dir,
               part ? "_domains" : "", frame);
      parsed_vtu vtu = parse_vtu(path);
      const char *piece = strstr(vtu.header, "<Piece");
      ck_assert_ptr_nonnull(piece);
      ck_assert_uint_eq(tag_attribute(piece, "NumberOfPoints"),
                        (part ? 8 : 1) * POINT_COUNT);
      const unsigned char *types =
          find_array(&vtu, "types", "UInt8", 1, 1, POINT_COUNT);
      ck_assert_uint_eq(types[0], part ? 12 : 1);
      free_vtu(&vtu);
    }
  ck_assert_int_eq(temp_dir_entry_count(), 5); /* 4 files and the .pvd */
  gm_domain_destroy(domain);
  remove_temp_dir();
}
END_TEST

/* 1D: each domain is a VTK_LINE between its two ends. */
START_TEST(test_domains_1d_lines) {
  make_temp_dir();
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_1D;
  def.extent[0] = 2.0;  /* m */
  def.cell_size = 0.25; /* m */
  def.shape = GM_SHAPE_UGIMP;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, 1000.0);
  const double position[POINT_COUNT] = {0.3, 0.55, 1.0, 1.4, 1.7};  /* m */
  const double volume[POINT_COUNT] = {0.1, 0.05, 0.2, 0.125, 0.15}; /* m */
  test_add_points(domain, material, POINT_COUNT, position, NULL, volume);
  char path[512];
  snprintf(path, sizeof path, "%s/lines.vtu", temp_dir);
  TEST_ASSERT_OK(domain, gm_domain_write_domains_vtu(domain, path));
  parsed_vtu vtu = parse_vtu(path);
  check_domain_cells(&vtu, 2, 3); /* VTK_LINE */
  double points[POINT_COUNT * 2][3];
  check_domain_points(&vtu, domain, 2, points);
  check_domain_fields(&vtu, domain);
  /* Closed form: the uGIMP domain is the initial one, the volume (m per
   * unit area in 1D) centred on the point. Tolerance: the two ends are
   * x -+ L/2, each rounded once at |x| <= 2 m: 4 ulps of 2 m. */
  double position_now[POINT_COUNT];
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION,
                                             position_now, POINT_COUNT));
  double initial_volume[POINT_COUNT];
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_INITIAL_VOLUME,
                                             initial_volume, POINT_COUNT));
  for (size_t i = 0; i < POINT_COUNT; i++) {
    const double tolerance = 4.0 * 2.0 * DBL_EPSILON; /* m */
    double low = points[2 * i][0], high = points[2 * i + 1][0];
    ck_assert_double_eq_tol(high - low, initial_volume[i], tolerance);
    ck_assert_double_eq_tol(0.5 * (low + high), position_now[i], tolerance);
  }
  free_vtu(&vtu);
  gm_domain_destroy(domain);
  remove_temp_dir();
}
END_TEST

START_TEST(test_domains_missing_directory) {
  make_temp_dir();
  gm_domain *domain = make_shaped_domain(GM_SHAPE_CPGIMP);
  char path[512];
  snprintf(path, sizeof path, "%s/no-such-dir/domains.vtu", temp_dir);
  ck_assert_int_eq(gm_domain_write_domains_vtu(domain, path), GM_ERR_IO);
  const char *message = gm_domain_last_error(domain);
  ck_assert_msg(strstr(message, path) != NULL,
                "message '%s' does not name '%s'", message, path);
  ck_assert_int_eq(temp_dir_entry_count(), 0);
  ck_assert_int_eq(gm_domain_write_domains_vtu(domain, NULL), GM_ERR_NULL);
  ck_assert_int_eq(gm_domain_write_domains_vtu(domain, ""),
                   GM_ERR_INVALID_ARGUMENT);
  ck_assert_int_eq(gm_domain_write_domains_vtu(NULL, path), GM_ERR_NULL);
  gm_domain_destroy(domain);
  remove_temp_dir();
}
END_TEST

/* One <DataSet> of a .pvd. */
typedef struct pvd_entry {
  double timestep; /* s */
  int part;
  char file[64];
} pvd_entry;

/* The DataSets of a .pvd, in file order; returns their count. */
static int read_pvd_entries(const char *path, pvd_entry *entries,
                            int capacity) {
  size_t size = 0;
  char *text = read_whole_file(path, &size);
  ck_assert_ptr_nonnull(strstr(text, "</Collection>\n</VTKFile>"));
  int count = 0;
  for (const char *tag = strstr(text, "<DataSet"); tag;
       tag = strstr(tag + 1, "<DataSet")) {
    ck_assert_int_lt(count, capacity);
    pvd_entry *entry = &entries[count++];
    const char *time = strstr(tag, "timestep=\"");
    const char *part = strstr(tag, "part=\"");
    const char *file = strstr(tag, "file=\"");
    ck_assert(time && part && file);
    entry->timestep = strtod(time + strlen("timestep=\""), NULL);
    entry->part = (int)strtol(part + strlen("part=\""), NULL, 10);
    file += strlen("file=\"");
    size_t length = strcspn(file, "\"");
    ck_assert_uint_lt(length, sizeof entry->file);
    memcpy(entry->file, file, length);
    entry->file[length] = '\0';
  }
  free(text);
  return count;
}

/* Frames 0 and 3 without domains, 1 and 2 with: the .pvd lists part 0 for
 * every frame and part 1, at the same timestep, for frames 1 and 2. */
START_TEST(test_series_with_domains) {
  make_temp_dir();
  gm_domain *domain = make_shaped_domain(GM_SHAPE_CPDI);
  char pvd[512];
  snprintf(pvd, sizeof pvd, "%s/bar.pvd", temp_dir);
  gm_series *series = NULL;
  ck_assert_int_eq(gm_series_create(pvd, &series), GM_OK);
  ck_assert_int_eq(gm_series_set_domains(NULL, 1), GM_ERR_NULL);
  const bool domains[4] = {false, true, true, false};
  double times[4];
  for (int frame = 0; frame < 4; frame++) {
    if (frame > 0)
      TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
    ck_assert_int_eq(gm_series_set_domains(series, domains[frame] ? 7 : 0),
                     GM_OK);
    TEST_ASSERT_OK(domain, gm_domain_get_time(domain, &times[frame], NULL));
    TEST_ASSERT_OK(domain, gm_series_write(series, domain));
  }
  gm_series_destroy(series);

  pvd_entry entries[16];
  ck_assert_int_eq(read_pvd_entries(pvd, entries, 16), 6);
  int e = 0;
  for (int frame = 0; frame < 4; frame++) {
    for (int part = 0; part < (domains[frame] ? 2 : 1); part++, e++) {
      char expected[64];
      snprintf(expected, sizeof expected, "bar%s_%06d.vtu",
               part ? "_domains" : "", frame);
      ck_assert_str_eq(entries[e].file, expected);
      ck_assert_int_eq(entries[e].part, part);
      /* %.17g round-trips a double exactly. */
      ck_assert_double_eq(entries[e].timestep, times[frame]);
      char path[512];
      snprintf(path, sizeof path, "%s/%s", temp_dir, expected);
      parsed_vtu vtu = parse_vtu(path);
      const char *piece = strstr(vtu.header, "<Piece");
      ck_assert_ptr_nonnull(piece);
      ck_assert_uint_eq(tag_attribute(piece, "NumberOfCells"), POINT_COUNT);
      ck_assert_uint_eq(tag_attribute(piece, "NumberOfPoints"),
                        (part ? 4 : 1) * POINT_COUNT);
      free_vtu(&vtu);
    }
  }
  /* 4 point files, 2 domain files and the .pvd; no temporary files. */
  ck_assert_int_eq(temp_dir_entry_count(), 7);
  gm_domain_destroy(domain);
  remove_temp_dir();
}
END_TEST

/* A domains file that cannot be written fails the frame: GM_ERR_IO naming
 * the file, the .pvd does not list the frame, and the next call writes the
 * same frame number. A directory in the way makes the rename fail. */
START_TEST(test_series_domains_failure) {
  make_temp_dir();
  gm_domain *domain = make_shaped_domain(GM_SHAPE_UGIMP);
  char pvd[512], blocker[512];
  snprintf(pvd, sizeof pvd, "%s/bar.pvd", temp_dir);
  snprintf(blocker, sizeof blocker, "%s/bar_domains_000000.vtu", temp_dir);
  ck_assert_int_eq(mkdir(blocker, 0700), 0);
  gm_series *series = NULL;
  ck_assert_int_eq(gm_series_create(pvd, &series), GM_OK);
  ck_assert_int_eq(gm_series_set_domains(series, 1), GM_OK);
  ck_assert_int_eq(gm_series_write(series, domain), GM_ERR_IO);
  const char *message = gm_domain_last_error(domain);
  ck_assert_msg(strstr(message, blocker) != NULL,
                "message '%s' does not name '%s'", message, blocker);
  pvd_entry entries[4];
  ck_assert_int_eq(read_pvd_entries(pvd, entries, 4), 0);
  ck_assert_int_eq(rmdir(blocker), 0);
  TEST_ASSERT_OK(domain, gm_series_write(series, domain));
  ck_assert_int_eq(read_pvd_entries(pvd, entries, 4), 2);
  ck_assert_str_eq(entries[0].file, "bar_000000.vtu");
  ck_assert_str_eq(entries[1].file, "bar_domains_000000.vtu");
  gm_series_destroy(series);
  /* The two frame files and the .pvd; no temporary file left. */
  ck_assert_int_eq(temp_dir_entry_count(), 3);
  gm_domain_destroy(domain);
  remove_temp_dir();
}
END_TEST

static Suite *vtu_suite(void) {
  Suite *suite = suite_create("vtu");
  TCase *vtu = tcase_create("vtu");
  tcase_add_test(vtu, test_vtu_round_trip);
  tcase_add_test(vtu, test_vtu_missing_directory);
  tcase_add_test(vtu, test_vtu_round_trip_3d);
  suite_add_tcase(suite, vtu);
  TCase *domains = tcase_create("domains");
  tcase_add_test(domains, test_domains_round_trip_cpdi);
  tcase_add_test(domains, test_domains_1d_lines);
  tcase_add_test(domains, test_domains_3d_hexahedra);
  tcase_add_test(domains, test_domains_missing_directory);
  suite_add_tcase(suite, domains);
  TCase *series = tcase_create("series");
  tcase_add_test(series, test_series_three_frames);
  tcase_add_test(series, test_series_bad_arguments);
  tcase_add_test(series, test_series_with_domains);
  tcase_add_test(series, test_series_3d);
  tcase_add_test(series, test_series_domains_failure);
  suite_add_tcase(suite, series);
  return suite;
}

int main(void) {
  return test_run_suite(vtu_suite()) ? 1 : 0;
}
