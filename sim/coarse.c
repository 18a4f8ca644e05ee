/* SPDX-License-Identifier: MIT */
/* coarse.c: kernel coarse-graining of a frame into continuum fields (Goldhirsch 2010; Weinhart et
 * al. 2012, Granular Matter 14: 289, "WTLS12" below) and flux counters through a segment.
 *
 * Every field is a sum over points of a value times a kernel weight at the nodes:
 *   - grains at their centres: m (rho, eq. 3 of WTLS12), pi r^2 (phi), m v (j, eq. 4), m v v
 *     (the kinetic stress through sum m v'v' W = sum m v v W - j j / rho, exact because V = j /
 *     rho at the same node; WTLS12 eq. 11 with v' = v - V(r)), 1 (number density), the grain's
 *     contact count and its sum of n n (coordination and fabric);
 *   - contacts along their branch: f_i (x) (r_i - r_j) spread over the segment from r_i to r_j
 *     with the line integral int_0^1 W(r - r_i + s r_ij) ds (WTLS12 eq. 12; Goldhirsch 2010
 *     eq. 40), and for a wall contact f_i (x) (r_i - c) over the segment to the contact point c
 *     (WTLS12 eq. 14). The line integral is taken by 3-point Gauss-Legendre on sub-segments no
 *     longer than half the kernel width (exact for quintic polynomials; the Lucy kernel
 *     is C2 and the error is below 1e-4 of the field for the widths the app accepts).
 * With `normalise`, a point's weights are divided by their sum over the whole node lattice times
 * the cell area, so each point deposits exactly its value: the fields integrate to the grains'
 * totals and the contact stress to the virial sum over contacts, to rounding (tests/sim). */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Sums kept per node. */
enum {
    CH_RHO,
    CH_PHI,
    CH_JX,
    CH_JY,
    CH_MXX,
    CH_MXY,
    CH_MYY,
    CH_N,
    CH_Z,
    CH_FXX,
    CH_FXY,
    CH_FYY,
    CH_CXX,
    CH_CXY,
    CH_CYX,
    CH_CYY,
    CH_COUNT
};

struct SimCoarse {
    SimCoarseDef def;
    int nodes;
    int samples;
    double *sums;    /* nodes * CH_COUNT */
    double *weights; /* scratch of one point's weights over its support box */
    int weights_capacity;
    double *grain_z; /* per grain: contacts, then fabric xx, xy, yy (4 per grain) */
    int grain_capacity;
};

double sim_kernel(SimKernel kernel, double r, double c)
{
    if (!(c > 0.0) || !(r < c))
        return 0.0;
    if (kernel == SIM_KERNEL_GAUSSIAN) {
        /* sigma = c / 3, cut at 3 sigma and renormalised for the cut tail (1 - e^-4.5) */
        double sigma = c / 3.0;
        double norm = 2 * SIM_PI * sigma * sigma * (1.0 - exp(-4.5));
        return exp(-0.5 * (r * r) / (sigma * sigma)) / norm;
    }
    return sim_kernel_lucy(r, c);
}

double sim_kernel_1d(SimKernel kernel, double y, double c)
{
    if (!(c > 0.0) || !(fabs(y) < c))
        return 0.0;
    double y2 = y * y, a = sqrt(c * c - y2); /* the chord at height y spans [-a, a] */
    if (kernel == SIM_KERNEL_GAUSSIAN) {
        double sigma = c / 3.0;
        double norm = 2 * SIM_PI * sigma * sigma * (1.0 - exp(-4.5));
        return exp(-0.5 * y2 / (sigma * sigma)) * sqrt(2.0 * SIM_PI) * sigma *
               erf(a / (sqrt(2.0) * sigma)) / norm;
    }
    /* Lucy: W = 5/(pi c^2) (1 - 6 s^2 + 8 s^3 - 3 s^4), s = r / c; integrals of r^k over the
     * chord (r^3: int R^3 dx = x (2x^2 + 5y^2) R / 8 + 3 y^4 / 8 ln(x + R), R(a) = c). */
    double i0 = 2.0 * a;
    double i2 = 2.0 * (a * a * a / 3.0 + y2 * a);
    double a3 = a * a * a;
    double i4 = 2.0 * (a3 * a * a / 5.0 + 2.0 * y2 * a3 / 3.0 + y2 * y2 * a);
    double i3 = 2.0 * (a * (2.0 * a * a + 5.0 * y2) * c / 8.0);
    if (y2 > 0.0)
        i3 += 2.0 * (3.0 * y2 * y2 / 8.0) * log((a + c) / fabs(y));
    double c2 = c * c;
    return 5.0 / (SIM_PI * c2) * (i0 - 6.0 * i2 / c2 + 8.0 * i3 / (c2 * c) - 3.0 * i4 / (c2 * c2));
}

/* ---------------------------------------------------------------- names */

static const struct {
    const char *name, *unit;
    int contacts;
} field_info[SIM_CG_FIELD_COUNT] = {
    [SIM_CG_PHI] = {"phi", "1", 0},      [SIM_CG_RHO] = {"rho", "kg/m^2", 0},
    [SIM_CG_JX] = {"jx", "kg/(m s)", 0}, [SIM_CG_JY] = {"jy", "kg/(m s)", 0},
    [SIM_CG_VX] = {"vx", "m/s", 0},      [SIM_CG_VY] = {"vy", "m/s", 0},
    [SIM_CG_T] = {"T", "m^2/s^2", 0},    [SIM_CG_KXX] = {"kxx", "N/m", 0},
    [SIM_CG_KXY] = {"kxy", "N/m", 0},    [SIM_CG_KYY] = {"kyy", "N/m", 0},
    [SIM_CG_CXX] = {"cxx", "N/m", 1},    [SIM_CG_CXY] = {"cxy", "N/m", 1},
    [SIM_CG_CYX] = {"cyx", "N/m", 1},    [SIM_CG_CYY] = {"cyy", "N/m", 1},
    [SIM_CG_SXX] = {"sxx", "N/m", 1},    [SIM_CG_SXY] = {"sxy", "N/m", 1},
    [SIM_CG_SYX] = {"syx", "N/m", 1},    [SIM_CG_SYY] = {"syy", "N/m", 1},
    [SIM_CG_P] = {"p", "N/m", 1},        [SIM_CG_Z] = {"z", "1", 1},
    [SIM_CG_FXX] = {"fxx", "1", 1},      [SIM_CG_FXY] = {"fxy", "1", 1},
    [SIM_CG_FYY] = {"fyy", "1", 1},
};

int sim_coarse_field_from_name(const char *name)
{
    for (int k = 0; k < SIM_CG_FIELD_COUNT; ++k)
        if (strcmp(name, field_info[k].name) == 0)
            return k;
    return -1;
}

const char *sim_coarse_field_name(SimCoarseField field)
{
    return (int)field >= 0 && field < SIM_CG_FIELD_COUNT ? field_info[field].name : "unknown";
}

const char *sim_coarse_field_unit(SimCoarseField field)
{
    return (int)field >= 0 && field < SIM_CG_FIELD_COUNT ? field_info[field].unit : "";
}

int sim_coarse_field_needs_contacts(SimCoarseField field)
{
    return (int)field >= 0 && field < SIM_CG_FIELD_COUNT && field_info[field].contacts;
}

/* ---------------------------------------------------------------- set-up */

SimCoarseDef sim_coarse_def_default(void)
{
    return (SimCoarseDef){.kernel = SIM_KERNEL_LUCY, .nx = 1, .ny = 1, .normalise = 1};
}

static SimCoarse *coarse_fail(SimError *error, SimStatus status, const char *message)
{
    if (error) {
        memset(error, 0, sizeof *error);
        error->status = status;
        error->step = error->grain = -1;
        snprintf(error->field, sizeof error->field, "coarse");
        snprintf(error->message, sizeof error->message, "%s", message);
    }
    return NULL;
}

SimCoarse *sim_coarse_create(const SimCoarseDef *def, SimError *error)
{
    SimCoarseDef d = *def;
    int along_x = d.geometry != SIM_COARSE_PROFILE_Y, along_y = d.geometry != SIM_COARSE_PROFILE_X;
    if (!along_x)
        d.nx = 1;
    if (!along_y)
        d.ny = 1;
    double span = 0.0; /* support box of a point, in cells */
    if (!(d.width > 0.0) || !isfinite(d.width))
        return coarse_fail(error, SIM_ERROR_INVALID, "the kernel width must be > 0");
    if (d.nx < 1 || d.ny < 1 || (along_x && !(d.cell_x > 0.0)) || (along_y && !(d.cell_y > 0.0)))
        return coarse_fail(error, SIM_ERROR_INVALID, "no nodes");
    if ((double)d.nx * (double)d.ny > SIM_COARSE_MAX_NODES)
        return coarse_fail(error, SIM_ERROR_INVALID, "too many nodes");
    if (d.geometry == SIM_COARSE_PROFILE_Y && !(d.x1 > d.x0))
        return coarse_fail(error, SIM_ERROR_INVALID, "empty averaging strip");
    if (d.geometry == SIM_COARSE_PROFILE_X && !(d.y1 > d.y0))
        return coarse_fail(error, SIM_ERROR_INVALID, "empty averaging strip");
    double bx = along_x ? 2.0 * d.width / d.cell_x + 3.0 : 1.0;
    double by = along_y ? 2.0 * d.width / d.cell_y + 3.0 : 1.0;
    span = bx * by;
    if (d.normalise && ((along_x && d.width < d.cell_x) || (along_y && d.width < d.cell_y)))
        return coarse_fail(error, SIM_ERROR_INVALID,
                           "the kernel width must be at least the cell side");
    if (span > 4e6)
        return coarse_fail(error, SIM_ERROR_INVALID, "the kernel is too wide for the cells");
    SimCoarse *cg = calloc(1, sizeof *cg);
    if (!cg)
        return coarse_fail(error, SIM_ERROR_MEMORY, "out of memory");
    cg->def = d;
    cg->nodes = d.nx * d.ny;
    cg->weights_capacity = (int)span;
    cg->sums = calloc((size_t)cg->nodes * CH_COUNT, sizeof *cg->sums);
    cg->weights = malloc((size_t)cg->weights_capacity * sizeof *cg->weights);
    if (!cg->sums || !cg->weights) {
        sim_coarse_destroy(cg);
        return coarse_fail(error, SIM_ERROR_MEMORY, "out of memory");
    }
    return cg;
}

void sim_coarse_destroy(SimCoarse *cg)
{
    if (!cg)
        return;
    free(cg->sums);
    free(cg->weights);
    free(cg->grain_z);
    free(cg);
}

int sim_coarse_nodes(const SimCoarse *cg)
{
    return cg->nodes;
}

void sim_coarse_node(const SimCoarse *cg, int k, double *x, double *y)
{
    const SimCoarseDef *d = &cg->def;
    int i = k % d->nx, j = k / d->nx;
    *x =
        d->geometry == SIM_COARSE_PROFILE_Y ? 0.5 * (d->x0 + d->x1) : d->x0 + (i + 0.5) * d->cell_x;
    *y =
        d->geometry == SIM_COARSE_PROFILE_X ? 0.5 * (d->y0 + d->y1) : d->y0 + (j + 0.5) * d->cell_y;
}

int sim_coarse_samples(const SimCoarse *cg)
{
    return cg->samples;
}

void sim_coarse_clear(SimCoarse *cg)
{
    memset(cg->sums, 0, (size_t)cg->nodes * CH_COUNT * sizeof *cg->sums);
    cg->samples = 0;
}

long sim_coarse_sum_count(const SimCoarse *cg)
{
    return (long)cg->nodes * CH_COUNT;
}

void sim_coarse_get_sums(const SimCoarse *cg, double *sums)
{
    memcpy(sums, cg->sums, (size_t)cg->nodes * CH_COUNT * sizeof *sums);
}

void sim_coarse_set_sums(SimCoarse *cg, const double *sums, int samples)
{
    memcpy(cg->sums, sums, (size_t)cg->nodes * CH_COUNT * sizeof *sums);
    cg->samples = samples;
}

/* ---------------------------------------------------------------- deposits */

/* Adds weight * v[q] to channels off + q of node n. */
static inline void add_node(SimCoarse *cg, int n, double weight, const double *v, int nv, int off)
{
    double *s = cg->sums + (size_t)n * CH_COUNT + off;
    for (int q = 0; q < nv; ++q)
        s[q] += weight * v[q];
}

/* One point on the grid: nodes of its support box (render's loop order when not normalising). */
static void deposit_grid(SimCoarse *cg, double x, double y, const double *v, int nv, int off)
{
    const SimCoarseDef *d = &cg->def;
    double w = d->width;
    int i0 = (int)ceil((x - w - d->x0) / d->cell_x - 0.5);
    int i1 = (int)floor((x + w - d->x0) / d->cell_x - 0.5);
    int j0 = (int)ceil((y - w - d->y0) / d->cell_y - 0.5);
    int j1 = (int)floor((y + w - d->y0) / d->cell_y - 0.5);
    if (i1 < 0 || j1 < 0 || i0 > d->nx - 1 || j0 > d->ny - 1)
        return; /* no node of the field in reach */
    if (!d->normalise) {
        i0 = i0 < 0 ? 0 : i0;
        j0 = j0 < 0 ? 0 : j0;
        i1 = i1 > d->nx - 1 ? d->nx - 1 : i1;
        j1 = j1 > d->ny - 1 ? d->ny - 1 : j1;
        for (int j = j0; j <= j1; ++j) {
            double dy = d->y0 + (j + 0.5) * d->cell_y - y;
            for (int i = i0; i <= i1; ++i) {
                double dx = d->x0 + (i + 0.5) * d->cell_x - x;
                double k = sim_kernel(d->kernel, sqrt(dx * dx + dy * dy), w);
                if (k != 0.0)
                    add_node(cg, j * d->nx + i, k, v, nv, off);
            }
        }
        return;
    }
    int bw = i1 - i0 + 1, m = 0;
    double sum = 0.0;
    for (int j = j0; j <= j1; ++j) {
        double dy = d->y0 + (j + 0.5) * d->cell_y - y;
        for (int i = i0; i <= i1; ++i, ++m) {
            double dx = d->x0 + (i + 0.5) * d->cell_x - x;
            cg->weights[m] = sim_kernel(d->kernel, sqrt(dx * dx + dy * dy), w);
            sum += cg->weights[m];
        }
    }
    if (!(sum > 0.0))
        return;
    double scale = 1.0 / (sum * d->cell_x * d->cell_y);
    for (int j = j0 < 0 ? 0 : j0; j <= j1 && j < d->ny; ++j)
        for (int i = i0 < 0 ? 0 : i0; i <= i1 && i < d->nx; ++i) {
            double k = cg->weights[(j - j0) * bw + (i - i0)];
            if (k != 0.0)
                add_node(cg, j * d->nx + i, k * scale, v, nv, off);
        }
}

/* One point on a profile: position u along it (p, the other coordinate, must lie in the strip);
 * the 2D kernel integrated across the strip (sim_kernel_1d), divided by the strip's width. */
static void deposit_profile(SimCoarse *cg, double u, double p, const double *v, int nv, int off)
{
    const SimCoarseDef *d = &cg->def;
    int along_y = d->geometry == SIM_COARSE_PROFILE_Y;
    double lo = along_y ? d->x0 : d->y0, hi = along_y ? d->x1 : d->y1;
    if (!(p >= lo && p <= hi))
        return;
    double u0 = along_y ? d->y0 : d->x0, h = along_y ? d->cell_y : d->cell_x, w = d->width;
    int n = along_y ? d->ny : d->nx;
    int k0 = (int)ceil((u - w - u0) / h - 0.5), k1 = (int)floor((u + w - u0) / h - 0.5);
    if (k1 < 0 || k0 > n - 1)
        return;
    double sum = 0.0;
    for (int k = k0; k <= k1; ++k) {
        cg->weights[k - k0] = sim_kernel_1d(d->kernel, u0 + (k + 0.5) * h - u, w);
        sum += cg->weights[k - k0];
    }
    double scale = 1.0 / (hi - lo);
    if (d->normalise) {
        if (!(sum > 0.0))
            return;
        scale /= sum * h;
    }
    for (int k = k0 < 0 ? 0 : k0; k <= k1 && k < n; ++k)
        if (cg->weights[k - k0] != 0.0)
            add_node(cg, k, cg->weights[k - k0] * scale, v, nv, off);
}

/* A point of the frame, with its periodic images (or wrapped into the period for a strip in x). */
static void deposit(SimCoarse *cg, const SimFrame *f, double x, double y, const double *v, int nv,
                    int off)
{
    const SimCoarseDef *d = &cg->def;
    double period = f->periodic ? f->domain_x1 - f->domain_x0 : 0.0;
    if (d->geometry == SIM_COARSE_PROFILE_Y) {
        if (period > 0.0)
            x = f->domain_x0 + (x - f->domain_x0) - period * floor((x - f->domain_x0) / period);
        deposit_profile(cg, y, x, v, nv, off);
        return;
    }
    for (int image = -1; image <= 1; ++image) {
        if (image != 0 && !(period > 0.0))
            continue;
        double xi = x + image * period;
        if (d->geometry == SIM_COARSE_GRID)
            deposit_grid(cg, xi, y, v, nv, off);
        else
            deposit_profile(cg, xi, y, v, nv, off);
    }
}

/* Unit normal from grain i to its partner of contact c (centre j with the periodic minimum
 * image, or the wall's contact point), and the branch r_i - r_end. */
static void contact_geometry(const SimFrame *f, const SimContact *c, double *nx, double *ny,
                             double *bx, double *by)
{
    int i = c->i;
    double dx, dy;
    if (c->j >= 0) {
        dx = f->x[c->j] - f->x[i];
        dy = f->y[c->j] - f->y[i];
        double period = f->periodic ? f->domain_x1 - f->domain_x0 : 0.0;
        if (period > 0.0)
            dx -= period * round(dx / period);
    } else {
        dx = c->x - f->x[i];
        dy = c->y - f->y[i];
    }
    double d = sqrt(dx * dx + dy * dy);
    *nx = d > 0.0 ? dx / d : 1.0;
    *ny = d > 0.0 ? dy / d : 0.0;
    *bx = -dx;
    *by = -dy;
}

static int is_fixed(const SimFrame *f, int i)
{
    return f->flags && (f->flags[i] & SIM_GRAIN_FIXED) != 0;
}

/* Per-grain contact counts and fabric sums (4 per grain). */
static SimStatus grain_contacts(SimCoarse *cg, const SimFrame *f)
{
    if (f->count > cg->grain_capacity) {
        double *p = realloc(cg->grain_z, (size_t)f->count * 4 * sizeof *p);
        if (!p)
            return SIM_ERROR_MEMORY;
        cg->grain_z = p;
        cg->grain_capacity = f->count;
    }
    memset(cg->grain_z, 0, (size_t)f->count * 4 * sizeof *cg->grain_z);
    for (int k = 0; k < f->contact_count; ++k) {
        const SimContact *c = &f->contacts[k];
        double nx, ny, bx, by;
        contact_geometry(f, c, &nx, &ny, &bx, &by);
        int ends[2] = {c->i, c->j};
        for (int e = 0; e < 2; ++e) {
            if (ends[e] < 0)
                continue;
            double *g = cg->grain_z + 4 * (size_t)ends[e];
            g[0] += 1.0;
            g[1] += nx * nx;
            g[2] += nx * ny;
            g[3] += ny * ny;
        }
    }
    return SIM_OK;
}

/* Contact stress of one contact along its branch: f_i (x) b with b = r_i - r_end, f_i =
 * -F_n n + F_t s (s = (n_y, -n_x)), over the points r_i - s b (WTLS12 eq. 12). */
static void deposit_contact(SimCoarse *cg, const SimFrame *f, const SimContact *c)
{
    static const double gauss_t[3] = {-0.77459666924148337704, 0.0, 0.77459666924148337704};
    static const double gauss_w[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0}; /* sum 1 */
    double nx, ny, bx, by;
    contact_geometry(f, c, &nx, &ny, &bx, &by);
    double fx = -c->normal_force * nx + c->tangential_force * ny;
    double fy = -c->normal_force * ny - c->tangential_force * nx;
    double tensor[4] = {fx * bx, fx * by, fy * bx, fy * by};
    double length = sqrt(bx * bx + by * by);
    int parts = (int)ceil(length / (0.5 * cg->def.width));
    parts = parts < 1 ? 1 : parts;
    double xi = f->x[c->i], yi = f->y[c->i];
    for (int p = 0; p < parts; ++p)
        for (int q = 0; q < 3; ++q) {
            double s = (p + 0.5 + 0.5 * gauss_t[q]) / parts, weight = gauss_w[q] / parts;
            double v[4] = {weight * tensor[0], weight * tensor[1], weight * tensor[2],
                           weight * tensor[3]};
            deposit(cg, f, xi - s * bx, yi - s * by, v, 4, CH_CXX);
        }
}

SimStatus sim_coarse_add(SimCoarse *cg, const SimFrame *f, const double *mass, double frame_vx,
                         double frame_vy)
{
    int contacts = cg->def.contacts;
    if (contacts && grain_contacts(cg, f) != SIM_OK)
        return SIM_ERROR_MEMORY;
    for (int i = 0; i < f->count; ++i) {
        if (is_fixed(f, i))
            continue;
        double r = f->radius[i];
        double m = mass ? mass[i] : SIM_PI * r * r;
        double vx = (f->vx ? f->vx[i] : 0.0) - frame_vx, vy = (f->vy ? f->vy[i] : 0.0) - frame_vy;
        double v[12] = {m,           SIM_PI * r * r, m * vx,      m * vy,
                        m * vx * vx, m * vx * vy,    m * vy * vy, 1.0};
        if (contacts)
            memcpy(v + CH_Z, cg->grain_z + 4 * (size_t)i, 4 * sizeof(double));
        deposit(cg, f, f->x[i], f->y[i], v, contacts ? 12 : 8, 0);
    }
    for (int k = 0; contacts && k < f->contact_count; ++k) {
        const SimContact *c = &f->contacts[k];
        if (is_fixed(f, c->i) && (c->j < 0 || is_fixed(f, c->j)))
            continue;
        deposit_contact(cg, f, c);
    }
    cg->samples++;
    return SIM_OK;
}

/* The derived field of node sums s (already averaged). */
static double derived(const double *s, SimCoarseField field)
{
    double rho = s[CH_RHO], inv = rho > 0.0 ? 1.0 / rho : 0.0;
    double kxx = s[CH_MXX] - s[CH_JX] * s[CH_JX] * inv;
    double kxy = s[CH_MXY] - s[CH_JX] * s[CH_JY] * inv;
    double kyy = s[CH_MYY] - s[CH_JY] * s[CH_JY] * inv;
    double per_grain = s[CH_N] > 0.0 ? 1.0 / s[CH_N] : 0.0;
    switch (field) {
    case SIM_CG_PHI:
        return s[CH_PHI];
    case SIM_CG_RHO:
        return rho;
    case SIM_CG_JX:
        return s[CH_JX];
    case SIM_CG_JY:
        return s[CH_JY];
    case SIM_CG_VX:
        return rho > 0.0 ? s[CH_JX] / rho : 0.0;
    case SIM_CG_VY:
        return rho > 0.0 ? s[CH_JY] / rho : 0.0;
    case SIM_CG_T:
        return 0.5 * (kxx + kyy) * inv; /* d = 2 */
    case SIM_CG_KXX:
        return kxx;
    case SIM_CG_KXY:
        return kxy;
    case SIM_CG_KYY:
        return kyy;
    case SIM_CG_CXX:
        return s[CH_CXX];
    case SIM_CG_CXY:
        return s[CH_CXY];
    case SIM_CG_CYX:
        return s[CH_CYX];
    case SIM_CG_CYY:
        return s[CH_CYY];
    case SIM_CG_SXX:
        return s[CH_CXX] + kxx;
    case SIM_CG_SXY:
        return s[CH_CXY] + kxy;
    case SIM_CG_SYX:
        return s[CH_CYX] + kxy;
    case SIM_CG_SYY:
        return s[CH_CYY] + kyy;
    case SIM_CG_P:
        return 0.5 * (s[CH_CXX] + kxx + s[CH_CYY] + kyy);
    case SIM_CG_Z:
        return s[CH_Z] * per_grain;
    case SIM_CG_FXX:
        return s[CH_FXX] * per_grain;
    case SIM_CG_FXY:
        return s[CH_FXY] * per_grain;
    case SIM_CG_FYY:
        return s[CH_FYY] * per_grain;
    default:
        return 0.0;
    }
}

void sim_coarse_field(const SimCoarse *cg, SimCoarseField field, double *out)
{
    double scale = cg->samples > 0 ? 1.0 / cg->samples : 0.0;
    for (int n = 0; n < cg->nodes; ++n) {
        double s[CH_COUNT];
        const double *src = cg->sums + (size_t)n * CH_COUNT;
        for (int q = 0; q < CH_COUNT; ++q)
            s[q] = cg->samples == 1 ? src[q] : src[q] * scale;
        out[n] = derived(s, field);
    }
}

void sim_world_masses(const SimWorld *w, double *mass)
{
    memcpy(mass, w->mass, (size_t)w->count * sizeof *mass);
}

/* ---------------------------------------------------------------- flux counters */

/* Open-addressing table of the mobile grains' last positions, keyed by stable id. */
typedef struct FluxSlot {
    uint32_t key; /* id + 1; 0 = empty */
    uint32_t stamp;
    double x, y;
} FluxSlot;

struct SimFlux {
    double x0, y0, x1, y1; /* m */
    long count;
    double mass; /* kg */
    FluxSlot *slots;
    int capacity, used; /* capacity: a power of two */
    uint32_t stamp;
};

SimFlux *sim_flux_create(double x0, double y0, double x1, double y1)
{
    SimFlux *f = calloc(1, sizeof *f);
    if (f)
        *f = (SimFlux){.x0 = x0, .y0 = y0, .x1 = x1, .y1 = y1};
    return f;
}

void sim_flux_destroy(SimFlux *f)
{
    if (f) {
        free(f->slots);
        free(f);
    }
}

void sim_flux_totals(const SimFlux *f, long *count, double *mass)
{
    *count = f->count;
    *mass = f->mass;
}

void sim_flux_set_totals(SimFlux *f, long count, double mass)
{
    f->count = count;
    f->mass = mass;
}

static FluxSlot *flux_slot(FluxSlot *slots, int capacity, uint32_t key)
{
    uint32_t h = key * 2654435761u; /* Knuth's multiplicative hash */
    for (int k = (int)(h & (uint32_t)(capacity - 1));; k = (k + 1) & (capacity - 1))
        if (slots[k].key == key || slots[k].key == 0)
            return &slots[k];
}

/* Room for `count` live grains at half load; entries not seen at the last update are dropped. */
static int flux_reserve(SimFlux *f, int count)
{
    if (2 * (f->used + count) < f->capacity)
        return 0;
    int capacity = 64;
    while (capacity < 4 * count)
        capacity *= 2;
    FluxSlot *slots = calloc((size_t)capacity, sizeof *slots);
    if (!slots)
        return -1;
    int used = 0;
    for (int k = 0; k < f->capacity; ++k)
        if (f->slots[k].key && f->slots[k].stamp == f->stamp) {
            *flux_slot(slots, capacity, f->slots[k].key) = f->slots[k];
            ++used;
        }
    free(f->slots);
    f->slots = slots;
    f->capacity = capacity;
    f->used = used;
    return 0;
}

SimStatus sim_flux_update(SimFlux *f, const SimWorld *w)
{
    if (flux_reserve(f, w->mobile_count) != 0)
        return SIM_ERROR_MEMORY;
    double ax = f->x1 - f->x0, ay = f->y1 - f->y0;
    double period = (w->effects & SIM_EFFECT_PERIODIC_X) ? w->def.domain_x1 - w->def.domain_x0 : 0;
    uint32_t stamp = f->stamp + 1;
    for (int i = 0; i < w->mobile_count; ++i) {
        FluxSlot *s = flux_slot(f->slots, f->capacity, w->id[i] + 1u);
        double qx = w->x[i], qy = w->y[i];
        if (s->key == 0) { /* a new grain: recorded, not counted */
            *s = (FluxSlot){.key = w->id[i] + 1u, .stamp = stamp, .x = qx, .y = qy};
            ++f->used;
            continue;
        }
        double px = s->x, py = s->y;
        if (period > 0.0)
            px += period * round((qx - px) / period); /* a wrap is not a crossing */
        double side_p = ax * (py - f->y0) - ay * (px - f->x0);
        double side_q = ax * (qy - f->y0) - ay * (qx - f->x0);
        if ((side_p > 0.0) != (side_q > 0.0)) {
            /* where the move meets the segment's line, as a fraction t of the segment */
            double mx = qx - px, my = qy - py;
            double den = ax * my - ay * mx;
            double t = den != 0.0 ? ((px - f->x0) * my - (py - f->y0) * mx) / den : -1.0;
            if (t >= 0.0 && t <= 1.0) {
                int sign = side_p > 0.0 ? 1 : -1; /* left to right: + */
                f->count += sign;
                f->mass += sign * w->mass[i];
            }
        }
        s->stamp = stamp;
        s->x = qx;
        s->y = qy;
    }
    f->stamp = stamp;
    return SIM_OK;
}
