/*
 * shapes.h - the shapes folder: the shape functions and a point's support
 * on the grid, pure functions of positions, domains and the grid spacing
 * (they never see the domain): linear (shape_linear.h), GIMP
 * (shape_gimp.h), B-splines (shape_bspline.h), and the support of a point
 * for every shape variant with the corners of its current domain
 * (support.h, support.c; in 3D support_3d.h, support_3d.c; the fixed
 * three-node axes of short GIMP domains, support_short.h; the inline 2D
 * CPDI support, support_cpdi.h; the 3D CPDI support, support_cpdi_3d.{h,c}),
 * and gm_pair, two doubles in one vector register (pair.h; here, the bottom
 * layer, so that the CPDI support and the transfers above share it). The
 * bottom layer: core/domain.h includes it for gm_shape_grid. Private to the
 * library.
 */
#ifndef GM_SHAPES_H
#define GM_SHAPES_H

#include "shapes/pair.h"
#include "shapes/shape_bspline.h"
#include "shapes/shape_gimp.h"
#include "shapes/shape_linear.h"
#include "shapes/support.h"
#include "shapes/support_3d.h"
#include "shapes/support_cpdi.h"
#include "shapes/support_cpdi_3d.h"
#include "shapes/support_short.h"

#endif
