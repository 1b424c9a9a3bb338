/*
 * defaults.c - the default value of every definition and result structure,
 * exported as gm_*_init() (granmpm(3), "Definition structures"). They are
 * the one source of the defaults: the inline gm_*_default() of the headers
 * call them, and so do hosts that cannot use a C inline function (Fortran
 * through the granmpm module, Python through ctypes).
 *
 * Each gm_X_init(out, struct_size) writes the defaults into a caller's
 * structure of struct_size bytes (sizeof, c_sizeof or ctypes.sizeof). They
 * take a pointer and a size rather than returning the structure by value
 * because a structure returned by value from a newer library that appended
 * fields would overrun an older caller's storage; with the size the library
 * writes only what the caller has (design.md: fields are only appended).
 */
#include "core/core.h"

#include "core/api_check.h"

#include <stddef.h>
#include <string.h>

/* Copies the library's `defaults` (library_size bytes) into the caller's
 * structure of struct_size bytes: GM_ERR_STRUCT_SIZE (nothing written)
 * unless struct_size is this layout, an earlier one the library accepts or
 * a larger one (the layout table of api_check.c); bytes past the library's
 * layout are zeroed; struct_size, the first member of every such structure, is
 * set to the bytes filled from the defaults. */
static gm_status copy_defaults(void *out, size_t struct_size,
                               const void *defaults, gm_layout layout) {
  if (!out)
    return GM_ERR_NULL;
  if (!gm_layout_known(layout, struct_size))
    return GM_ERR_STRUCT_SIZE;
  size_t library_size = gm_layout_size(layout);
  size_t filled = struct_size < library_size ? struct_size : library_size;
  memcpy(out, defaults, filled);
  if (struct_size > library_size)
    memset((char *)out + library_size, 0, struct_size - library_size);
  memcpy(out, &filled, sizeof filled);
  return GM_OK;
}

/* The defaults of gm_X into out: the layout named after the type. */
#define COPY_DEFAULTS(out, struct_size, value, layout)                         \
  copy_defaults(out, struct_size, &(value), layout)

gm_status gm_domain_def_init(gm_domain_def *def, size_t struct_size) {
  gm_domain_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.geometry = GM_GEOMETRY_PLANE_STRAIN;
  value.extent[0] = value.extent[1] = value.extent[2] = 1.0; /* m */
  value.cell_size = 0.1;                                     /* m */
  value.scheme = GM_SCHEME_USL;
  value.cfl = 0.5;
  value.max_retries = 4;
  value.worker_count = 1;
  value.shape = GM_SHAPE_LINEAR;
  value.family = GM_FAMILY_PLAIN;
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_DOMAIN_DEF);
}

gm_status gm_material_def_init(gm_material_def *def, size_t struct_size) {
  gm_material_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.name = "user";
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_MATERIAL_DEF);
}

gm_status gm_elastic_def_init(gm_elastic_def *def, size_t struct_size) {
  gm_elastic_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.name = "elastic";
  value.youngs_modulus = 1e6; /* Pa */
  value.poisson_ratio = 0.3;
  value.density = 1000.0; /* kg/m^3 */
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_ELASTIC_DEF);
}

gm_status gm_wall_def_init(gm_wall_def *def, size_t struct_size) {
  gm_wall_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.normal[1] = 1.0; /* a floor: material above */
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_WALL_DEF);
}

gm_status gm_wall_force_init(gm_wall_force *force, size_t struct_size) {
  gm_wall_force value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  return COPY_DEFAULTS(force, struct_size, value, GM_LAYOUT_WALL_FORCE);
}

gm_status gm_rigid_load_init(gm_rigid_load *load, size_t struct_size) {
  gm_rigid_load value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  return COPY_DEFAULTS(load, struct_size, value, GM_LAYOUT_RIGID_LOAD);
}

gm_status gm_rigid_def_init(gm_rigid_def *def, size_t struct_size) {
  gm_rigid_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.name = "rigid";
  value.density = 1000.0; /* kg/m^3 */
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_RIGID_DEF);
}

gm_status gm_source_def_init(gm_source_def *def, size_t struct_size) {
  gm_source_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_SOURCE_DEF);
}

gm_status gm_sink_def_init(gm_sink_def *def, size_t struct_size) {
  gm_sink_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_SINK_DEF);
}

gm_status gm_flow_totals_init(gm_flow_totals *totals, size_t struct_size) {
  gm_flow_totals value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  return COPY_DEFAULTS(totals, struct_size, value, GM_LAYOUT_FLOW_TOTALS);
}

gm_status gm_granular_def_init(gm_granular_def *def, size_t struct_size) {
  gm_granular_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.tolerance = 1e-6; /* kg/m^3 */
  value.density_control = GM_DENSITY_CONTROL_RETURN;
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_GRANULAR_DEF);
}

gm_status gm_granular_summary_init(gm_granular_summary *summary,
                                   size_t struct_size) {
  gm_granular_summary value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  return COPY_DEFAULTS(summary, struct_size, value, GM_LAYOUT_GRANULAR_SUMMARY);
}

gm_status gm_points_def_init(gm_points_def *def, size_t struct_size) {
  gm_points_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_POINTS_DEF);
}

gm_status gm_fill_def_init(gm_fill_def *def, size_t struct_size) {
  gm_fill_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.points_per_cell_axis = 2;
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_FILL_DEF);
}

gm_status gm_summary_init(gm_summary *summary, size_t struct_size) {
  gm_summary value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  return COPY_DEFAULTS(summary, struct_size, value, GM_LAYOUT_SUMMARY);
}

/* The built-in materials: the data sets of the papers named in their
 * headers. */

/* 001 sec 5.1.1: the stored granular material of Wieckowski 2004. */
gm_status gm_drucker_prager_def_init(gm_drucker_prager_def *def,
                                     size_t struct_size) {
  gm_drucker_prager_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.name = "drucker_prager";
  value.youngs_modulus = 1e6; /* Pa */
  value.poisson_ratio = 0.3;
  value.density = 1500.0;                     /* kg/m^3 */
  value.friction_angle = 0.43633231299858239; /* 25 degrees in radians */
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_DRUCKER_PRAGER_DEF);
}

/* 001 sec 5.1.2: the filling data; max_pressure for a silo ~6 m deep. */
gm_status gm_filling_def_init(gm_filling_def *def, size_t struct_size) {
  gm_filling_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.name = "filling";
  value.density = 1500.0; /* kg/m^3, 2850 / (1 + 0.9) */
  value.poisson_ratio = 0.3;
  value.kappa = 0.02;
  value.void_ratio = 0.9;
  value.reference_pressure = 600.0;          /* Pa */
  value.bulk_viscosity = 1e4;                /* Pa s */
  value.friction_angle = 0.5235987755982988; /* 30 degrees */
  value.fluidity = 1e4;                      /* 1/s */
  value.exponent = 1.0;
  value.reference_stress = 0.0; /* Pa */
  value.max_pressure = 1e5;     /* Pa */
  value.max_iterations = 60;
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_FILLING_DEF);
}

/* 000 Table 3: the granular material of Seyedan & Solowski 2021. */
gm_status gm_mohr_coulomb_def_init(gm_mohr_coulomb_def *def,
                                   size_t struct_size) {
  gm_mohr_coulomb_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.name = "mohr_coulomb";
  value.youngs_modulus = 1e9; /* Pa */
  value.poisson_ratio = 0.3;
  value.density = 2250.0;                     /* kg/m^3 */
  value.friction_angle = 0.52359877559829887; /* 30 degrees */
  value.dilation_angle = 0.0;
  value.bagnold_viscosity = 0.15; /* Pa s^2 */
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_MOHR_COULOMB_DEF);
}

/* 001 sec 5.1.1: the silo discharge data. */
gm_status gm_perzyna_def_init(gm_perzyna_def *def, size_t struct_size) {
  gm_perzyna_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.name = "perzyna";
  value.youngs_modulus = 1e6; /* Pa */
  value.poisson_ratio = 0.3;
  value.density = 1500.0;                    /* kg/m^3 */
  value.friction_angle = 0.4363323129985824; /* 25 degrees */
  value.fluidity = 50.0;                     /* 1/s */
  value.exponent = 1.0;
  value.reference_stress = 0.0; /* Pa */
  value.max_iterations = 60;
  value.always_iterate = 0;
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_PERZYNA_DEF);
}

/* Constrained modulus of the default gm_drucker_prager_def, so that dt
 * stays valid when a point switches between the two. */
gm_status gm_stress_free_def_init(gm_stress_free_def *def, size_t struct_size) {
  gm_stress_free_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.name = "stress_free";
  value.density = 1500.0;                      /* kg/m^3 */
  value.p_wave_modulus = 1.3461538461538462e6; /* Pa, 1e6 0.7 / (1.3 0.4) */
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_STRESS_FREE_DEF);
}

/* 001 sec 5.3.1: the steel of the extrusion example. */
gm_status gm_von_mises_def_init(gm_von_mises_def *def, size_t struct_size) {
  gm_von_mises_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.name = "von_mises";
  value.youngs_modulus = 2e11; /* Pa */
  value.poisson_ratio = 0.3;
  value.density = 7800.0;   /* kg/m^3 */
  value.yield_stress = 2e7; /* Pa */
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_VON_MISES_DEF);
}

gm_status gm_mu_i_def_init(gm_mu_i_def *def, size_t struct_size) {
  gm_mu_i_def value;
  memset(&value, 0, sizeof value);
  value.struct_size = sizeof value;
  value.name = "mu_i";
  value.youngs_modulus = 1e6; /* Pa */
  value.poisson_ratio = 0.3;
  value.density = 1500.0;                     /* kg/m^3 */
  value.grain_density = 2500.0;               /* kg/m^3 */
  value.grain_diameter = 0.5e-3;              /* m */
  value.static_friction = 0.3818628674187188; /* tan(20.9 deg) */
  value.limit_friction = 0.6434683848584607;  /* tan(32.76 deg) */
  value.inertial_number_scale = 0.279;
  value.critical_density = 0.0;
  value.regularise = 1;
  value.regularisation_exponent = 1.9;
  return COPY_DEFAULTS(def, struct_size, value, GM_LAYOUT_MU_I_DEF);
}
