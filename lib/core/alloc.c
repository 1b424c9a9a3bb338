/*
 * alloc.c - the library's allocator hook (gm_set_allocator). Every
 * allocation goes through here so an embedding code can route memory to
 * its own arena or tracker.
 */
#include "core/core.h"

#include "core/api_check.h"

#include <stdlib.h>
#include <string.h>

static void *default_malloc(size_t size, void *user) {
  (void)user;
  return malloc(size);
}

static void default_free(void *pointer, void *user) {
  (void)user;
  free(pointer);
}

static gm_allocator current_allocator = {sizeof(gm_allocator), default_malloc,
                                         default_free, NULL};

gm_status gm_set_allocator(const gm_allocator *allocator) {
  if (!allocator) {
    current_allocator.malloc_fn = default_malloc;
    current_allocator.free_fn = default_free;
    current_allocator.user = NULL;
    return GM_OK;
  }
  /* The preamble of every call that takes a structure (api_check.h); the
   * message goes where a failed create's does: there is no domain. */
  if (!gm_layout_known(GM_LAYOUT_ALLOCATOR, allocator->struct_size))
    return gm_layout_refuse(NULL, GM_LAYOUT_ALLOCATOR, allocator->struct_size);
  if (!allocator->malloc_fn || !allocator->free_fn)
    return GM_ERR_NULL;
  current_allocator = *allocator;
  return GM_OK;
}

void *gm_alloc(size_t size) {
  return current_allocator.malloc_fn(size ? size : 1, current_allocator.user);
}

void *gm_calloc(size_t count, size_t size) {
  if (size && count > SIZE_MAX / size)
    return NULL;
  void *pointer = gm_alloc(count * size);
  if (pointer)
    memset(pointer, 0, count * size);
  return pointer;
}

void gm_free(void *pointer) {
  if (pointer)
    current_allocator.free_fn(pointer, current_allocator.user);
}

bool gm_grow(void **array, size_t elem, size_t old_count, size_t new_count) {
  if (new_count <= old_count && *array)
    return true;
  void *grown = gm_calloc(new_count, elem);
  if (!grown)
    return false;
  if (*array && old_count)
    memcpy(grown, *array, old_count * elem);
  gm_free(*array);
  *array = grown;
  return true;
}
