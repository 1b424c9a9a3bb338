/*
 * block_grid.c - the sparse block grid: which blocks exist this step (those
 * holding points, plus the upper neighbours their cells' nodes reach), a
 * hash from block key to block index, neighbour links and colours.
 * Everything here is proportional to the occupied blocks, never to the box
 * (with periodic x faces: to the occupied rows of blocks).
 */
#include "core/core.h"

#include "core/domain.h"
#include "core/key_sort.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

bool gm_block_key_of(const gm_domain *domain, const double *position_xyz,
                     int64_t *key) {
  int64_t node[3] = {0, 0, 0};
  for (int k = 0; k < domain->dim; k++) {
    /* The same arithmetic as gm_shape_linear_axis, so the block agrees
     * with the cell the shape functions use; nodes count from the ghost
     * layer below the box (support.h). */
    double scaled =
        (position_xyz[k] - domain->shape_grid.origin[k]) * domain->inv_cell;
    if (!(scaled >= GM_GHOST_LAYERS &&
          scaled < (double)(domain->cells[k] + GM_GHOST_LAYERS)))
      return false;
    node[k] = (int64_t)scaled;
  }
  *key = domain->dim == 3
             ? gm_block_key_of_node_3d(&domain->grid, node[0], node[1], node[2])
             : gm_block_key_of_node(&domain->grid, node[0], node[1]);
  return true;
}

static size_t hash_slot(const gm_grid *grid, int64_t key) {
  uint64_t mixed = (uint64_t)key * 0x9E3779B97F4A7C15ull;
  return (size_t)(mixed >> 17) & (grid->hash_capacity - 1);
}

/* Index of key, or GM_NO_BLOCK. */
uint32_t gm_grid_find(const gm_grid *grid, int64_t key) {
  size_t slot = hash_slot(grid, key);
  while (grid->hash_key[slot] != -1) {
    if (grid->hash_key[slot] == key)
      return grid->hash_value[slot];
    slot = (slot + 1) & (grid->hash_capacity - 1);
  }
  return GM_NO_BLOCK;
}

/* Inserts key (value unset) if absent; returns false when out of memory. */
static bool hash_insert(gm_grid *grid, int64_t key);

static bool hash_rebuild(gm_grid *grid, size_t capacity) {
  int64_t *old_key = grid->hash_key;
  size_t old_capacity = grid->hash_capacity;
  int64_t *new_key = gm_alloc(capacity * sizeof(int64_t));
  uint32_t *new_value = gm_alloc(capacity * sizeof(uint32_t));
  if (!new_key || !new_value) {
    gm_free(new_key);
    gm_free(new_value);
    return false;
  }
  memset(new_key, 0xff, capacity * sizeof(int64_t)); /* all -1 = empty */
  gm_free(grid->hash_value);
  grid->hash_key = new_key;
  grid->hash_value = new_value;
  grid->hash_capacity = capacity;
  grid->hash_used = 0;
  for (size_t slot = 0; slot < old_capacity; slot++)
    if (old_key[slot] != -1)
      hash_insert(grid, old_key[slot]);
  gm_free(old_key);
  return true;
}

static bool hash_insert(gm_grid *grid, int64_t key) {
  if (2 * (grid->hash_used + 1) > grid->hash_capacity &&
      !hash_rebuild(grid, grid->hash_capacity ? 2 * grid->hash_capacity : 64))
    return false;
  size_t slot = hash_slot(grid, key);
  while (grid->hash_key[slot] != -1) {
    if (grid->hash_key[slot] == key)
      return true;
    slot = (slot + 1) & (grid->hash_capacity - 1);
  }
  grid->hash_key[slot] = key;
  grid->hash_value[slot] = 0; /* see NEIGHBOURS_IN */
  grid->hash_used++;
  return true;
}

/* While gm_grid_build inserts, before the values are set, a key's value
 * says whether its block was inserted with its neighbours (NEIGHBOURS_IN)
 * or only as another block's neighbour (0). A key met again in a later
 * run of points (the granular cloud's first binning meets each plain key
 * once per node layer) is then looked up once instead of inserted with
 * its neighbours again: the same keys inserted in the same order, so the
 * same hash. A growth of the hash clears the marks (hash_rebuild inserts
 * afresh), which only costs a repeated insertion. */
#define NEIGHBOURS_IN 1u

static uint32_t *build_mark(gm_grid *grid, int64_t key) {
  if (!grid->hash_capacity)
    return NULL;
  size_t slot = hash_slot(grid, key);
  while (grid->hash_key[slot] != -1) {
    if (grid->hash_key[slot] == key)
      return &grid->hash_value[slot];
    slot = (slot + 1) & (grid->hash_capacity - 1);
  }
  return NULL;
}

static void hash_clear(gm_grid *grid) {
  if (grid->hash_capacity)
    memset(grid->hash_key, 0xff, grid->hash_capacity * sizeof(int64_t));
  grid->hash_used = 0;
}

/* Makes room for block_count blocks (node fields, links, counters). */
static bool reserve_blocks(gm_domain *domain, size_t block_count) {
  gm_grid *grid = &domain->grid;
  if (block_count <= grid->block_capacity)
    return true;
  size_t old = grid->block_capacity;
  /* The node fields are most of the grid's memory (40 bytes per node, 64
   * nodes per block). The first binning sizes them to the blocks the
   * points occupy plus a few; later growth adds an eighth, so a flow that
   * spreads still reallocates only geometrically often, and a scene that
   * stays in place never reallocates after its first step. (A headroom of
   * a half, before, cost 7 bytes per point of a compact block:
   * docs/performance.md, "Where the bytes go".) */
  size_t headroom = old == 0 ? 4 : block_count / 8 + 4;
  size_t capacity = block_count + headroom;
  size_t nodes_old = old * GM_BLOCK_NODES, nodes = capacity * GM_BLOCK_NODES;
  void **arrays[] = {(void **)&grid->mass, (void **)&grid->momentum[0],
                     (void **)&grid->momentum[1], (void **)&grid->force[0],
                     (void **)&grid->force[1]};
  for (size_t a = 0; a < sizeof arrays / sizeof arrays[0]; a++)
    if (!gm_grow(arrays[a], sizeof(double), nodes_old, nodes))
      return false;
  if (grid->dim == 3 && /* the z components, 3D only */
      (!gm_grow((void **)&grid->momentum[2], sizeof(double), nodes_old,
                nodes) ||
       !gm_grow((void **)&grid->force[2], sizeof(double), nodes_old, nodes)))
    return false;
  /* Each array is stored back as soon as it has grown: gm_grow frees the
   * old one, so a later failure must not leave a stale pointer behind. */
  struct {
    void **array;
    size_t element, old_count, new_count;
  } links[] = {
      {(void **)&grid->neighbour, GM_BLOCK_NEIGHBOURS * sizeof(uint32_t), old,
       capacity},
      {(void **)&grid->block_key, sizeof(int64_t), old, capacity},
      {(void **)&grid->point_start, sizeof(uint32_t), old + 1, capacity + 1},
      {(void **)&grid->color_block, sizeof(uint32_t), old, capacity},
      {(void **)&grid->gap_slot, sizeof(uint32_t), old, capacity}};
  for (size_t a = 0; a < sizeof links / sizeof links[0]; a++)
    if (!gm_grow(links[a].array, links[a].element, links[a].old_count,
                 links[a].new_count))
      return false;
  grid->block_capacity = capacity;
  return true;
}

/* Inserts block `key` and those of its upper neighbours (slot ox + 2 oy +
 * 4 oz, as the links) whose bit is set in `slots` and that exist in the
 * box; the block itself (slot 0) is always inserted. */
static bool insert_slots(gm_grid *grid, int64_t key, unsigned slots) {
  int64_t blocks_x = grid->blocks_per_axis[0];
  int64_t blocks_y = grid->dim > 1 ? grid->blocks_per_axis[1] : 1;
  int64_t blocks_z = grid->dim == 3 ? grid->blocks_per_axis[2] : 1;
  int64_t block[3] = {0, 0, 0};
  if (grid->dim == 3)
    gm_block_coordinates_3d(grid, key, block);
  else
    gm_block_coordinates(grid, key, block);
  for (int slot = 0; slot < GM_BLOCK_NEIGHBOURS; slot++) {
    int64_t ox = slot & 1, oy = (slot >> 1) & 1, oz = slot >> 2;
    if ((slot != 0 && !(slots & (1u << slot))) || block[0] + ox >= blocks_x ||
        block[1] + oy >= blocks_y || block[2] + oz >= blocks_z)
      continue;
    /* Within the block's own layer. */
    if (!hash_insert(grid, key + (oz * blocks_y + oy) * blocks_x + ox))
      return false;
  }
  return true;
}

/* The same in 3D: the block and its seven upper neighbours that exist. */
static bool insert_with_neighbours_3d(gm_grid *grid, int64_t key) {
  int64_t blocks_x = grid->blocks_per_axis[0];
  int64_t blocks_y = grid->blocks_per_axis[1];
  int64_t block[3];
  gm_block_coordinates_3d(grid, key, block);
  for (int64_t dz = 0; dz <= 1; dz++)
    for (int64_t dy = 0; dy <= 1; dy++)
      for (int64_t dx = 0; dx <= 1; dx++)
        if (block[0] + dx < blocks_x && block[1] + dy < blocks_y &&
            block[2] + dz < grid->blocks_per_axis[2] &&
            !hash_insert(grid, key + (dz * blocks_y + dy) * blocks_x + dx))
          return false;
  return true;
}

/* Adds the blocks whose nodes the cells of block `key` reach. */
static bool insert_with_neighbours(gm_grid *grid, int64_t key) {
  if (grid->dim == 3)
    return insert_with_neighbours_3d(grid, key);
  int64_t blocks_x = grid->blocks_per_axis[0];
  int64_t block[2];
  gm_block_coordinates(grid, key, block);
  int reach_y = grid->dim > 1 ? 1 : 0;
  for (int64_t dy = 0; dy <= reach_y; dy++)
    for (int64_t dx = 0; dx <= 1; dx++)
      if (block[0] + dx < blocks_x &&
          block[1] + dy < grid->blocks_per_axis[1] &&
          !hash_insert(grid, key + dy * blocks_x + dx)) /* same layer */
        return false;
  return true;
}

/* Every upper neighbour: a block's cells may reach any of them. */
static unsigned all_slots(const gm_grid *grid) {
  return grid->dim == 3 ? 0xffu : grid->dim == 2 ? 0x0fu : 0x03u;
}

/* Whether the upper neighbours a block needs are found from its points'
 * cells (sparse_slots). For linear shapes the support is the point's
 * cell, and every transfer, gather, gap and rigid pass reaches the nodes
 * through it (p2g_3d.c, g2p_3d.c, wall_gaps_3d.c, rigid.c): a neighbour no
 * cell reaches receives nothing and is read by nothing, so leaving it out
 * changes no bit. Only the granular family in 3D uses it: its node layers
 * hold one to three points per 4 x 4 x 4-node block (the 30 %-disconnected
 * cloud of granmpm-bench, 8 layers), where a quarter of the blocks were
 * neighbours no cell reached (docs/performance.md, "Sparse node layers").
 * In 2D (8 x 8-node blocks, 3 neighbours) the cloud's layers lost only 4 %
 * of their blocks and the step gained 2 % of instructions: not used there.
 * Periodic x faces keep whole rows (gm_grid_build). */
static bool sparse_neighbours(const gm_domain *domain) {
  return domain->def.family == GM_FAMILY_GRANULAR && domain->dim == 3 &&
         domain->shape_grid.shape == GM_SHAPE_LINEAR && !gm_periodic_x(domain);
}

/* The neighbour slots reached from a cell that is the last of its block
 * along the axes of bit mask `axes`: every slot ox + 2 oy + 4 oz whose
 * axes are all among them (and slot 0). */
static const uint8_t reached_slots[8] = {0x01, 0x03, 0x05, 0x0f,
                                         0x11, 0x33, 0x55, 0xff};

/* The neighbour slots the cell of point i reaches, `block` the coordinates
 * of its key's block. The cell is the one of gm_shape_linear_axis_inside;
 * where it lies outside that block (a key the position does not give),
 * all slots, as without the pruning. */
static unsigned sparse_slots(const gm_domain *domain, size_t i,
                             const int64_t block[3], unsigned every) {
  const gm_point_buffers *current = &domain->points.buffer[domain->points.cur];
  int shift = domain->grid.shift;
  int64_t mask = ((int64_t)1 << shift) - 1;
  unsigned axes = 0; /* bit k: the cell is the last of its block on axis k */
  for (int k = 0; k < domain->dim; k++) {
    double scaled = (current->position[k][i] - domain->shape_grid.origin[k]) *
                    domain->inv_cell; /* cells */
    int64_t node = (int64_t)scaled;
    if (!(scaled >= 0.0) || node >> shift != block[k])
      return every;
    axes |= (unsigned)((node & mask) == mask) << k;
  }
  return reached_slots[axes];
}

/* The eight links of a 3D block (slot ox + 2 oy + 4 oz); none past the
 * last block of an axis. */
static void link_block_3d(gm_grid *grid, size_t b, uint32_t *links) {
  int64_t blocks_x = grid->blocks_per_axis[0];
  int64_t blocks_y = grid->blocks_per_axis[1];
  int64_t key = grid->block_key[b];
  int64_t block[3];
  gm_block_coordinates_3d(grid, key, block);
  for (int slot = 0; slot < 8; slot++) {
    int64_t ox = slot & 1, oy = (slot >> 1) & 1, oz = slot >> 2;
    bool inside = block[0] + ox < blocks_x && block[1] + oy < blocks_y &&
                  block[2] + oz < grid->blocks_per_axis[2];
    links[slot] =
        slot == 0 ? (uint32_t)b
        : inside
            ? gm_grid_find(grid, key + (oz * blocks_y + oy) * blocks_x + ox)
            : GM_NO_BLOCK;
  }
}

static void link_blocks(gm_grid *grid) {
  int64_t blocks_x = grid->blocks_per_axis[0];
  size_t colour_count[GM_BLOCK_COLOURS] = {0};
  for (size_t b = 0; b < grid->block_count; b++) {
    int64_t key = grid->block_key[b];
    uint32_t *links = grid->neighbour + b * GM_BLOCK_NEIGHBOURS;
    if (grid->dim == 3) {
      link_block_3d(grid, b, links);
      colour_count[gm_block_colour(grid, key)]++;
      continue;
    }
    for (int slot = 4; slot < GM_BLOCK_NEIGHBOURS; slot++)
      links[slot] = GM_NO_BLOCK; /* no z neighbours below 3D */
    links[0] = (uint32_t)b;
    links[1] = gm_grid_find(grid, key + 1);
    links[2] = grid->dim > 1 ? gm_grid_find(grid, key + blocks_x) : GM_NO_BLOCK;
    links[3] =
        grid->dim > 1 ? gm_grid_find(grid, key + blocks_x + 1) : GM_NO_BLOCK;
    int64_t block[2];
    gm_block_coordinates(grid, key, block);
    if (block[0] == blocks_x - 1) /* no wrap-around to the next row */
      links[1] = links[3] = GM_NO_BLOCK;
    if (grid->dim > 1 && block[1] == grid->blocks_per_axis[1] - 1)
      links[2] = links[3] = GM_NO_BLOCK; /* nor to the next layer */
    colour_count[gm_block_colour(grid, key)]++;
  }
  grid->color_start[0] = 0;
  for (int c = 0; c < GM_BLOCK_COLOURS; c++)
    grid->color_start[c + 1] = grid->color_start[c] + colour_count[c];
  size_t fill[GM_BLOCK_COLOURS];
  memcpy(fill, grid->color_start, sizeof fill);
  for (size_t b = 0; b < grid->block_count; b++)
    grid->color_block[fill[gm_block_colour(grid, grid->block_key[b])]++] =
        (uint32_t)b;
}

/* Inserts each run of one key with the upper neighbours its points' cells
 * reach (sparse_neighbours: never with periodic x faces). */
static bool insert_sparse(gm_grid *grid, const gm_domain *domain) {
  const gm_points *points = &domain->points;
  const int64_t *point_key = points->block_key;
  unsigned every = all_slots(grid);
  for (size_t i = 0; i < points->count;) {
    int64_t run_key = point_key[i];
    int64_t block[3] = {0, 0, 0}; /* of the run's key */
    if (grid->dim == 3)
      gm_block_coordinates_3d(grid, run_key, block);
    else
      gm_block_coordinates(grid, run_key, block);
    unsigned slots = 1;
    for (; i < points->count && point_key[i] == run_key; i++)
      slots |= sparse_slots(domain, i, block, every);
    if (!insert_slots(grid, run_key, slots))
      return false;
  }
  return true;
}

gm_status gm_grid_build(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  const gm_points *points = &domain->points;
  const int64_t *point_key = points->block_key;
  hash_clear(grid);
  bool periodic = gm_periodic_x(domain);
  bool sparse = sparse_neighbours(domain);
  grid->sparse = sparse;
  int64_t blocks_x = grid->blocks_per_axis[0];
  /* Points are sorted by block: most keys repeat. */
  if (sparse) {
    if (!insert_sparse(grid, domain))
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "grid: out of memory for the block hash");
  } else {
    int64_t previous = -1;
    for (size_t i = 0; i < points->count; i++) {
      if (point_key[i] == previous)
        continue;
      previous = point_key[i];
      /* Periodic x faces: the whole row of blocks, so that the owner of
       * every image node exists (grid/periodic.c). Rows are short next to
       * the work of a layer that fills the period. */
      int64_t first = periodic ? previous - previous % blocks_x : previous;
      int64_t last = periodic ? first + blocks_x - 1 : previous;
      uint32_t *mark = periodic ? NULL : build_mark(grid, previous);
      if (mark && *mark == NEIGHBOURS_IN)
        continue;
      for (int64_t key = first; key <= last; key++)
        if (!insert_with_neighbours(grid, key))
          return gm_set_error(domain, GM_ERR_NO_MEMORY,
                              "grid: out of memory for the block hash");
      if (!periodic && (mark = build_mark(grid, previous)) != NULL)
        *mark = NEIGHBOURS_IN;
    }
  }
  if (!reserve_blocks(domain, grid->hash_used))
    return gm_set_error(domain, GM_ERR_NO_MEMORY,
                        "grid: out of memory for %zu blocks", grid->hash_used);
  size_t count = 0;
  for (size_t slot = 0; slot < grid->hash_capacity; slot++)
    if (grid->hash_key[slot] != -1)
      grid->block_key[count++] = grid->hash_key[slot];
  /* Sorted keys fix the order of every grid sum. The keys are distinct,
   * so any correct sort gives the one ascending order: gm_key_sort
   * (core/key_sort.c, an introsort in place) replaced qsort, whose merge
   * sort through a comparison callback took about 100 instructions per
   * point-step in the granular cloud's two binnings (docs/performance.md,
   * "The granular cloud"), and which may allocate its merge buffer inside
   * a step. */
  gm_key_sort(grid->block_key, count);
  grid->block_count = count;
  for (size_t b = 0; b < count; b++) {
    size_t slot = hash_slot(grid, grid->block_key[b]);
    while (grid->hash_key[slot] != grid->block_key[b])
      slot = (slot + 1) & (grid->hash_capacity - 1);
    grid->hash_value[slot] = (uint32_t)b;
  }
  link_blocks(grid);
  return GM_OK;
}
