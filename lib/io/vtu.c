/*
 * vtu.c - the VTK XML UnstructuredGrid writer (format version 1.0, raw
 * appended binary data, the format ParaView reads natively) and
 * gm_domain_write_vtu, which writes every point and field with it. The
 * domain polygons of vtu_domains.c use the same writer with another layout
 * (vtu_format.h).
 *
 * Written on top of the public field accessors (gm_domain_get_field,
 * gm_domain_get_ids) so it does not depend on the internal point layout.
 *
 * File layout: an XML header whose DataArrays all say format="appended" and
 * give an offset, then <AppendedData encoding="raw">, an underscore, and the
 * arrays back to back. Offsets count bytes from the first byte after the
 * underscore; every array is prefixed by its size in bytes as a UInt64
 * (header_type="UInt64"), in the host byte order declared in byte_order.
 *
 * In the points file every material point is one VTK point and one
 * VTK_VERTEX cell, so ParaView shows the points without a Glyph filter.
 * Vectors are padded to 3 components (VTK's convention, so ParaView treats
 * them as vectors); the stress has 6 components in Voigt order
 * xx yy zz xy yz zx (GM_XX..GM_ZX) and F 9 components, row-major.
 *
 * The file is written to "<path>.tmp" and renamed over path only when it is
 * complete, so a failed write never leaves a truncated file under path.
 */
#include "io/io.h"

#include "io/vtu_format.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

typedef enum vtu_type { VTU_FLOAT64, VTU_INT64, VTU_INT32, VTU_UINT8 } vtu_type;

/* Source of an array's values. */
typedef enum vtu_source {
  SOURCE_VERTICES,     /* the layout's vertex field, padded to x, y, z */
  SOURCE_CONNECTIVITY, /* 0, 1, ...: VTK points in file order */
  SOURCE_OFFSETS,      /* end of each cell: vertices, 2 vertices, ... */
  SOURCE_CELL_TYPES,   /* the layout's cell type for every cell */
  SOURCE_FIELD,        /* gm_domain_get_field(field), padded */
  SOURCE_IDS,          /* gm_domain_get_ids() */
  SOURCE_INTEGER       /* an integer-valued field converted to Int32 */
} vtu_source;

/* Where an array goes in the XML tree. SECTION_FIELDS is the layout's
 * PointData or CellData: one tuple per material point either way. */
typedef enum vtu_section {
  SECTION_FIELDS,
  SECTION_POINTS,
  SECTION_CELLS
} vtu_section;

typedef struct vtu_array {
  const char *name;
  vtu_section section;
  vtu_source source;
  gm_field field; /* for SOURCE_FIELD and SOURCE_INTEGER */
  vtu_type type;
  size_t components;                  /* in the file (after padding) */
  const char *const *component_names; /* component names, or NULL */
} vtu_array;

/* ComponentName attributes: Voigt order GM_XX..GM_ZX; F row-major. */
static const char *const stress_names[] = {"xx", "yy", "zz", "xy", "yz", "zx"};
static const char *const tensor_names[] = {"xx", "xy", "xz", "yx", "yy",
                                           "yz", "zx", "zy", "zz"};

/* The arrays of a file, in file order. The single FieldData array,
 * TimeValue, is handled separately (it has 1 tuple, not one per point). */
static const vtu_array vtu_arrays[] = {
    {"Points", SECTION_POINTS, SOURCE_VERTICES, GM_FIELD_POSITION, VTU_FLOAT64,
     3, NULL},
    {"connectivity", SECTION_CELLS, SOURCE_CONNECTIVITY, GM_FIELD_ID, VTU_INT64,
     1, NULL},
    {"offsets", SECTION_CELLS, SOURCE_OFFSETS, GM_FIELD_ID, VTU_INT64, 1, NULL},
    {"types", SECTION_CELLS, SOURCE_CELL_TYPES, GM_FIELD_ID, VTU_UINT8, 1,
     NULL},
    {"id", SECTION_FIELDS, SOURCE_IDS, GM_FIELD_ID, VTU_INT64, 1, NULL},
    {"material", SECTION_FIELDS, SOURCE_INTEGER, GM_FIELD_MATERIAL, VTU_INT32,
     1, NULL},
    {"velocity", SECTION_FIELDS, SOURCE_FIELD, GM_FIELD_VELOCITY, VTU_FLOAT64,
     3, NULL},
    {"external_force", SECTION_FIELDS, SOURCE_FIELD, GM_FIELD_EXTERNAL_FORCE,
     VTU_FLOAT64, 3, NULL},
    {"mass", SECTION_FIELDS, SOURCE_FIELD, GM_FIELD_MASS, VTU_FLOAT64, 1, NULL},
    {"volume", SECTION_FIELDS, SOURCE_FIELD, GM_FIELD_VOLUME, VTU_FLOAT64, 1,
     NULL},
    {"initial_volume", SECTION_FIELDS, SOURCE_FIELD, GM_FIELD_INITIAL_VOLUME,
     VTU_FLOAT64, 1, NULL},
    {"density", SECTION_FIELDS, SOURCE_FIELD, GM_FIELD_DENSITY, VTU_FLOAT64, 1,
     NULL},
    {"stress", SECTION_FIELDS, SOURCE_FIELD, GM_FIELD_STRESS, VTU_FLOAT64, 6,
     stress_names},
    {"deformation_gradient", SECTION_FIELDS, SOURCE_FIELD,
     GM_FIELD_DEFORMATION_GRADIENT, VTU_FLOAT64, 9, tensor_names},
    {"domain_size", SECTION_FIELDS, SOURCE_FIELD, GM_FIELD_DOMAIN_SIZE,
     VTU_FLOAT64, 3, NULL},
    /* granular method: gm_point_state and parallel grid of the last step */
    {"state", SECTION_FIELDS, SOURCE_INTEGER, GM_FIELD_STATE, VTU_INT32, 1,
     NULL},
    {"component", SECTION_FIELDS, SOURCE_INTEGER, GM_FIELD_COMPONENT, VTU_INT32,
     1, NULL},
};
enum { VTU_ARRAY_COUNT = sizeof vtu_arrays / sizeof vtu_arrays[0] };
/* Widest per-point array, in doubles per material point (the deformation
 * gradient; the VTK points take 3 per vertex on top of that). */
enum { VTU_MAX_COMPONENTS = 9 };

/* Everything one write needs, so helpers take a single argument. */
typedef struct vtu_writer {
  gm_domain *domain; /* for error messages only, see gm_vtu_write */
  const gm_vtu_layout *layout;
  const char *path;     /* final file name */
  char *temporary_path; /* path + ".tmp", written then renamed */
  FILE *file;
  size_t point_count; /* material points = cells */
  double time;        /* s */
  void *buffer;       /* point_count * buffer_width doubles of scratch */
} vtu_writer;

/* Doubles of scratch per material point: the widest array. */
static size_t buffer_width(const gm_vtu_layout *layout) {
  size_t vertices = 3 * layout->vertices; /* x, y, z per VTK point */
  return vertices > VTU_MAX_COMPONENTS ? vertices : VTU_MAX_COMPONENTS;
}

static size_t type_size(vtu_type type) {
  switch (type) {
  case VTU_FLOAT64:
  case VTU_INT64:
    return 8;
  case VTU_INT32:
    return 4;
  case VTU_UINT8:
    return 1;
  }
  return 0;
}

static const char *type_name(vtu_type type) {
  switch (type) {
  case VTU_FLOAT64:
    return "Float64";
  case VTU_INT64:
    return "Int64";
  case VTU_INT32:
    return "Int32";
  case VTU_UINT8:
    return "UInt8";
  }
  return "";
}

static const char *host_byte_order(void) {
  const uint16_t probe = 1;
  unsigned char first_byte;
  memcpy(&first_byte, &probe, 1);
  return first_byte == 1 ? "LittleEndian" : "BigEndian";
}

/* Bytes an array takes in the appended block, size prefix included. */
static uint64_t appended_bytes(uint64_t payload_bytes) {
  return sizeof(uint64_t) + payload_bytes;
}

/* Tuples of an array: one per VTK point for the coordinates and the
 * connectivity, one per material point (= cell) for everything else. */
static size_t array_tuples(const vtu_writer *writer, const vtu_array *array) {
  bool per_vertex =
      array->source == SOURCE_VERTICES || array->source == SOURCE_CONNECTIVITY;
  return writer->point_count * (per_vertex ? writer->layout->vertices : 1);
}

static uint64_t array_payload_bytes(const vtu_writer *writer,
                                    const vtu_array *array) {
  return (uint64_t)array_tuples(writer, array) * array->components *
         type_size(array->type);
}

/* The domain is const in the public signature, but its last_error buffer is
 * mutable diagnostic state by design (like errno): casting const away here,
 * for the message only, is intended. Nothing else of the domain is
 * modified. Captures errno text before anything can overwrite errno. */
static gm_status io_error(vtu_writer *writer, const char *what) {
  const char *reason = errno ? strerror(errno) : "unknown error";
  return gm_set_error(writer->domain, GM_ERR_IO,
                      "%s: cannot %s '%s' (temporary file for '%s'): %s",
                      writer->layout->caller, what, writer->temporary_path,
                      writer->path, reason);
}

/* ---------------------------------------------------------------- header */

static bool print_array_header(FILE *file, const vtu_array *array,
                               uint64_t offset) {
  bool ok = fprintf(file,
                    "        <DataArray type=\"%s\" Name=\"%s\" "
                    "NumberOfComponents=\"%zu\" format=\"appended\" "
                    "offset=\"%llu\"",
                    type_name(array->type), array->name, array->components,
                    (unsigned long long)offset) > 0;
  for (size_t k = 0; ok && array->component_names && k < array->components; k++)
    ok = fprintf(file, " ComponentName%zu=\"%s\"", k,
                 array->component_names[k]) > 0;
  return ok && fputs("/>\n", file) >= 0;
}

/* Prints the arrays of one section between its opening and closing tags
 * (already formatted); offsets[a] is where array a starts. */
static bool print_section(vtu_writer *writer, vtu_section section,
                          const char *open_tag, const char *close_tag,
                          const uint64_t *offsets) {
  if (fputs(open_tag, writer->file) < 0)
    return false;
  for (size_t a = 0; a < VTU_ARRAY_COUNT; a++)
    if (vtu_arrays[a].section == section &&
        !print_array_header(writer->file, &vtu_arrays[a], offsets[a]))
      return false;
  return fputs(close_tag, writer->file) >= 0;
}

static bool print_header(vtu_writer *writer) {
  /* Offsets: TimeValue first (one Float64), then the arrays in order. */
  uint64_t offsets[VTU_ARRAY_COUNT];
  uint64_t next = appended_bytes(sizeof(double));
  for (size_t a = 0; a < VTU_ARRAY_COUNT; a++) {
    offsets[a] = next;
    next += appended_bytes(array_payload_bytes(writer, &vtu_arrays[a]));
  }
  /* The field section: "<PointData ...>" or "<CellData ...>". */
  const char *tag = writer->layout->fields_tag;
  char open_fields[128], close_fields[32];
  snprintf(open_fields, sizeof open_fields,
           "      <%s Scalars=\"mass\" Vectors=\"velocity\" "
           "Tensors=\"stress\">\n",
           tag);
  snprintf(close_fields, sizeof close_fields, "      </%s>\n", tag);
  FILE *file = writer->file;
  return fprintf(file,
                 "<?xml version=\"1.0\"?>\n"
                 "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
                 "byte_order=\"%s\" header_type=\"UInt64\">\n"
                 "  <UnstructuredGrid>\n"
                 "    <FieldData>\n"
                 "      <DataArray type=\"Float64\" Name=\"TimeValue\" "
                 "NumberOfTuples=\"1\" format=\"appended\" offset=\"0\"/>\n"
                 "    </FieldData>\n"
                 "    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n",
                 host_byte_order(),
                 writer->point_count * writer->layout->vertices,
                 writer->point_count) > 0 &&
         print_section(writer, SECTION_FIELDS, open_fields, close_fields,
                       offsets) &&
         print_section(writer, SECTION_POINTS, "      <Points>\n",
                       "      </Points>\n", offsets) &&
         print_section(writer, SECTION_CELLS, "      <Cells>\n",
                       "      </Cells>\n", offsets) &&
         fputs("    </Piece>\n"
               "  </UnstructuredGrid>\n"
               "  <AppendedData encoding=\"raw\">\n"
               "   _",
               file) >= 0;
}

/* ------------------------------------------------------------- payloads */

/* Spreads n tuples of `from` components in place to `to` >= from
 * components, zero padded. Walks backwards so no value is overwritten
 * before it has been moved. */
static void pad_components(double *values, size_t n, size_t from, size_t to) {
  if (from == to)
    return;
  for (size_t i = n; i-- > 0;) {
    for (size_t k = to; k-- > from;)
      values[i * to + k] = 0.0;
    for (size_t k = from; k-- > 0;)
      values[i * to + k] = values[i * from + k];
  }
}

/* Material ids are small integers stored as doubles: exact. Converting in
 * place front to back is safe, each int32 lands at or before its double;
 * memcpy keeps the type punning well defined. */
static void convert_to_int32(void *buffer, size_t n) {
  unsigned char *bytes = buffer;
  for (size_t i = 0; i < n; i++) {
    double material;
    memcpy(&material, bytes + i * sizeof material, sizeof material);
    int32_t material_id = (int32_t)material;
    memcpy(bytes + i * sizeof material_id, &material_id, sizeof material_id);
  }
}

/* Fills the buffer with first, first + step, first + 2 step, ... (count
 * Int64 values). */
static void fill_sequence(vtu_writer *writer, int64_t first, int64_t step,
                          size_t count) {
  int64_t *values = writer->buffer;
  for (size_t i = 0; i < count; i++)
    values[i] = first + step * (int64_t)i;
}

/* Copies a field into the buffer as tuples_per_point tuples per material
 * point, each padded from components / tuples_per_point values to
 * array->components. */
static gm_status fill_field(vtu_writer *writer, const vtu_array *array,
                            gm_field field, size_t tuples_per_point) {
  const gm_domain *domain = writer->domain;
  size_t n = writer->point_count;
  size_t components = 0;
  gm_status status = gm_domain_field_components(domain, field, &components);
  if (status != GM_OK)
    return status;
  if (components % tuples_per_point != 0 ||
      components / tuples_per_point > array->components)
    return gm_set_error(writer->domain, GM_ERR_UNSUPPORTED,
                        "%s: field %d has %zu components, the VTU array '%s' "
                        "holds %zu x %zu",
                        writer->layout->caller, (int)field, components,
                        array->name, tuples_per_point, array->components);
  status = gm_domain_get_field(domain, field, writer->buffer, n * components);
  if (status != GM_OK)
    return status;
  pad_components(writer->buffer, n * tuples_per_point,
                 components / tuples_per_point, array->components);
  return GM_OK;
}

/* Fills writer->buffer with one array's values; returns a status. */
static gm_status fill_array(vtu_writer *writer, const vtu_array *array) {
  const gm_vtu_layout *layout = writer->layout;
  size_t n = writer->point_count;
  int64_t vertices = (int64_t)layout->vertices;
  switch (array->source) {
  case SOURCE_VERTICES:
    return fill_field(writer, array, layout->vertex_field, layout->vertices);
  case SOURCE_CONNECTIVITY: /* the VTK points in file order */
    fill_sequence(writer, 0, 1, n * layout->vertices);
    return GM_OK;
  case SOURCE_OFFSETS: /* each cell ends `vertices` after the previous one */
    fill_sequence(writer, vertices, vertices, n);
    return GM_OK;
  case SOURCE_CELL_TYPES:
    memset(writer->buffer, layout->cell_type, n);
    return GM_OK;
  case SOURCE_IDS:
    return gm_domain_get_ids(writer->domain, writer->buffer, n);
  case SOURCE_INTEGER: {
    gm_status status = fill_field(writer, array, array->field, 1);
    if (status == GM_OK)
      convert_to_int32(writer->buffer, n);
    return status;
  }
  case SOURCE_FIELD:
    return fill_field(writer, array, array->field, 1);
  }
  return GM_ERR_INVALID_ARGUMENT; /* not reached: every source is above */
}

static bool write_block(FILE *file, const void *data, uint64_t bytes) {
  return fwrite(&bytes, sizeof bytes, 1, file) == 1 &&
         (bytes == 0 || fwrite(data, (size_t)bytes, 1, file) == 1);
}

static gm_status write_payloads(vtu_writer *writer) {
  if (!write_block(writer->file, &writer->time, sizeof writer->time))
    return io_error(writer, "write");
  for (size_t a = 0; a < VTU_ARRAY_COUNT; a++) {
    gm_status status = fill_array(writer, &vtu_arrays[a]);
    if (status != GM_OK)
      return status;
    uint64_t bytes = array_payload_bytes(writer, &vtu_arrays[a]);
    if (!write_block(writer->file, writer->buffer, bytes))
      return io_error(writer, "write");
  }
  if (fputs("\n  </AppendedData>\n</VTKFile>\n", writer->file) < 0)
    return io_error(writer, "write");
  return GM_OK;
}

/* ----------------------------------------------------------------- write */

static gm_status write_temporary_file(vtu_writer *writer) {
  errno = 0;
  writer->file = fopen(writer->temporary_path, "wb");
  if (!writer->file)
    return io_error(writer, "open");
  gm_status status = GM_OK;
  errno = 0;
  if (!print_header(writer))
    status = io_error(writer, "write");
  if (status == GM_OK)
    status = write_payloads(writer);
  errno = 0;
  /* fclose flushes: its failure (e.g. disk full) means an incomplete file. */
  bool closed = fclose(writer->file) == 0;
  writer->file = NULL;
  if (!closed && status == GM_OK)
    status = io_error(writer, "close");
  return status;
}

static gm_status allocate_writer(vtu_writer *writer) {
  size_t path_length = strlen(writer->path);
  writer->temporary_path = gm_alloc(path_length + sizeof ".tmp");
  size_t n = writer->point_count;
  size_t width = buffer_width(writer->layout);
  /* Guard the size computation against overflow on absurd counts. */
  if (n > SIZE_MAX / (width * sizeof(double)))
    writer->buffer = NULL;
  else
    writer->buffer = gm_alloc(n * width * sizeof(double));
  if (!writer->temporary_path || !writer->buffer)
    return gm_set_error(writer->domain, GM_ERR_NO_MEMORY,
                        "%s: out of memory for %zu points writing '%s'",
                        writer->layout->caller, n, writer->path);
  memcpy(writer->temporary_path, writer->path, path_length);
  memcpy(writer->temporary_path + path_length, ".tmp", sizeof ".tmp");
  return GM_OK;
}

gm_status gm_vtu_write(const gm_domain *domain, const char *path,
                       const gm_vtu_layout *layout) {
  if (!domain)
    return GM_ERR_NULL;
  /* Cast away const for error messages only: see io_error(). */
  gm_domain *error_domain = (gm_domain *)domain;
  if (!path)
    return gm_set_error(error_domain, GM_ERR_NULL, "%s: path is NULL",
                        layout->caller);
  if (path[0] == '\0')
    return gm_set_error(error_domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: path is empty", layout->caller);
  vtu_writer writer = {0};
  writer.domain = error_domain;
  writer.layout = layout;
  writer.path = path;
  writer.point_count = gm_domain_point_count(domain);
  gm_status status = gm_domain_get_time(domain, &writer.time, NULL);
  if (status == GM_OK)
    status = allocate_writer(&writer);
  if (status == GM_OK)
    status = write_temporary_file(&writer);
  if (status == GM_OK) {
    errno = 0;
    if (rename(writer.temporary_path, path) != 0)
      status = gm_set_error(
          error_domain, GM_ERR_IO, "%s: cannot rename '%s' to '%s': %s",
          layout->caller, writer.temporary_path, path, strerror(errno));
  }
  if (status != GM_OK && writer.temporary_path)
    remove(writer.temporary_path); /* best effort: it may not exist */
  gm_free(writer.temporary_path);
  gm_free(writer.buffer);
  return status;
}

/* Points: one VTK point and one VTK_VERTEX cell per material point. */
static const gm_vtu_layout points_layout = {
    "gm_domain_write_vtu", GM_FIELD_POSITION, 1, GM_VTK_VERTEX, "PointData"};

gm_status gm_domain_write_vtu(const gm_domain *domain, const char *path) {
  return gm_vtu_write(domain, path, &points_layout);
}
