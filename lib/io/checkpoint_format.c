/*
 * checkpoint_format.c - byte encoding of checkpoint files: the output
 * buffer, the bounds-checked reader, the checksum, and the named setup
 * records with their comparison (layout in checkpoint_format.h; the file
 * itself is checkpoint_file.c).
 */
#include "io/io.h"

#include "io/checkpoint_format.h"

#include <stdio.h>
#include <string.h>

/* ------------------------------------------------------------- writing */

void gm_writer_bytes(gm_byte_writer *writer, const void *bytes, size_t size) {
  if (writer->failed || size == 0)
    return;
  if (size > SIZE_MAX / 2 - writer->size) {
    writer->failed = true;
    return;
  }
  if (writer->size + size > writer->capacity) {
    size_t capacity = 2 * (writer->size + size);
    void *grown = writer->data;
    if (!gm_grow(&grown, 1, writer->size, capacity)) {
      writer->failed = true;
      return;
    }
    writer->data = grown;
    writer->capacity = capacity;
  }
  memcpy(writer->data + writer->size, bytes, size);
  writer->size += size;
}

void gm_writer_u8(gm_byte_writer *writer, uint8_t value) {
  gm_writer_bytes(writer, &value, sizeof value);
}

void gm_writer_u32(gm_byte_writer *writer, uint32_t value) {
  gm_writer_bytes(writer, &value, sizeof value);
}

void gm_writer_u64(gm_byte_writer *writer, uint64_t value) {
  gm_writer_bytes(writer, &value, sizeof value);
}

void gm_writer_i64(gm_byte_writer *writer, int64_t value) {
  gm_writer_bytes(writer, &value, sizeof value);
}

void gm_writer_f64(gm_byte_writer *writer, double value) {
  gm_writer_bytes(writer, &value, sizeof value);
}

void gm_writer_array(gm_byte_writer *writer, const void *data, size_t size) {
  gm_writer_u64(writer, (uint64_t)size);
  gm_writer_bytes(writer, data, size);
}

void gm_writer_free(gm_byte_writer *writer) {
  gm_free(writer->data);
  memset(writer, 0, sizeof *writer);
}

/* ------------------------------------------------------------- reading */

/* Where the next size bytes start, or NULL (reader failed) past the end. */
static const unsigned char *take(gm_byte_reader *reader, size_t size) {
  if (reader->failed || size > reader->size - reader->offset) {
    reader->failed = true;
    return NULL;
  }
  const unsigned char *start = reader->data + reader->offset;
  reader->offset += size;
  return start;
}

/* Copies size bytes into out, or zeros on failure. */
static void read_into(gm_byte_reader *reader, void *out, size_t size) {
  const unsigned char *start = take(reader, size);
  if (start)
    memcpy(out, start, size);
  else
    memset(out, 0, size);
}

uint8_t gm_reader_u8(gm_byte_reader *reader) {
  uint8_t value;
  read_into(reader, &value, sizeof value);
  return value;
}

uint32_t gm_reader_u32(gm_byte_reader *reader) {
  uint32_t value;
  read_into(reader, &value, sizeof value);
  return value;
}

uint64_t gm_reader_u64(gm_byte_reader *reader) {
  uint64_t value;
  read_into(reader, &value, sizeof value);
  return value;
}

int64_t gm_reader_i64(gm_byte_reader *reader) {
  int64_t value;
  read_into(reader, &value, sizeof value);
  return value;
}

double gm_reader_f64(gm_byte_reader *reader) {
  double value;
  read_into(reader, &value, sizeof value);
  return value;
}

const unsigned char *gm_reader_array(gm_byte_reader *reader, size_t size) {
  if (gm_reader_u64(reader) != (uint64_t)size)
    reader->failed = true;
  return take(reader, size);
}

const unsigned char *gm_reader_any_array(gm_byte_reader *reader, size_t *size) {
  uint64_t stored = gm_reader_u64(reader);
  if (stored > reader->size - reader->offset) {
    reader->failed = true;
    return NULL;
  }
  *size = (size_t)stored;
  return take(reader, *size);
}

uint64_t gm_fnv1a64(const void *bytes, size_t size, uint64_t hash) {
  const unsigned char *byte = bytes;
  for (size_t k = 0; k < size; k++) {
    hash ^= byte[k];
    hash *= 0x100000001b3ull; /* the 64-bit FNV prime */
  }
  return hash;
}

/* -------------------------------------------------------- setup records */

static void record_header(gm_byte_writer *writer, const char *name,
                          gm_record_kind kind, size_t count) {
  size_t length = strlen(name);
  uint16_t stored = (uint16_t)(length < UINT16_MAX ? length : UINT16_MAX);
  gm_writer_bytes(writer, &stored, sizeof stored);
  gm_writer_bytes(writer, name, stored);
  gm_writer_u8(writer, (uint8_t)kind);
  gm_writer_u64(writer, (uint64_t)count);
}

void gm_record_reals(gm_byte_writer *writer, const char *name,
                     const double *values, size_t count) {
  record_header(writer, name, GM_RECORD_REALS, count);
  gm_writer_bytes(writer, values, count * sizeof(double));
}

void gm_record_integer(gm_byte_writer *writer, const char *name,
                       int64_t value) {
  record_header(writer, name, GM_RECORD_INTEGERS, 1);
  gm_writer_i64(writer, value);
}

void gm_record_text(gm_byte_writer *writer, const char *name,
                    const char *text) {
  record_header(writer, name, GM_RECORD_TEXT, strlen(text));
  gm_writer_bytes(writer, text, strlen(text));
}

void gm_record_bytes(gm_byte_writer *writer, const char *name,
                     const void *bytes, size_t size) {
  record_header(writer, name, GM_RECORD_BYTES, size);
  gm_writer_bytes(writer, bytes, size);
}

/* One record, parsed in place. */
typedef struct record_view {
  const char *name;
  size_t name_length;
  gm_record_kind kind;
  size_t count;               /* elements */
  const unsigned char *bytes; /* count elements */
} record_view;

static bool next_record(gm_byte_reader *reader, record_view *record) {
  uint16_t name_length;
  read_into(reader, &name_length, sizeof name_length);
  record->name_length = name_length;
  record->name = (const char *)take(reader, name_length);
  record->kind = (gm_record_kind)gm_reader_u8(reader);
  uint64_t count = gm_reader_u64(reader);
  size_t element = record->kind <= GM_RECORD_INTEGERS ? 8 : 1;
  if (reader->failed || record->kind > GM_RECORD_BYTES ||
      count > (reader->size - reader->offset) / element) {
    reader->failed = true;
    return false;
  }
  record->count = (size_t)count;
  record->bytes = take(reader, record->count * element);
  return !reader->failed;
}

/* Characters of a name or text shown in messages: at most 100. */
static int shown(size_t length) {
  return (int)(length < 100 ? length : 100);
}

/* Describes how two records with the same name differ. */
static void describe_difference(const record_view *file, const record_view *own,
                                char *message, size_t message_size) {
  int name_length = shown(own->name_length);
  if (file->kind == GM_RECORD_TEXT && own->kind == GM_RECORD_TEXT) {
    snprintf(message, message_size,
             "%.*s differs (file \"%.*s\", domain "
             "\"%.*s\")",
             name_length, own->name, shown(file->count),
             (const char *)file->bytes, shown(own->count),
             (const char *)own->bytes);
    return;
  }
  if (file->kind != own->kind || file->count != own->count) {
    snprintf(message, message_size,
             "%.*s differs (%zu values in the file, %zu "
             "in the domain)",
             name_length, own->name, file->count, own->count);
    return;
  }
  size_t element = own->kind == GM_RECORD_BYTES ? 1 : 8, k = 0;
  while (memcmp(file->bytes + k * element, own->bytes + k * element, element) ==
         0)
    k++; /* stops: the records differ somewhere */
  if (own->kind == GM_RECORD_REALS) {
    double in_file, in_domain;
    memcpy(&in_file, file->bytes + 8 * k, 8);
    memcpy(&in_domain, own->bytes + 8 * k, 8);
    char index[32] = ""; /* for records of more than one value */
    if (own->count > 1)
      snprintf(index, sizeof index, "[%zu]", k);
    snprintf(message, message_size,
             "%.*s%s differs (file %.17g, domain "
             "%.17g)",
             name_length, own->name, index, in_file, in_domain);
  } else if (own->kind == GM_RECORD_INTEGERS) {
    int64_t in_file, in_domain;
    memcpy(&in_file, file->bytes + 8 * k, 8);
    memcpy(&in_domain, own->bytes + 8 * k, 8);
    snprintf(message, message_size, "%.*s differs (file %lld, domain %lld)",
             name_length, own->name, (long long)in_file, (long long)in_domain);
  } else {
    snprintf(message, message_size, "%.*s differs at byte %zu", name_length,
             own->name, k);
  }
}

bool gm_records_equal(const unsigned char *file, size_t file_size,
                      const unsigned char *domain, size_t domain_size,
                      char *message, size_t message_size) {
  gm_byte_reader in_file = {file, file_size, 0, false};
  gm_byte_reader in_domain = {domain, domain_size, 0, false};
  while (in_domain.offset < domain_size) {
    record_view own = {0}, stored = {0};
    next_record(&in_domain, &own); /* written by this library: well formed */
    if (in_file.offset >= file_size || !next_record(&in_file, &stored)) {
      snprintf(message, message_size, "the file's setup ends before %.*s",
               shown(own.name_length), own.name);
      return false;
    }
    if (stored.name_length != own.name_length ||
        memcmp(stored.name, own.name, own.name_length) != 0) {
      snprintf(message, message_size,
               "the file has %.*s where the domain has "
               "%.*s",
               shown(stored.name_length), stored.name, shown(own.name_length),
               own.name);
      return false;
    }
    size_t element = own.kind <= GM_RECORD_INTEGERS ? 8 : 1;
    if (stored.kind != own.kind || stored.count != own.count ||
        memcmp(stored.bytes, own.bytes, own.count * element) != 0) {
      describe_difference(&stored, &own, message, message_size);
      return false;
    }
  }
  if (in_file.offset != file_size) {
    snprintf(message, message_size,
             "the file's setup has more entries than "
             "the domain's");
    return false;
  }
  return true;
}
