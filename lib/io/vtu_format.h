/*
 * vtu_format.h - the VTK XML UnstructuredGrid writer of vtu.c, shared by the
 * two kinds of file the library writes:
 *
 *  - points (gm_domain_write_vtu): one VTK point and one VTK_VERTEX cell
 *    per material point, the fields as PointData;
 *  - domains (gm_domain_write_domains_vtu, vtu_domains.c): the corners of
 *    each material point's domain as VTK points, one VTK_LINE (1D),
 *    VTK_QUAD (2D) or VTK_HEXAHEDRON (3D) cell per material point, the
 *    fields as CellData.
 *
 * Both files have the same arrays in the same order; only where the VTK
 * points come from, how many there are per material point, the cell type
 * and the section holding the fields differ. A layout says which.
 */
#ifndef GM_VTU_FORMAT_H
#define GM_VTU_FORMAT_H

#include "io/io.h"

/* VTK cell type numbers (vtkCellType.h; fixed by the file format). */
enum {
  GM_VTK_VERTEX = 1,
  GM_VTK_LINE = 3,
  GM_VTK_QUAD = 9,
  GM_VTK_HEXAHEDRON = 12
};

typedef struct gm_vtu_layout {
  const char *caller; /* public function name, starts error messages */
  /* Field giving the VTK points, `vertices` after one another per
   * material point, each with components / vertices coordinates (m);
   * padded with zeros to x, y, z. */
  gm_field vertex_field;
  size_t vertices;        /* VTK points per material point, 1..8 */
  uint8_t cell_type;      /* GM_VTK_*, one cell per material point */
  const char *fields_tag; /* "PointData" or "CellData" */
} gm_vtu_layout;

/* Writes the domain in `layout` to path, through "<path>.tmp" renamed over
 * path only when complete (nothing is left behind on failure). */
gm_status gm_vtu_write(const gm_domain *domain, const char *path,
                       const gm_vtu_layout *layout);

#endif
