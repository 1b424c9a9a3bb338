/*
 * granmpm/filling.h - the pressure-volume model of Wieckowski 2004 ("001")
 * sec 5.1.2 for silo filling. Included from the end of granmpm.h (after
 * granmpm/perzyna.h); do not include it directly.
 *
 * Conventions: stress in Pa, tension positive, p = -tr(sigma)/3
 * (compression positive), s = sigma + p I, q = sqrt(3/2 s:s).
 *
 * Pressure (eq 24), a Voigt body: elastic part plus bulk viscosity,
 *   p = p0 exp[(1 + e0)/kappa (1 - exp(eps_vol))] + (-mu d(eps_vol)/dt)^+,
 * where eps_vol = ln(V/V0) is the logarithmic volumetric strain (tension
 * positive) from the reference state of void ratio e0 and pressure p0, so
 * exp(eps_vol) = (1 + e)/(1 + e0) and the elastic part is the soil-mechanics
 * line e - e0 = -kappa ln(p/p0). eps_vol is read off the point's density
 * at the end of the step, eps_vol = ln(rho0/rho) with rho0 = density
 * below (001 computes the pressure from the density for this model, sec
 * 3.3), and the rate is (sum of the strain increments)/dt: the paper's
 * "explicit integration" of eq 24. The pressure does not depend on the
 * incoming stress. A point placed at rho0 starts at p0; one placed looser
 * starts at p0 exp[(1 + e0)/kappa (1 - rho0/rho)], practically 0 for 001's
 * portions (20 kg in 0.02 m^3: 1000 kg/m^3, so eps_vol = 0.405 and
 * p = 600 Pa e^-47.5). Give a source or gm_point_def the placement
 * density; for the granular family a critical density where the pressure
 * has dropped to about p0/100, rho0/(1 + kappa ln(100)/(1 + e0)), keeps
 * the density control from pushing a free surface apart.
 *
 * Deviator: eqs 16-22 as in granmpm/perzyna.h (the same backward Euler
 * viscoplastic return, by calling gm_perzyna_update), with the pressure-
 * dependent shear modulus of sec 5.1.2
 *   G = 3/2 (1 - 2 nu)/(1 + nu) (1 + e0)/kappa p_el exp(eps_vol),
 * i.e. G = 3 K (1 - 2 nu)/(2 (1 + nu)) with the tangent bulk modulus
 * K = -dp_el/d(eps_vol) = (1 + e) p_el / kappa of the elastic part p_el
 * (the viscous part has no stiffness, so p in that formula is p_el), at the
 * end of the step. The cone f = q - m p uses the total pressure p.
 *
 * Per-point state: state[0] = eps_vol (-, written for output; read off
 * the density each step), state[1] = accumulated equivalent viscoplastic
 * strain (-).
 */
#ifndef GRANMPM_FILLING_H
#define GRANMPM_FILLING_H

enum { GM_FILLING_STATE_COUNT = 2 };

typedef struct gm_filling_def {
  size_t struct_size;        /* set by gm_filling_def_default() */
  const char *name;          /* copied; for messages and VTU */
  double density;            /* rho0, bulk density at e0 (kg/m^3), > 0:
                                skeleton density rho_s / (1 + e0) (the
                                paper: 2850/1.9 = 1500); also the default
                                density of new points */
  double poisson_ratio;      /* nu, -1 < nu < 0.5 (sets G/K) */
  double kappa;              /* elastic coefficient of e - e0 = -kappa
                                ln(p/p0), -, > 0 (sands ~0.001-0.05) */
  double void_ratio;         /* e0 at the reference state, -, > 0 */
  double reference_pressure; /* p0, Pa, > 0: pressure at eps_vol = 0 */
  double bulk_viscosity;     /* mu, Pa s, >= 0 (0: no viscous term) */
  double friction_angle;     /* phi, rad, 0 < phi < pi/2 */
  double fluidity;           /* gamma of eq 18, 1/s, > 0 */
  double exponent;           /* N of the overstress function, > 0 */
  double reference_stress;   /* Pa, >= 0, as in gm_perzyna_def */
  double max_pressure;       /* Pa, >= p0: the largest pressure expected;
                                bounds K + 4G/3 for the stable time step
                                (K <= max_pressure (1 + e0)/kappa). Past
                                it eq 24 continues linearly in the log
                                volume strain with its tangent modulus
                                there, so the bound still holds. The bulk
                                viscosity adds its own explicit limit
                                dt < ~rho h^2 / mu, not checked here. */
  int max_iterations;        /* 1..1000, as in gm_perzyna_def */
} gm_filling_def;

/* Defaults: the filling data of 001 sec 5.1.2 (kappa = 0.02, nu = 0.3,
 * e0 = 0.9, p0 = 600 Pa, phi = 30 deg, mu = 1e4 Pa s, gamma = 1e4 1/s,
 * N = 1, rho_s = 2850 kg/m^3); max_pressure 1e5 Pa (a silo ~6 m deep). */
/** gm_filling_def_init(&d, sizeof d) writes these defaults (gm_*_init
 * convention, granmpm.h); gm_filling_def_default() returns them. */
GM_API gm_status gm_filling_def_init(gm_filling_def *out, size_t struct_size);

static inline gm_filling_def gm_filling_def_default(void) {
  gm_filling_def value;
  (void)gm_filling_def_init(&value, sizeof value);
  return value;
}

/** Registers the filling material (GM_FILLING_STATE_COUNT state doubles
 * per point, initially 0). GM_ERR_INVALID_ARGUMENT names the offending
 * gm_filling_def field. */
GM_API gm_status gm_domain_add_filling(gm_domain *domain,
                                       const gm_filling_def *def,
                                       int *material_id);

/** The update itself (user must point to a gm_filling_def; batch->state
 * must hold GM_FILLING_STATE_COUNT columns). Returns as gm_perzyna_update. */
GM_API int gm_filling_update(const gm_material_batch *batch, void *user,
                             char *message, size_t message_size);

#endif /* GRANMPM_FILLING_H */
