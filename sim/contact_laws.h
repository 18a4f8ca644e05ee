/* SPDX-License-Identifier: MIT */
/* contact_laws.h: the contact laws, written once for a generic lane type, included twice: with
 * LAW_T = double (contact_scalar.h; one contact: the wall pass and the diagnostics) and with
 * LAW_T = a vector of SIM_LANES doubles (the grain-grain pass, SIM_LANES contacts at a time).
 * Lane operations are supplied by the includer as LAW(abs), LAW(min), LAW(copysign), LAW(sel) and
 * LAW(sqrt), constants LAW_ZERO and LAW_ONE; LAW(name) appends the instance suffix. Every operation
 * is an exactly rounded IEEE operation in both instances (no contraction, no reciprocal estimates),
 * so a contact gives the same bits whatever the lane type. `key` is a compile-time constant in
 * every caller. */

/* Normal force magnitude (positive = repulsive) and its elastic part. 000 eq. 3.6 (linear),
 * Hertz-type sqrt(xi) (k_n xi + gamma_n dxi/dt). dxi/dt = -v_n.
 * Event-aware onset (KEY_EVENT, linear law only; docs/accuracy.md "Event-aware onset"): the force
 * of one evaluation is the mean of the force over the step around it, [t - h, t + h] with
 * h = half_dt (velocity Verlet applies it for dt/2 on each side), with the overlap's linear
 * trajectory xi(t + tau) = xi + |v_n| tau (approaching) or xi - |v_n| tau (separating). With
 * reach = |v_n| h the part of the step in contact is (eq. A3)
 *     phi = clamp((xi + reach) / (2 reach), 0, 1),
 * the overlap at the middle of that part is xi_m = phi reach (eq. A4), and the mean force is
 *     F = phi (k_n xi_m + gamma_n dxi/dt)                                            (eq. A5).
 * A step wholly in contact (xi >= reach) has phi = 1, xi_m = xi: the step law's bits. half_dt = 0
 * gives the instantaneous force (the diagnostics). */
KERNEL LAW_T LAW(normal_force)(const unsigned key, LAW_T k_n, LAW_T gamma_n, LAW_T xi, LAW_T v_n,
                               double half_dt, LAW_T *elastic)
{
    LAW_T f;
    if (key & KEY_HERTZ) {
        LAW_T root = LAW(sqrt)(xi);
        *elastic = k_n * xi * root;
        f = *elastic - gamma_n * root * v_n;
    } else if (key & KEY_EVENT) {
        LAW_T reach = LAW(abs)(v_n) * half_dt;
        LAW_T span = reach + reach;
        /* masks as selects, no branch: lanes in, out and across an event mix at random */
        LAW_T safe = LAW(sel)(span > 0.0, span, LAW_ONE);
        LAW_T part = LAW(sel)(xi + reach > 0.0, (xi + reach) / safe, LAW_ZERO);
        LAW_T phi = LAW(sel)(xi >= reach, LAW_ONE, part);
        LAW_T x = LAW(sel)(xi >= reach, xi, phi * reach);
        *elastic = phi * (k_n * x);
        f = phi * (k_n * x - gamma_n * v_n);
    } else {
        *elastic = k_n * xi;
        f = *elastic - gamma_n * v_n;
    }
    if (key & KEY_CLIP)
        f = LAW(sel)(f > 0.0, f, LAW_ZERO); /* a select: the sign is data, not control */
    return f;
}

/* Tangential force along s. Regularised Coulomb: 000 eq. 3.28 (`damping` is gamma_s). Spring:
 * 004 eqs. 1.12-1.13 with the cap on the elastic normal force, xi_t kept at the cap while
 * sliding, and the tangential dashpot of Luding 2008 (Granular Matter 10, 235, section 2.2,
 * "tangential contact model"; `damping` is gamma_t): the trial force k_t xi_t + gamma_t v_s is
 * tested against mu F_el and, when it slips, the spring is kept at (cap - gamma_t v_s) / k_t so
 * that the force stays on the cap. gamma_t = 0 selects the undamped spring's expressions (same
 * bits). Written without data-dependent branches: sticking and sliding contacts mix at random. */
KERNEL LAW_T LAW(tangential_force)(const unsigned key, LAW_T k_t, LAW_T mu, LAW_T damping,
                                   LAW_T v_s, LAW_T f_n, LAW_T f_el, double dt, LAW_T *xi_t)
{
    const unsigned law = key & KEY_TANGENTIAL;
    if (law == SIM_TANGENTIAL_REGULARISED)
        return LAW(copysign)(LAW(min)(damping * LAW(abs)(v_s), mu * LAW(abs)(f_n)), v_s);
    if (law == SIM_TANGENTIAL_SPRING) {
        LAW_T stretch = *xi_t + v_s * dt;
        LAW_T spring = k_t * stretch;
        LAW_T f = LAW(sel)(damping != 0.0, spring + damping * v_s, spring);
        LAW_T cap = mu * f_el;
        LAW_T capped = LAW(copysign)(LAW(min)(LAW(abs)(f), cap), f);
        LAW_T kept = LAW(sel)(damping != 0.0, capped - damping * v_s, capped);
        *xi_t = LAW(sel)(capped != f, kept / k_t, stretch); /* slip: spring kept at the cap */
        return capped;
    }
    (void)v_s;
    return LAW_ZERO;
}

/* Rolling torque M (004 eqs. 4.1-4.2): M <- M - k_r (omega_j - omega_i) dt, |M| <= mu_r f_el.
 * Chord law: k_r = k_n l_c^2, mu_r = mu l_c (the caller passes them so). */
KERNEL LAW_T LAW(rolling_torque)(LAW_T k_r, LAW_T mu_r, LAW_T relative_spin, LAW_T f_el, double dt,
                                 LAW_T *m_r)
{
    LAW_T m = *m_r - k_r * relative_spin * dt;
    LAW_T cap = mu_r * f_el;
    m = LAW(sel)(LAW(abs)(m) > cap, LAW(copysign)(cap, m), m);
    *m_r = m;
    return m;
}

/* Common chord of two overlapping disks at centre distance d (004 §1.7); 0 when apart. */
KERNEL LAW_T LAW(disk_chord)(LAW_T d, LAW_T ri, LAW_T rj)
{
    LAW_T a = (d * d - (ri - rj) * (ri - rj)) * ((ri + rj) * (ri + rj) - d * d);
    LAW_T positive = LAW(sel)(a > 0.0, a, LAW_ONE); /* no sqrt of a negative in any lane */
    return LAW(sel)(a > 0.0, LAW(sqrt)(positive) / d, LAW_ZERO);
}
