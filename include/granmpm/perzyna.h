/*
 * granmpm/perzyna.h - elastic-viscoplastic Drucker-Prager material of the
 * Perzyna type (Wieckowski 2004, "001", sec 5.1.1, eqs 15-23). Included from
 * the end of granmpm.h; do not include it directly.
 *
 * Conventions: stress in Pa, tension positive; pressure
 *   p = -(s_xx + s_yy + s_zz)/3                (compression positive),
 * deviator s = sigma + p I and the Mises invariant
 *   q = sqrt(3/2 s:s)    (s:s counts each shear component twice).
 * The yield function is f = q - m p with (001 sec 5.1.1)
 *   m = 18 sin(phi) / (9 - sin^2(phi)),
 * the mean of the triaxial-compression cone 6 sin/(3 - sin) and the
 * extension cone 6 sin/(3 + sin) matched to Mohr-Coulomb. The material is
 * cohesionless. The viscoplastic flow is non-associated and deviatoric
 * (plastic potential g = q, so no plastic volume change): eq 18
 *   e_vp = fluidity <Phi(f)> dg/dsigma,  Phi = ((q - m p) / sigma_n)^N,
 * with the normalising stress sigma_n = m p in the paper; here
 *   sigma_n = max(m p, reference_stress)
 * so reference_stress = 0 (the default) is exactly the paper's model, and a
 * positive value bounds the overstress function near the free surface
 * (p -> 0). The pressure is elastic (eq 23) with a tension cut-off: a
 * cohesionless material carries no mean tension, so p is clipped at 0.
 *
 * Per-point state: state[0] = accumulated equivalent viscoplastic strain
 * (-), the sum of the increments Delta e_vp of eq 22, which equal
 * sqrt(2/3 e_vp:e_vp) dt.
 */
#ifndef GRANMPM_PERZYNA_H
#define GRANMPM_PERZYNA_H

enum { GM_PERZYNA_STATE_COUNT = 1 };

typedef struct gm_perzyna_def {
  size_t struct_size;      /* set by gm_perzyna_def_default() */
  const char *name;        /* copied; for messages and VTU */
  double youngs_modulus;   /* E, Pa, > 0 */
  double poisson_ratio;    /* nu, -1 < nu < 0.5 */
  double density;          /* kg/m^3, > 0, default for new points */
  double friction_angle;   /* phi, rad, 0 < phi < pi/2 (sets m above) */
  double fluidity;         /* gamma of eq 18 ("viscosity parameter"), 1/s,
                              > 0; the viscosity is 1/gamma, so gamma -> inf
                              is the rate-independent Drucker-Prager limit */
  double exponent;         /* N of Phi, > 0 (the paper uses N = 1); 0.1..10
                              is the useful range (N = 1 has a closed form) */
  double reference_stress; /* Pa, >= 0: sigma_n = max(m p, this); 0 = the
                              paper's normalisation by m p */
  int max_iterations;      /* Newton/bisection iterations for N != 1, 1..1000;
                              beyond them the update returns 1 (recoverable) */
  int always_iterate;      /* 0 (default): closed form for N = 1; nonzero:
                              the iteration also for N = 1 (for checks) */
} gm_perzyna_def;

/* Defaults: the silo discharge data of 001 sec 5.1.1 (E = 1e6 Pa, nu = 0.3,
 * phi = 25 deg, gamma = 50 1/s, N = 1, density 1500 kg/m^3). */
/** gm_perzyna_def_init(&d, sizeof d) writes these defaults (gm_*_init
 * convention, granmpm.h); gm_perzyna_def_default() returns them. */
GM_API gm_status gm_perzyna_def_init(gm_perzyna_def *out, size_t struct_size);

static inline gm_perzyna_def gm_perzyna_def_default(void) {
  gm_perzyna_def value;
  (void)gm_perzyna_def_init(&value, sizeof value);
  return value;
}

/** Registers the Perzyna Drucker-Prager material (GM_PERZYNA_STATE_COUNT
 * state doubles per point, initially 0). GM_ERR_INVALID_ARGUMENT names the
 * offending gm_perzyna_def field. */
GM_API gm_status gm_domain_add_perzyna(gm_domain *domain,
                                       const gm_perzyna_def *def,
                                       int *material_id);

/** The update itself (user must point to a gm_perzyna_def; batch->state
 * must hold at least GM_PERZYNA_STATE_COUNT columns). Returns 0, or 1 if
 * the iteration for N != 1 did not converge (the library then halves dt),
 * or -1 for a non-finite trial state; message names the point. */
GM_API int gm_perzyna_update(const gm_material_batch *batch, void *user,
                             char *message, size_t message_size);

#endif /* GRANMPM_PERZYNA_H */
