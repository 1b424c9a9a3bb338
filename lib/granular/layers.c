/*
 * layers.c - node layers for the parallel grids (000 sec 3.3): components
 * that share a grid node must not meet on one grid, so each gets a layer
 * of block keys (core/block_grid.h) different from those of the components it
 * shares nodes with. A greedy colouring in label order keeps this deterministic
 * and uses few layers: components that share no node share a layer.
 */
#include "granular/granular.h"

#include <string.h>

/* Greedy colouring of the components that share nodes, in label order;
 * returns the number of layers. The conflicts (low << 32 | high) may
 * repeat: a repeated neighbour only marks its layer twice. */
gm_status gm_assign_layers(gm_domain *domain, size_t components,
                           size_t *layer_count) {
  gm_granular_work *work = &domain->granular;
  size_t count = work->conflict_count;
  if (count > work->adjacency_capacity) {
    if (!gm_grow((void **)&work->adjacency, sizeof(int32_t),
                 work->adjacency_capacity, count))
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "granular: out of memory for grid conflicts");
    work->adjacency_capacity = count;
  }
  /* CSR of the lower neighbours of each component (the ones coloured
   * before it), by a counting sort on the higher label: O(conflicts). */
  uint32_t *start = work->adjacency_start;
  memset(start, 0, (components + 1) * sizeof(uint32_t));
  for (size_t i = 0; i < count; i++)
    start[(work->conflict[i] & 0xffffffffu) + 1]++;
  for (size_t c = 0; c < components; c++)
    start[c + 1] += start[c];
  for (size_t i = 0; i < count; i++) {
    uint32_t high = (uint32_t)(work->conflict[i] & 0xffffffffu);
    work->adjacency[start[high]++] = (int32_t)(work->conflict[i] >> 32);
  }
  for (size_t c = components; c > 0; c--) /* undo the fill shift */
    start[c] = start[c - 1];
  start[0] = 0;
  size_t layers = 1;
  for (size_t c = 0; c < components; c++)
    work->layer_stamp[c] = -1;
  for (size_t c = 0; c < components; c++) {
    for (uint32_t k = start[c]; k < start[c + 1]; k++)
      work->layer_stamp[work->component_layer[work->adjacency[k]]] = (int32_t)c;
    int32_t layer = 0;
    while (work->layer_stamp[layer] == (int32_t)c)
      layer++;
    work->component_layer[c] = layer;
    if ((size_t)layer + 1 > layers)
      layers = (size_t)layer + 1;
  }
  *layer_count = layers;
  return GM_OK;
}
