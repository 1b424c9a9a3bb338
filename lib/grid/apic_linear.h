/*
 * apic_linear.h - APIC with linear (multilinear) shape functions: the
 * light nodes' share of C_p's update. Shared by the 1D/2D gather (g2p.c)
 * and the 3D gather (g2p_3d.c). Private.
 *
 * Why. Linear MPM keeps C_p = B_p D_p^-1 = sum_i v_i (x) grad N_ip (Jiang
 * et al. 2015's rule for multilinear weights; p2g.c says why C_p rather
 * than B_p), and the next scatter hands node i m_p N_ip (v_p + C_p (x_i -
 * x_p)): a node's velocity relative to the point is handed back to it.
 * FLIP and PIC forget a node's velocity at every scatter (the node gets
 * m_p N_ip v_p); APIC keeps it, so each node becomes a degree of freedom
 * of its own, of mass m_i, integrated by the explicit grid update. A node
 * near a free face that only the tail of a point's tent reaches (the
 * point a fraction 1 - f -> 0 of a cell from the node plane beyond it)
 * has m_i -> 0 while the stress gradient force on it does not vanish: an
 * oscillator of omega^2 = k_i / m_i, unstable once omega dt > 2 (the
 * explicit bound of the grid update, here for one node). Measured, a free
 * elastic block translating at (1.3, 0.05) m/s (E = 1e4 Pa, 8 x 2 cells
 * of 0.1 m, 2 x 2 points per cell, USL, main at 536e1ab): the error grows
 * from round-off only while the bottom row of points creeps across a node
 * row, by 3.8, 5, 10, 21 and 250 times per step as its weight on the node
 * row below falls through 0.026, 0.021, 0.016, 0.011, 0.006 (about
 * (c dt / h)^2 / (1 - f), c dt / h = 0.37), and its elastic energy reaches 5 J
 * by step 250 and 100 J by step 400 (the translation carries 135 J/m); FLIP and
 * PIC keep the same block at round-off for 2000 steps.
 *
 * The remedy: the update that the grid's forces make to a node of too
 * little mass enters C_p in part only, as if the node's mass were m_crit
 * (mass scaling of that node for the affine part alone):
 *   C_p = sum_i v_i (x) grad N_ip - dt sum_i (1 - theta_i) a_i (x) grad N_ip,
 *   theta_i = min(1, m_i / m_crit),
 * with a_i the node's acceleration of this step. The velocity v_p = sum
 * N_ip v_i, the linear momentum and the point's own velocity field are
 * untouched; a node at rest or in free flight (a_i = 0) keeps its whole
 * velocity, so affine velocity fields are still reproduced exactly. In a
 * one-node model (u the node's velocity relative to the point, sigma the
 * point's stress: u' = u - theta dt f(sigma) / m_i, sigma' = sigma +
 * M dt grad u') the update is stable for theta dt^2 k_i / m_i <= 4; m_crit
 * = dt^2 k_i / 2 keeps it at half that. The stiffness k_i = sum_q M_q V_q
 * |grad N_iq|^2 of a node inside a body of the point's density and P-wave
 * modulus is gamma rho h^d c^2 / h^2, gamma = h^2 int |grad N|^2 / int N
 * = 2 (1D), 8/3 (2D, 3D; 2.5 on a lattice of 2 points per cell per
 * axis); a node at a face has less, so this over-estimates it there, on
 * the safe side. A node with the mass of a full node needs theta < 1 only
 * above c dt / h = 0.87 (gamma 8/3), so inside a body (every node of it
 * at a cfl below 0.87) nothing changes, bit for bit.
 */
#ifndef GM_APIC_LINEAR_H
#define GM_APIC_LINEAR_H

#include "core/domain.h"

/* The node mass (kg, or kg per m of thickness in the plane, per m^2 in
 * 1D, the whole ring in axisymmetry) below which node i's acceleration
 * enters point p's C_p in part only, over the step dt (s): m_crit = dt^2
 * k / 2 with k = gamma rho c^2 h^(d - 2) = gamma M h^(d - 2), M the point
 * material's P-wave modulus (Pa, as the stable dt reads it, stable_dt.c;
 * rho c^2 = M, so neither the density nor the volume enters), times
 * 2 pi r_p in axisymmetry (radius: x_p, m). Zero for a material without
 * stiffness. */
static inline double gm_apic_light_node_mass(const gm_domain *domain, size_t p,
                                             double radius, double dt) {
  double modulus =
      domain->materials[domain->points.material[p]].p_wave_modulus; /* Pa */
  double h = domain->def.cell_size;                                 /* m */
  double gamma = domain->dim == 1 ? 2.0 : 8.0 / 3.0;                /* - */
  double reach = domain->dim == 1 ? 1.0 / h : domain->dim == 3 ? h : 1.0;
  if (domain->axisymmetric)
    reach *= 2.0 * 3.14159265358979323846 * radius;
  return 0.5 * gamma * modulus * reach * dt * dt;
}

/* theta_i = min(1, m_i / m_crit), with 1 - theta_i returned (0 for a node
 * heavy enough). */
static inline double gm_apic_light_node_deficit(double node_mass,
                                                double critical_mass) {
  return node_mass < critical_mass ? 1.0 - node_mass / critical_mass : 0.0;
}

#endif
