/* SPDX-License-Identifier: MIT */
/* test_stats.c: the ensemble statistics (app/driver/stats.h): Student-t quantiles against tabulated
 * values, a sample's mean, standard deviation and interval, Welch's interval, its coverage and
 * false-alarm rate over many synthetic ensembles, and a synthetic dt list whose known shift is
 * found where it is and nowhere else. */
#include "test.h"

#include "driver/stats.h"

#include <stdint.h>

/* Deterministic standard normal draws: xorshift64* and Box-Muller. */
typedef struct Normal {
    uint64_t state;
    int have;
    double spare;
} Normal;

static double uniform(Normal *g)
{
    g->state ^= g->state >> 12;
    g->state ^= g->state << 25;
    g->state ^= g->state >> 27;
    uint64_t r = g->state * 2685821657736338717ull;
    return ((double)(r >> 11) + 0.5) / 9007199254740992.0; /* (0, 1) */
}

static double normal(Normal *g)
{
    if (g->have) {
        g->have = 0;
        return g->spare;
    }
    double u = uniform(g), v = uniform(g);
    double r = sqrt(-2.0 * log(u)), a = 6.283185307179586 * v;
    g->spare = r * sin(a);
    g->have = 1;
    return r * cos(a);
}

static void draw(Normal *g, double *x, int n, double mean, double sigma)
{
    for (int k = 0; k < n; ++k)
        x[k] = mean + sigma * normal(g);
}

/* Tabulated two-sided 95 % quantiles t(0.975, dof) (10 digits) and the closed forms for 1 and 2
 * degrees of freedom (to double precision). */
static int stats_t_quantile_table(void)
{
    static const double dof[] = {4, 5, 10, 18, 30};
    static const double t[] = {2.776445105, 2.570581836, 2.228138852, 2.100922040, 2.042272456};
    for (int k = 0; k < 5; ++k) {
        TEST_REL(app_t_quantile(0.975, dof[k]), t[k], 1e-8);
        TEST_REL(app_t_quantile(0.025, dof[k]), -t[k], 1e-8);
        TEST_NEAR(app_t_cdf(app_t_quantile(0.975, dof[k]), dof[k]), 0.975, 1e-13);
    }
    for (int k = 1; k <= 9; ++k) {
        double p = 0.5 + 0.05 * k; /* dof 1: tan(pi (p - 1/2)); dof 2: (2p - 1) / sqrt(2p(1-p)) */
        TEST_REL(app_t_quantile(p, 1.0), tan(3.141592653589793 * (p - 0.5)), 1e-12);
        TEST_REL(app_t_quantile(p, 2.0), (2.0 * p - 1.0) / sqrt(2.0 * p * (1.0 - p)), 1e-12);
    }
    TEST_REL(app_t_quantile(0.995, 3.0), 5.840909310, 1e-8);
    TEST_NEAR(app_t_quantile(0.5, 7.0), 0.0, 0.0);
    /* a Welch dof need not be an integer: between its neighbours */
    double q = app_t_quantile(0.975, 7.5);
    TEST_ASSERT(q < app_t_quantile(0.975, 7.0) && q > app_t_quantile(0.975, 8.0));
    TEST_ASSERT(isnan(app_t_quantile(1.0, 3.0)) && isnan(app_t_quantile(0.9, 0.0)));
    return 0;
}

static int stats_sample_and_welch(void)
{
    const double x[] = {1.0, 2.0, NAN, 3.0, 4.0, 5.0}; /* the NaN is left out */
    AppSample s = app_sample_stats(x, 6, 0.95);
    TEST_ASSERT(s.n == 5);
    TEST_NEAR(s.mean, 3.0, 1e-15);
    TEST_NEAR(s.std, sqrt(2.5), 1e-15);
    TEST_REL(s.half, app_t_quantile(0.975, 4.0) * sqrt(2.5) / sqrt(5.0), 1e-15);
    AppSample one = app_sample_stats(x, 1, 0.95);
    TEST_ASSERT(one.n == 1 && one.mean == 1.0 && isnan(one.std) && isnan(one.half));
    /* equal sizes and stds: dof = 2 (n - 1), half = t sqrt(2 s^2 / n) */
    AppSample a = {.n = 10, .mean = 1.0, .std = 1.0}, b = {.n = 10, .mean = 0.0, .std = 1.0};
    AppShift d = app_welch_shift(&a, &b, 0.95);
    TEST_NEAR(d.shift, 1.0, 0.0);
    TEST_NEAR(d.dof, 18.0, 1e-12);
    TEST_REL(d.half, app_t_quantile(0.975, 18.0) * sqrt(0.2), 1e-12);
    TEST_ASSERT(d.significant == 1);
    /* one constant sample: the other's dof alone */
    AppSample c = {.n = 6, .mean = 0.5, .std = 0.0};
    d = app_welch_shift(&c, &b, 0.95);
    TEST_NEAR(d.dof, 9.0, 1e-12);
    TEST_ASSERT(d.significant == 0);
    /* both constant: any difference is beyond their error, none is within */
    AppSample e = {.n = 4, .mean = 2.0, .std = 0.0}, f = {.n = 4, .mean = 2.0, .std = 0.0};
    TEST_ASSERT(app_welch_shift(&e, &c, 0.95).significant == 1);
    TEST_ASSERT(app_welch_shift(&e, &f, 0.95).significant == 0);
    TEST_ASSERT(app_welch_shift(&one, &b, 0.95).significant == -1);
    return 0;
}

/* Over 4000 synthetic pairs of ensembles (n = 12 and 20, unequal sigmas), the 95 % interval of
 * the difference covers the true shift about 95 % of the time, and with no shift about 5 % are
 * flagged; a shift of 1.5 sigma is found nearly always. */
static int stats_welch_coverage(void)
{
    Normal g = {.state = 0x9e3779b97f4a7c15ull};
    double x[20], y[20];
    const int R = 4000;
    int covered = 0, false_alarm = 0, found = 0;
    for (int r = 0; r < R; ++r) {
        draw(&g, x, 12, 0.7, 2.0);
        draw(&g, y, 20, 0.0, 1.0);
        AppSample a = app_sample_stats(x, 12, 0.95), b = app_sample_stats(y, 20, 0.95);
        AppShift d = app_welch_shift(&a, &b, 0.95);
        covered += fabs(d.shift - 0.7) <= d.half;
        draw(&g, x, 12, 0.0, 2.0);
        a = app_sample_stats(x, 12, 0.95);
        false_alarm += app_welch_shift(&a, &b, 0.95).significant == 1;
        draw(&g, x, 20, 1.5, 1.0);
        a = app_sample_stats(x, 20, 0.95);
        found += app_welch_shift(&a, &b, 0.95).significant == 1;
    }
    double coverage = (double)covered / R, alarms = (double)false_alarm / R;
    fprintf(stderr, "coverage %.4f, false alarms %.4f, found %.4f\n", coverage, alarms,
            (double)found / R);
    TEST_NEAR(coverage, 0.95, 0.015); /* binomial sd 0.0034 */
    TEST_NEAR(alarms, 0.05, 0.015);
    TEST_ASSERT(found > 0.98 * R);
    return 0;
}

/* A synthetic dt list, finest first: samples of exactly mean 0 at the reference and the next
 * three dts, and of mean delta = 2 sigma at the coarsest (normal draws re-centred, so the means
 * are known exactly). The shift delta is found, within its interval; the others are not shifts;
 * the mean stays within its error up to row 3. */
static int stats_known_shift_over_dt(void)
{
    enum { LEVELS = 5, N = 30 };

    const double delta = 2.0, target[LEVELS] = {0.0, 0.0, 0.0, 0.0, delta};
    Normal g = {.state = 12345};
    AppSample s[LEVELS];
    AppShift d[LEVELS];
    for (int v = 0; v < LEVELS; ++v) {
        double x[N], mean = 0.0;
        draw(&g, x, N, 0.0, 1.0);
        for (int k = 0; k < N; ++k)
            mean += x[k] / N;
        for (int k = 0; k < N; ++k)
            x[k] += target[v] - mean;
        s[v] = app_sample_stats(x, N, 0.95);
        d[v] = app_welch_shift(&s[v], &s[0], 0.95);
    }
    for (int v = 1; v < LEVELS; ++v) {
        TEST_NEAR(d[v].shift, target[v], 1e-12);
        TEST_ASSERT(d[v].half > 0.3 && d[v].half < 0.8); /* about 2 sqrt(2 / 30) */
        TEST_ASSERT(d[v].significant == (target[v] != 0.0));
    }
    TEST_ASSERT(app_shift_within_until(d, LEVELS) == 3);
    d[2].significant = -1; /* an unknown row ends the run of rows within */
    TEST_ASSERT(app_shift_within_until(d, LEVELS) == 1);
    d[1].significant = 1;
    TEST_ASSERT(app_shift_within_until(d, LEVELS) == 0);
    TEST_ASSERT(app_shift_within_until(d, 1) == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(stats_t_quantile_table), TEST_CASE(stats_sample_and_welch),
          TEST_CASE(stats_welch_coverage), TEST_CASE(stats_known_shift_over_dt))
