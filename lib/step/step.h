/*
 * step.h - the step folder, the orchestrators: the domain's lifecycle
 * (domain.c: create sizes every folder's scratch, destroy frees it), the
 * step (step.c: the stages of an attempt and their order per update
 * scheme, retries, commit; it calls every folder below) and
 * gm_domain_advance (advance.c). Only io/, the top layer, is above it.
 * Private to the library.
 */
#ifndef GM_STEP_H
#define GM_STEP_H

#include "boundaries/boundaries.h"
#include "granular/granular.h"
#include "grid/grid.h"
#include "materials/materials.h"
#include "points/points.h"

#endif
