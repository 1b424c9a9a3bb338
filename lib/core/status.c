/*
 * status.c - status codes, version, error messages.
 */
#include "core/core.h"

#include "core/domain.h"

#include <stdio.h>
#include <string.h>

const char *gm_strerror(gm_status status) {
  switch (status) {
#define GM_STATUS_CASE_(name, value, text)                                     \
  case name:                                                                   \
    return text;
    GM_STATUS_LIST(GM_STATUS_CASE_)
#undef GM_STATUS_CASE_
  }
  return "unknown status code";
}

const char *gm_version(void) {
  return GM_VERSION_STRING;
}

int gm_version_number(void) {
  return GM_VERSION_NUMBER;
}

int gm_geometry_dimension(gm_geometry geometry) {
  switch (geometry) {
  case GM_GEOMETRY_1D:
    return 1;
  case GM_GEOMETRY_PLANE_STRAIN:
  case GM_GEOMETRY_AXISYMMETRIC:
    return 2;
  case GM_GEOMETRY_3D:
    return 3;
  }
  return 0;
}

/* The message of a failed gm_domain_create or gm_series_create, where no
 * domain holds it (per thread). */
static _Thread_local char create_error[GM_ERROR_MESSAGE_SIZE];

const char *gm_last_create_error(void) {
  return create_error;
}

gm_status gm_set_create_error(gm_status status, const char *format, ...) {
  va_list args;
  va_start(args, format);
  vsnprintf(create_error, sizeof create_error, format, args);
  va_end(args);
  return status;
}

gm_status gm_set_error(gm_domain *domain, gm_status status, const char *format,
                       ...) {
  if (!domain)
    return status;
  va_list args;
  va_start(args, format);
  vsnprintf(domain->last_error, sizeof domain->last_error, format, args);
  va_end(args);
  return status;
}

void gm_worker_error(gm_worker_scratch *scratch, gm_status status, size_t index,
                     const char *format, ...) {
  if (scratch->error_status != GM_OK && scratch->error_index <= index)
    return;
  scratch->error_status = status;
  scratch->error_index = index;
  scratch->error_inverted = false; /* the caller marks inversions */
  va_list args;
  va_start(args, format);
  vsnprintf(scratch->error_message, sizeof scratch->error_message, format,
            args);
  va_end(args);
}

void gm_clear_worker_errors(gm_domain *domain) {
  for (int w = 0; w < domain->worker_count; w++) {
    domain->scratch[w].error_status = GM_OK;
    domain->scratch[w].callback_result = 0;
    domain->scratch[w].error_inverted = false;
  }
}

gm_status gm_collect_worker_errors(gm_domain *domain) {
  gm_worker_scratch *first = NULL;
  for (int w = 0; w < domain->worker_count; w++) {
    gm_worker_scratch *scratch = &domain->scratch[w];
    if (scratch->error_status == GM_OK)
      continue;
    if (!first || scratch->error_index < first->error_index)
      first = scratch;
  }
  if (!first)
    return GM_OK;
  memcpy(domain->last_error, first->error_message, sizeof domain->last_error);
  return first->error_status;
}
