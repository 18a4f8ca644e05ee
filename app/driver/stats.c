/* SPDX-License-Identifier: MIT */
/* stats.c: sample statistics, Student-t quantiles and Welch's interval (stats.h). */
#include "driver/stats.h"

#include <math.h>

/* The continued fraction of the regularised incomplete beta function I_x(a, b), evaluated by
 * the modified Lentz method; it converges fast for x < (a + 1) / (a + b + 2). */
static double beta_fraction(double a, double b, double x)
{
    const double tiny = 1e-300;
    double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
    d = 1.0 / (fabs(d) < tiny ? tiny : d);
    double h = d;
    for (int m = 1; m <= 400; ++m) {
        double m2 = 2.0 * m;
        /* even step: d_{2m} = m (b - m) x / ((a + 2m - 1) (a + 2m)) */
        double e = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
        d = 1.0 + e * d;
        c = 1.0 + e / c;
        d = 1.0 / (fabs(d) < tiny ? tiny : d);
        c = fabs(c) < tiny ? tiny : c;
        h *= d * c;
        /* odd step: d_{2m+1} = -(a + m) (a + b + m) x / ((a + 2m) (a + 2m + 1)) */
        double o = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
        d = 1.0 + o * d;
        c = 1.0 + o / c;
        d = 1.0 / (fabs(d) < tiny ? tiny : d);
        c = fabs(c) < tiny ? tiny : c;
        double delta = d * c;
        h *= delta;
        if (fabs(delta - 1.0) < 1e-16)
            break;
    }
    return h;
}

/* I_x(a, b), a, b > 0, x in [0, 1]. */
static double incomplete_beta(double a, double b, double x)
{
    if (!(x > 0.0))
        return 0.0;
    if (!(x < 1.0))
        return 1.0;
    double front = exp(lgamma(a + b) - lgamma(a) - lgamma(b) + a * log(x) + b * log1p(-x));
    if (x < (a + 1.0) / (a + b + 2.0))
        return front * beta_fraction(a, b, x) / a;
    return 1.0 - front * beta_fraction(b, a, 1.0 - x) / b;
}

double app_t_cdf(double t, double dof)
{
    if (!(dof > 0.0) || isnan(t))
        return NAN;
    if (isinf(t))
        return t > 0.0 ? 1.0 : 0.0;
    /* P(T > |t|) = I_{dof / (dof + t^2)}(dof / 2, 1 / 2) / 2 */
    double tail = 0.5 * incomplete_beta(0.5 * dof, 0.5, dof / (dof + t * t));
    return t >= 0.0 ? 1.0 - tail : tail;
}

double app_t_quantile(double p, double dof)
{
    if (!(dof > 0.0) || !(p > 0.0 && p < 1.0))
        return NAN;
    if (p == 0.5)
        return 0.0;
    double tail = p > 0.5 ? 1.0 - p : p; /* the quantile of 1 - tail, then its sign */
    double lo = 0.0, hi = 1.0;
    while (0.5 * incomplete_beta(0.5 * dof, 0.5, dof / (dof + hi * hi)) > tail && hi < 1e300)
        hi *= 2.0;
    for (int k = 0; k < 2000 && hi - lo > 1e-15 * hi; ++k) {
        double mid = 0.5 * (lo + hi);
        if (0.5 * incomplete_beta(0.5 * dof, 0.5, dof / (dof + mid * mid)) > tail)
            lo = mid;
        else
            hi = mid;
    }
    double t = 0.5 * (lo + hi);
    return p > 0.5 ? t : -t;
}

AppSample app_sample_stats(const double *x, int count, double level)
{
    AppSample s = {.n = 0, .mean = NAN, .std = NAN, .half = NAN};
    double sum = 0.0;
    for (int k = 0; k < count; ++k)
        if (isfinite(x[k])) {
            sum += x[k];
            ++s.n;
        }
    if (s.n == 0)
        return s;
    s.mean = sum / s.n;
    if (s.n < 2)
        return s;
    double squares = 0.0; /* two passes: no cancellation in the variance */
    for (int k = 0; k < count; ++k)
        if (isfinite(x[k]))
            squares += (x[k] - s.mean) * (x[k] - s.mean);
    s.std = sqrt(squares / (s.n - 1));
    s.half = app_t_quantile(0.5 + 0.5 * level, s.n - 1) * s.std / sqrt((double)s.n);
    return s;
}

AppShift app_welch_shift(const AppSample *sample, const AppSample *reference, double level)
{
    AppShift r = {
        .shift = sample->mean - reference->mean, .half = NAN, .dof = NAN, .significant = -1};
    if (sample->n < 2 || reference->n < 2 || isnan(r.shift))
        return r;
    double va = sample->std * sample->std / sample->n;
    double vb = reference->std * reference->std / reference->n;
    double se2 = va + vb;
    if (!(se2 > 0.0)) { /* both samples constant: any difference is beyond their error */
        r.half = 0.0;
        r.dof = sample->n + reference->n - 2;
    } else {
        r.dof = se2 * se2 / (va * va / (sample->n - 1) + vb * vb / (reference->n - 1));
        r.half = app_t_quantile(0.5 + 0.5 * level, r.dof) * sqrt(se2);
    }
    r.significant = fabs(r.shift) > r.half;
    return r;
}

int app_shift_within_until(const AppShift *shifts, int count)
{
    int k = 0;
    while (k + 1 < count && shifts[k + 1].significant == 0)
        ++k;
    return k;
}

int app_linear_fit(const double *x, const double *y, int n, double *a, double *b, double *a_err)
{
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    int m = 0;
    for (int k = 0; k < n; ++k) {
        if (!isfinite(y[k]))
            continue;
        sx += x[k];
        sy += y[k];
        sxx += x[k] * x[k];
        sxy += x[k] * y[k];
        ++m;
    }
    const double det = m * sxx - sx * sx;
    *a = NAN;
    if (m >= 1)
        *a = sy / m;
    *b = NAN;
    if (a_err)
        *a_err = 0.0;
    if (m < 2 || !(fabs(det) > 0.0))
        return -1;
    *b = (m * sxy - sx * sy) / det;
    *a = (sy - *b * sx) / m;
    if (m >= 3 && a_err) {
        double rss = 0.0;
        for (int k = 0; k < n; ++k) {
            if (!isfinite(y[k]))
                continue;
            const double r = y[k] - *a - *b * x[k];
            rss += r * r;
        }
        *a_err = sqrt(rss / (m - 2) * sxx / det);
    }
    return 0;
}
