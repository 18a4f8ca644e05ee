/* SPDX-License-Identifier: MIT */
/* stats.h: the statistics of an ensemble of runs (`sablier ensemble`, docs/accuracy.md): sample
 * mean, standard deviation and Student-t confidence interval, the shift of one mean against a
 * reference mean with Welch's interval, and where a list of such shifts stops being significant.
 * App core: plain numbers, no files. */
#ifndef APP_STATS_H
#define APP_STATS_H

/// One sample's statistics. n < 2: std and half are NaN.
typedef struct AppSample {
    int n;       ///< finite values counted
    double mean; ///< NaN when n = 0
    double std;  ///< sample standard deviation (n - 1 in the denominator)
    double half; ///< half-width of the two-sided confidence interval of the mean (Student t)
} AppSample;

/// A mean's shift against a reference mean (mean - reference) and its interval (Welch).
typedef struct AppShift {
    double shift;    ///< NaN when either mean is
    double half;     ///< half-width of the interval of the difference; 0 when both stds are 0
    double dof;      ///< Welch-Satterthwaite degrees of freedom
    int significant; ///< 1: |shift| > half; 0: within; -1: unknown (a sample of fewer than 2)
} AppShift;

/// The p-quantile of Student's t distribution with `dof` > 0 degrees of freedom (not necessarily
/// an integer), p in (0, 1); NaN outside. Bisection on the distribution function (regularised
/// incomplete beta), to double precision.
double app_t_quantile(double p, double dof);

/// P(T <= t) for Student's t with `dof` > 0 degrees of freedom.
double app_t_cdf(double t, double dof);

/// Statistics of the finite values of x[0 .. count-1] (non-finite ones are left out) with the
/// two-sided interval of confidence `level` (0.95: 95 %).
AppSample app_sample_stats(const double *x, int count, double level);

/// The shift of `sample`'s mean against `reference`'s, with Welch's interval at `level`.
AppShift app_welch_shift(const AppSample *sample, const AppSample *reference, double level);

/// Rows 0 .. count-1 ordered from the reference outwards (row 0: the reference itself): the last
/// row k such that rows 1 .. k are all within their interval (not significant and known). 0 when
/// row 1 already moves (or count < 2).
int app_shift_within_until(const AppShift *shifts, int count);

/// The least-squares line y = a + b x through the points of x[0 .. n-1] whose y is finite (the
/// others are left out): 0, or -1 with fewer than two such points or all at one x (b is then NaN
/// and a the mean of the finite y, NaN when there is none). a_err: the standard error of the
/// intercept, sqrt(s^2 sum x^2 / det) with s^2 the residual variance (0 with fewer than three
/// points); NULL when not wanted.
int app_linear_fit(const double *x, const double *y, int n, double *a, double *b, double *a_err);

#endif
