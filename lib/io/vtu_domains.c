/*
 * vtu_domains.c - gm_domain_write_domains_vtu: the current domain of every
 * material point as a polygon, so ParaView draws the domains as the
 * snapshots of 000 Figs 12 and 16 show them (a parallelogram per point with
 * CPDI, a rectangle with the GIMP variants and linear MPM; in 3D a
 * hexahedron: the GIMP box, or for linear MPM and CPDI the parallelepiped
 * F carries the initial box to).
 *
 * The corners come from GM_FIELD_DOMAIN_CORNERS (support.h), counter-
 * clockwise from the lower left, which is VTK_QUAD's vertex order, so a
 * domain with det F > 0 is a correctly oriented quad. Each point's corners
 * are its own VTK points (neighbouring domains overlap or gap as they
 * deform; they share no vertices), and the point's fields are the cell's
 * CellData. The file format is vtu.c's (vtu_format.h).
 */
#include "io/io.h"

#include "io/vtu_format.h"

/* 2D: the four corners of the domain, one VTK_QUAD per material point. */
static const gm_vtu_layout quad_layout = {"gm_domain_write_domains_vtu",
                                          GM_FIELD_DOMAIN_CORNERS, 4,
                                          GM_VTK_QUAD, "CellData"};

/* 3D: the eight corners of the domain (fields.c: the parallelepiped
 * spanned by F times the initial half edges, in VTK_HEXAHEDRON's vertex
 * order), one VTK_HEXAHEDRON per material point. */
static const gm_vtu_layout hexahedron_layout = {"gm_domain_write_domains_vtu",
                                                GM_FIELD_DOMAIN_CORNERS, 8,
                                                GM_VTK_HEXAHEDRON, "CellData"};

/* 1D: the two ends of the domain (y = z = 0), one VTK_LINE per point. */
static const gm_vtu_layout line_layout = {"gm_domain_write_domains_vtu",
                                          GM_FIELD_DOMAIN_CORNERS, 2,
                                          GM_VTK_LINE, "CellData"};

gm_status gm_domain_write_domains_vtu(const gm_domain *domain,
                                      const char *path) {
  if (!domain)
    return GM_ERR_NULL;
  const gm_vtu_layout *layout = domain->dim == 1   ? &line_layout
                                : domain->dim == 3 ? &hexahedron_layout
                                                   : &quad_layout;
  return gm_vtu_write(domain, path, layout);
}
