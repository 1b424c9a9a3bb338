/*
 * checkpoint_file.c - checkpoint files on disk: the header (magic,
 * version, byte order, size, checksum), the write through a synced
 * temporary file and a rename, and the checked whole-file read (layout in
 * checkpoint_format.h).
 */
/* fsync(), fileno() and open() are POSIX, not C11. */
#define _POSIX_C_SOURCE 200809L

#include "io/io.h"

#include "io/checkpoint_format.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

static const unsigned char checkpoint_magic[8] = {0x89, 'G', 'M', 'C',
                                                  'K',  'P', 'T', '\n'};
#define BYTE_ORDER_MARKER 0x0A0B0C0Du
#define CHECKSUM_OFFSET   24u /* the header bytes before it are checksummed */

/* ----------------------------------------------------------- the file */

void gm_checkpoint_begin(gm_byte_writer *writer) {
  memset(writer, 0, sizeof *writer);
  unsigned char header[GM_CHECKPOINT_HEADER_SIZE] = {0};
  gm_writer_bytes(writer, header, sizeof header);
}

void gm_checkpoint_seal(gm_byte_writer *writer) {
  if (writer->failed)
    return;
  unsigned char *header = writer->data;
  uint32_t version = GM_CHECKPOINT_VERSION, marker = BYTE_ORDER_MARKER;
  uint64_t payload_size = writer->size - GM_CHECKPOINT_HEADER_SIZE;
  memcpy(header, checkpoint_magic, sizeof checkpoint_magic);
  memcpy(header + 8, &version, 4);
  memcpy(header + 12, &marker, 4);
  memcpy(header + 16, &payload_size, 8);
  uint64_t checksum = gm_fnv1a64(header, CHECKSUM_OFFSET, GM_FNV_OFFSET);
  checksum =
      gm_fnv1a64(header + GM_CHECKPOINT_HEADER_SIZE, payload_size, checksum);
  memcpy(header + CHECKSUM_OFFSET, &checksum, 8);
}

/* Makes the rename itself durable (best effort: not every file system
 * lets a directory be opened or synced). */
static void sync_directory_of(const char *path) {
  const char *slash = strrchr(path, '/');
  char directory[4096] = ".";
  if (slash) {
    size_t length = (size_t)(slash - path);
    if (length >= sizeof directory)
      return;
    if (length == 0) /* "/name" lives in "/" */
      length = 1;
    memcpy(directory, path, length);
    directory[length] = '\0';
  }
  int descriptor = open(directory, O_RDONLY);
  if (descriptor >= 0) {
    fsync(descriptor);
    close(descriptor);
  }
}

/* Writes, flushes and syncs bytes into a new file; false with errno set.
 * *created tells whether the file was made (and so is ours to remove). */
static bool write_synced(const char *path, const gm_byte_writer *writer,
                         bool *created) {
  FILE *file = fopen(path, "wb");
  *created = file != NULL;
  if (!file)
    return false;
  bool ok = fwrite(writer->data, 1, writer->size, file) == writer->size &&
            fflush(file) == 0 && fsync(fileno(file)) == 0;
  int saved = errno;
  if (fclose(file) != 0 && ok) {
    saved = errno;
    ok = false;
  }
  errno = saved;
  return ok;
}

gm_status gm_checkpoint_write_file(gm_domain *domain, const char *path,
                                   const gm_byte_writer *writer) {
  size_t length = strlen(path);
  char *temporary = gm_alloc(length + sizeof ".tmp");
  if (!temporary)
    return gm_set_error(domain, GM_ERR_NO_MEMORY,
                        "gm_domain_save: out of memory for '%s'", path);
  memcpy(temporary, path, length);
  memcpy(temporary + length, ".tmp", sizeof ".tmp");
  gm_status status = GM_OK;
  bool created = false;
  if (!write_synced(temporary, writer, &created))
    status = gm_set_error(domain, GM_ERR_IO,
                          "gm_domain_save: cannot write "
                          "'%s': %s",
                          temporary, strerror(errno));
  else if (rename(temporary, path) != 0)
    status = gm_set_error(domain, GM_ERR_IO,
                          "gm_domain_save: cannot rename "
                          "'%s' to '%s': %s",
                          temporary, path, strerror(errno));
  if (status != GM_OK && created)
    remove(temporary); /* never a file we did not create */
  else if (status == GM_OK)
    sync_directory_of(path);
  gm_free(temporary);
  return status;
}

/* Reads a whole file into a new buffer; false with errno set. */
static bool read_whole(const char *path, unsigned char **data, size_t *size) {
  FILE *file = fopen(path, "rb");
  if (!file)
    return false;
  size_t capacity = 1 << 16, used = 0;
  unsigned char *buffer = gm_alloc(capacity);
  bool ok = buffer != NULL;
  while (ok) {
    if (used == capacity) {
      void *grown = buffer;
      ok = capacity < SIZE_MAX / 2 && gm_grow(&grown, 1, used, 2 * capacity);
      buffer = grown;
      capacity *= 2;
      if (!ok) {
        errno = ENOMEM;
        break;
      }
    }
    used += fread(buffer + used, 1, capacity - used, file);
    if (used < capacity) { /* end of file or an error */
      ok = !ferror(file);
      break;
    }
  }
  int saved = errno;
  fclose(file);
  errno = saved;
  if (!ok) {
    gm_free(buffer);
    return false;
  }
  *data = buffer;
  *size = used;
  return true;
}

/* Checks the header against the file size and the payload's checksum. */
static gm_status check_header(gm_domain *domain, const char *path,
                              const unsigned char *data, size_t size,
                              uint32_t *file_version) {
  const char *what = "gm_domain_load";
  if (size < GM_CHECKPOINT_HEADER_SIZE ||
      memcmp(data, checkpoint_magic, sizeof checkpoint_magic) != 0)
    return gm_set_error(domain, GM_ERR_IO,
                        "%s: '%s' is not a libgranmpm "
                        "checkpoint (%zu bytes, no magic number)",
                        what, path, size);
  uint32_t version, marker;
  uint64_t payload_size, checksum;
  memcpy(&version, data + 8, 4);
  memcpy(&marker, data + 12, 4);
  memcpy(&payload_size, data + 16, 8);
  memcpy(&checksum, data + CHECKSUM_OFFSET, 8);
  if (marker != BYTE_ORDER_MARKER)
    return gm_set_error(domain, GM_ERR_IO,
                        "%s: '%s' was written on a machine "
                        "of another byte order (or is corrupted)",
                        what, path);
  if (version < GM_CHECKPOINT_OLDEST || version > GM_CHECKPOINT_VERSION)
    return gm_set_error(domain, GM_ERR_IO,
                        "%s: '%s' has checkpoint format "
                        "version %u; this library reads versions %u to %u%s",
                        what, path, (unsigned)version, GM_CHECKPOINT_OLDEST,
                        GM_CHECKPOINT_VERSION,
                        version == 1u
                            ? " (version 1 predates the force reports "
                              "and the stored CPDI "
                              "domains: restart that run from its "
                              "setup with this library)"
                            : "");
  if (payload_size != size - GM_CHECKPOINT_HEADER_SIZE)
    return gm_set_error(
        domain, GM_ERR_IO,
        "%s: '%s' is truncated or "
        "corrupted: %zu bytes, the header announces %llu",
        what, path, size,
        (unsigned long long)(payload_size + GM_CHECKPOINT_HEADER_SIZE));
  uint64_t computed = gm_fnv1a64(data, CHECKSUM_OFFSET, GM_FNV_OFFSET);
  computed = gm_fnv1a64(data + GM_CHECKPOINT_HEADER_SIZE,
                        size - GM_CHECKPOINT_HEADER_SIZE, computed);
  if (computed != checksum)
    return gm_set_error(domain, GM_ERR_IO,
                        "%s: '%s' is corrupted (checksum "
                        "mismatch)",
                        what, path);
  *file_version = version;
  return GM_OK;
}

gm_status gm_checkpoint_read_file(gm_domain *domain, const char *path,
                                  unsigned char **file, gm_byte_reader *payload,
                                  uint32_t *version) {
  unsigned char *data = NULL;
  size_t size = 0;
  if (!read_whole(path, &data, &size))
    return gm_set_error(domain, errno == ENOMEM ? GM_ERR_NO_MEMORY : GM_ERR_IO,
                        "gm_domain_load: cannot read '%s': %s", path,
                        strerror(errno));
  gm_status status = check_header(domain, path, data, size, version);
  if (status != GM_OK) {
    gm_free(data);
    return status;
  }
  *file = data;
  payload->data = data + GM_CHECKPOINT_HEADER_SIZE;
  payload->size = size - GM_CHECKPOINT_HEADER_SIZE;
  payload->offset = 0;
  payload->failed = false;
  return GM_OK;
}
