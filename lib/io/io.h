/*
 * io.h - the io folder: the VTK XML writer (vtu.c, vtu_domains.c, with
 * vtu_format.h), the ParaView series (series.c) and checkpoints
 * (checkpoint*.c, with checkpoint_format.h). Its contract with the rest of
 * the library is the public API only: no other folder calls into io/, so
 * this header only gathers what io/ uses from the folders below it.
 * Private to the library.
 */
#ifndef GM_IO_H
#define GM_IO_H

#include "granular/granular.h"
#include "materials/materials.h"
#include "points/points.h"

#endif
