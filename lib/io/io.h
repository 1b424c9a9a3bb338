/*
 * io.h - the io folder: the VTK XML writer (vtu.c, vtu_domains.c, with
 * vtu_format.h), the ParaView series (series.c) and checkpoints
 * (checkpoint*.c, with checkpoint_format.h). The top layer: the writers
 * are built on the public API like a host (gm_domain_get_time, the field
 * accessors), and no other folder calls into io/, so this header only
 * gathers what io/ uses from the folders below it. Private to the library.
 */
#ifndef GM_IO_H
#define GM_IO_H

#include "granular/granular.h"
#include "materials/materials.h"
#include "points/points.h"

#endif
