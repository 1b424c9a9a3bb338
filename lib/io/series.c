/*
 * series.c - ParaView time series: one .vtu per frame plus a .pvd
 * collection listing them with their simulated times.
 *
 * For pvd_path "out/bar.pvd" the frames are "out/bar_000000.vtu",
 * "out/bar_000001.vtu", ... (6 digits, more past 999999). With domains
 * enabled, a frame also has "out/bar_domains_000000.vtu", listed as part 1
 * of the same timestep (ParaView shows the parts of a timestep together, as
 * blocks of one dataset). The .pvd refers to the files by name only
 * (relative to the .pvd), so the directory can be moved as a whole. It is
 * rewritten after every frame, through a temporary file and a rename, so the
 * .pvd on disk is always a complete collection even if the simulation is killed
 * between two frames.
 */
#include "io/io.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

/* What the .pvd lists for one frame. */
typedef struct series_frame {
  double time;  /* s, simulated time */
  bool domains; /* the frame has a domains file (part 1) */
} series_frame;

struct gm_series {
  char *pvd_path;          /* as given */
  char *temporary_path;    /* pvd_path + ".tmp" */
  char *stem;              /* file name without directory and extension */
  char *frame_path;        /* scratch: directory + stem + part + number */
  size_t directory_length; /* bytes of pvd_path before the stem */
  size_t frame_count;      /* frames written and listed in the .pvd */
  size_t frame_capacity;
  series_frame *frames;
  bool write_domains; /* gm_series_set_domains */
};

/* What goes between the stem and "_NNNNNN.vtu" for each part. */
static const char *const part_infix[2] = {"", "_domains"};

/* Room for the longest part infix + "_" + the digits of any size_t +
 * ".vtu" + NUL. */
enum { FRAME_SUFFIX_CAPACITY = sizeof "_domains" + 32 };

static char *copy_bytes(const char *text, size_t length) {
  char *copy = gm_alloc(length + 1);
  if (copy) {
    memcpy(copy, text, length);
    copy[length] = '\0';
  }
  return copy;
}

/* Writes text into an XML attribute value, escaping the five special
 * characters so any file name gives well-formed XML. */
static bool print_xml_escaped(FILE *file, const char *text) {
  for (const char *c = text; *c; c++) {
    int written;
    switch (*c) {
    case '&':
      written = fputs("&amp;", file);
      break;
    case '<':
      written = fputs("&lt;", file);
      break;
    case '>':
      written = fputs("&gt;", file);
      break;
    case '"':
      written = fputs("&quot;", file);
      break;
    case '\'':
      written = fputs("&apos;", file);
      break;
    default:
      written = fputc(*c, file);
    }
    if (written == EOF)
      return false;
  }
  return true;
}

/* One <DataSet>: part 0 is the points file, part 1 the domains file. */
static bool print_dataset(const gm_series *series, FILE *file, size_t frame,
                          int part) {
  /* %.17g: the time round-trips exactly. */
  return fprintf(file, "    <DataSet timestep=\"%.17g\" part=\"%d\" file=\"",
                 series->frames[frame].time, part) >= 0 &&
         print_xml_escaped(file, series->stem) &&
         fprintf(file, "%s_%06zu.vtu\"/>\n", part_infix[part], frame) >= 0;
}

static bool print_collection(const gm_series *series, FILE *file) {
  if (fputs("<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"Collection\" version=\"1.0\">\n"
            "  <Collection>\n",
            file) == EOF)
    return false;
  for (size_t frame = 0; frame < series->frame_count; frame++) {
    int parts = series->frames[frame].domains ? 2 : 1;
    for (int part = 0; part < parts; part++)
      if (!print_dataset(series, file, frame, part))
        return false;
  }
  return fputs("  </Collection>\n</VTKFile>\n", file) != EOF;
}

/* Rewrites the .pvd for the first series->frame_count frames. On failure
 * returns false with errno describing it and leaves the old .pvd alone. */
static bool rewrite_collection(const gm_series *series) {
  errno = 0;
  FILE *file = fopen(series->temporary_path, "wb");
  if (!file)
    return false;
  bool ok = print_collection(series, file);
  int error = ok ? 0 : errno;
  /* fclose flushes: its failure (e.g. disk full) means a truncated file. */
  if (fclose(file) != 0 && ok) {
    ok = false;
    error = errno;
  }
  if (ok && rename(series->temporary_path, series->pvd_path) != 0) {
    ok = false;
    error = errno;
  }
  if (!ok) {
    remove(series->temporary_path); /* best effort */
    errno = error;
  }
  return ok;
}

static const char *errno_text(void) {
  return errno ? strerror(errno) : "unknown error";
}

static void series_free(gm_series *series) {
  gm_free(series->pvd_path);
  gm_free(series->temporary_path);
  gm_free(series->stem);
  gm_free(series->frame_path);
  gm_free(series->frames);
  gm_free(series);
}

/* Splits pvd_path into directory (kept as a length) and stem: the file name
 * up to its last '.', or all of it when it has no extension. */
static bool parse_path(gm_series *series, const char *pvd_path) {
  const char *slash = strrchr(pvd_path, '/');
  const char *name = slash ? slash + 1 : pvd_path;
  const char *dot = strrchr(name, '.');
  size_t stem_length = dot ? (size_t)(dot - name) : strlen(name);
  series->directory_length = (size_t)(name - pvd_path);
  series->stem = stem_length ? copy_bytes(name, stem_length) : NULL;
  return stem_length > 0;
}

gm_status gm_series_create(const char *pvd_path, gm_series **out) {
  if (!out)
    return gm_set_create_error(GM_ERR_NULL, "gm_series_create: out is NULL");
  *out = NULL;
  if (!pvd_path)
    return gm_set_create_error(GM_ERR_NULL,
                               "gm_series_create: pvd_path is NULL");
  gm_series *series = gm_calloc(1, sizeof *series);
  if (!series)
    return gm_set_create_error(GM_ERR_NO_MEMORY,
                               "gm_series_create: out of memory");
  if (!parse_path(series, pvd_path)) {
    series_free(series);
    /* "dir/" or "dir/.pvd": no name to derive the frame files from. */
    return gm_set_create_error(GM_ERR_INVALID_ARGUMENT,
                               "gm_series_create: pvd_path '%s' has no file "
                               "name to derive frame names from",
                               pvd_path);
  }
  size_t path_length = strlen(pvd_path);
  series->pvd_path = copy_bytes(pvd_path, path_length);
  series->temporary_path = gm_alloc(path_length + sizeof ".tmp");
  series->frame_path = gm_alloc(series->directory_length +
                                strlen(series->stem) + FRAME_SUFFIX_CAPACITY);
  if (!series->stem || !series->pvd_path || !series->temporary_path ||
      !series->frame_path) {
    series_free(series);
    return gm_set_create_error(GM_ERR_NO_MEMORY,
                               "gm_series_create: out of memory");
  }
  memcpy(series->temporary_path, pvd_path, path_length);
  memcpy(series->temporary_path + path_length, ".tmp", sizeof ".tmp");
  /* An empty but valid collection now: proves the directory exists and is
   * writable before any simulation time is spent. */
  if (!rewrite_collection(series)) {
    int error = errno;
    series_free(series);
    return gm_set_create_error(GM_ERR_IO,
                               "gm_series_create: cannot write '%s': %s",
                               pvd_path, strerror(error));
  }
  *out = series;
  return GM_OK;
}

/* Sets series->frame_path to the file of part `part` (0 points, 1
 * domains) of frame number `frame`. */
static void format_frame_path(gm_series *series, size_t frame, int part) {
  size_t stem_length = strlen(series->stem);
  memcpy(series->frame_path, series->pvd_path, series->directory_length);
  memcpy(series->frame_path + series->directory_length, series->stem,
         stem_length);
  snprintf(series->frame_path + series->directory_length + stem_length,
           FRAME_SUFFIX_CAPACITY, "%s_%06zu.vtu", part_infix[part], frame);
}

/* Writes the files of frame number `frame`: the points, and the domains
 * when enabled. Error messages name the file (gm_vtu_write). */
static gm_status write_frame_files(gm_series *series, const gm_domain *domain,
                                   size_t frame) {
  format_frame_path(series, frame, 0);
  gm_status status = gm_domain_write_vtu(domain, series->frame_path);
  if (status == GM_OK && series->frames[frame].domains) {
    format_frame_path(series, frame, 1);
    status = gm_domain_write_domains_vtu(domain, series->frame_path);
  }
  return status;
}

gm_status gm_series_write(gm_series *series, const gm_domain *domain) {
  if (!domain)
    return GM_ERR_NULL;
  /* The domain is const, but its last_error buffer is mutable diagnostic
   * state by design: const is cast away for error messages only. */
  gm_domain *error_domain = (gm_domain *)domain;
  if (!series)
    return gm_set_error(error_domain, GM_ERR_NULL,
                        "gm_series_write: series is NULL");
  size_t frame = series->frame_count;
  if (frame == series->frame_capacity) {
    size_t capacity = frame ? 2 * frame : 64;
    if (!gm_grow((void **)&series->frames, sizeof(series_frame), frame,
                 capacity))
      return gm_set_error(error_domain, GM_ERR_NO_MEMORY,
                          "gm_series_write: out of memory for frame %zu of "
                          "'%s'",
                          frame, series->pvd_path);
    series->frame_capacity = capacity;
  }
  series->frames[frame].domains = series->write_domains;
  gm_status status =
      gm_domain_get_time(domain, &series->frames[frame].time, NULL);
  if (status == GM_OK)
    status = write_frame_files(series, domain, frame);
  if (status != GM_OK)
    return status; /* not listed; the next call rewrites this number */
  series->frame_count = frame + 1;
  if (!rewrite_collection(series)) {
    /* Not listed: the .pvd stays the previous complete collection and the
     * next call rewrites this frame number. */
    series->frame_count = frame;
    return gm_set_error(error_domain, GM_ERR_IO,
                        "gm_series_write: cannot write '%s' (via '%s'): %s",
                        series->pvd_path, series->temporary_path, errno_text());
  }
  return GM_OK;
}

gm_status gm_series_set_domains(gm_series *series, int enabled) {
  if (!series)
    return GM_ERR_NULL; /* no domain to hold a message */
  series->write_domains = enabled != 0;
  return GM_OK;
}

void gm_series_destroy(gm_series *series) {
  if (series)
    series_free(series);
}
