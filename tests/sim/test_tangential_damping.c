/* SPDX-License-Identifier: MIT */
/* The spring law's tangential dashpot (sim/contact_laws.h, Luding 2008): a sticking contact is a
 * damped oscillator m x'' = -k_t x - gamma_t x', whose peaks decay by exp(-gamma_t T_d / 2m) per
 * damped period T_d = 2 pi / sqrt(k_t/m - (gamma_t/2m)^2); a sliding one stays on the Coulomb
 * cap with the spring kept at (cap - gamma_t v_s) / k_t; gamma_t = 0 is the undamped spring. */
#include "test.h"

#include "sim/contact_scalar.h"

#define MASS 0.01 /* kg */
#define K_T  1e4  /* N/m */

/* The logarithmic decrement of the tangential spring's peaks over `periods` damped periods, one
 * degree of freedom stepped by the law itself (symplectic Euler, dt = T_d / 4000). */
static double decrement(double gamma_t, int periods)
{
    const double rate = gamma_t / (2.0 * MASS);
    const double omega = sqrt(K_T / MASS - rate * rate), period = 2.0 * SIM_PI / omega;
    const double dt = period / 4000.0;
    double xi = 1e-4, v = 0.0, first = 0.0, last = 0.0, previous = 0.0, before = 0.0;
    int peaks = 0;
    for (long n = 0; n < 4000L * (periods + 1) && peaks <= periods; ++n) {
        /* no slip: mu F_el far above any spring force */
        const double f =
            tangential_force_d(SIM_TANGENTIAL_SPRING, K_T, 1.0, gamma_t, v, 1e9, 1e9, dt, &xi);
        v -= f / MASS * dt;
        if (previous > before && previous >= xi) { /* a maximum of xi at the last step */
            if (peaks == 0)
                first = previous;
            last = previous;
            ++peaks;
        }
        before = previous;
        previous = xi;
    }
    return peaks == periods + 1 ? log(first / last) / periods : (double)NAN;
}

static int sticking_decay_rate(void)
{
    const double gamma_t = 2.0; /* kg/s: damping ratio gamma_t / (2 sqrt(k_t m)) = 0.1 */
    const double rate = gamma_t / (2.0 * MASS);
    const double period = 2.0 * SIM_PI / sqrt(K_T / MASS - rate * rate);
    TEST_REL(decrement(gamma_t, 3), rate * period, 0.01);
    TEST_NEAR(decrement(0.0, 3), 0.0, 1e-3); /* undamped: no decay */
    return 0;
}

/* Sliding: |F_t| = mu F_el exactly, the spring kept so that k_t xi + gamma_t v_s is the cap. */
static int sliding_stays_on_cap(void)
{
    const double gamma_t = 3.0, v_s = 0.5, mu = 0.4, f_el = 10.0, dt = 1e-5;
    double xi = 3e-4;
    const double f =
        tangential_force_d(SIM_TANGENTIAL_SPRING, K_T, mu, gamma_t, v_s, f_el, f_el, dt, &xi);
    TEST_NEAR(f, mu * f_el, 0.0);
    TEST_NEAR(xi, (mu * f_el - gamma_t * v_s) / K_T, 1e-18);
    /* below the cap: the trial force, spring plus dashpot */
    xi = 1e-5;
    const double g =
        tangential_force_d(SIM_TANGENTIAL_SPRING, K_T, mu, gamma_t, 0.1, f_el, f_el, dt, &xi);
    TEST_NEAR(g, K_T * (1e-5 + 0.1 * dt) + gamma_t * 0.1, 1e-15);
    return 0;
}

/* gamma_t = 0: the undamped spring's bits, sticking and sliding. */
static int zero_damping_same_bits(void)
{
    const double dt = 1e-5, mu = 0.4, f_el = 10.0;
    const double stretches[] = {1e-5, -2e-5, 3e-4, -5e-4, 0.0};
    for (int k = 0; k < 5; ++k) {
        double xi = stretches[k], v_s = 0.3 * (k - 2);
        const double stretch = xi + v_s * dt, spring = K_T * stretch;
        const double capped = copysign(fmin(fabs(spring), mu * f_el), spring);
        const double f =
            tangential_force_d(SIM_TANGENTIAL_SPRING, K_T, mu, 0.0, v_s, f_el, f_el, dt, &xi);
        TEST_ASSERT(memcmp(&f, &capped, sizeof f) == 0);
        const double kept = capped != spring ? capped / K_T : stretch;
        TEST_ASSERT(memcmp(&xi, &kept, sizeof xi) == 0);
    }
    return 0;
}

TEST_MAIN(TEST_CASE(sticking_decay_rate), TEST_CASE(sliding_stays_on_cap),
          TEST_CASE(zero_damping_same_bits))
