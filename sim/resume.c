/* SPDX-License-Identifier: MIT */
/* resume.c: the exact-continuation section of a version-2 state file (docs/state-format.md).
 * The grains of a state are enough to start a stage, but the next step also depends on what the
 * world carries between steps: the grain order of the last neighbour build (the contact sums'
 * order), the lists themselves with their reference positions and the skin's state, the forces
 * of the last evaluation, the integrator's arrays, and the time as a step count from the
 * world's start time (not a sum of steps). This section holds them, so that a world loaded from
 * a state continues bit for bit as the saved one would have. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char exact_tag[8] = "EXACT-1\n";

typedef struct ExactHeader {
    char tag[8];
    double dt, start_time, def_skin;
    double skin, skin_min, skin_max, skin_density, disp_limit2, max_radius, cell_size, wall_shift,
        guard_speed2;
    int64_t skin_probe, build_step, rebuilds, guard_next;
    int32_t skin_auto, need_rebuild, scratch_count, periodic, has_history, pending_removal;
    int32_t pairs, wall_pairs; /* list entries */
} ExactHeader;

_Static_assert(sizeof(ExactHeader) == 168, "docs/state-format.md: the continuation header");

static int periodic_of(const SimWorld *w)
{
    return (w->effects & SIM_EFFECT_PERIODIC_X) != 0;
}

static int write_doubles(FILE *f, const double *a, size_t n)
{
    return n == 0 || fwrite(a, sizeof *a, n, f) == n;
}

static int write_ints(FILE *f, const int *a, size_t n)
{
    return n == 0 || fwrite(a, sizeof *a, n, f) == n;
}

int sim_exact_write(FILE *f, const SimWorld *w)
{
    ExactHeader h;
    memset(&h, 0, sizeof h);
    memcpy(h.tag, exact_tag, sizeof h.tag);
    h.dt = w->dt;
    h.start_time = w->def.start_time;
    h.def_skin = w->def.skin;
    h.skin = w->skin;
    h.skin_min = w->skin_min;
    h.skin_max = w->skin_max;
    h.skin_density = w->skin_density;
    h.disp_limit2 = w->disp_limit2;
    h.max_radius = w->max_radius;
    h.cell_size = w->cell_size;
    h.wall_shift = w->wall_shift;
    h.guard_speed2 = w->guard_speed2;
    h.skin_probe = w->skin_probe;
    h.build_step = w->build_step;
    h.rebuilds = w->rebuilds;
    h.guard_next = w->guard_next;
    h.skin_auto = w->skin_auto;
    h.need_rebuild = w->need_rebuild;
    h.scratch_count = w->scratch_count;
    h.periodic = periodic_of(w);
    h.has_history = w->has_history;
    h.pending_removal = w->pending_removal;
    h.pairs = w->nl.start ? w->nl.start[w->mobile_count] : 0;
    h.wall_pairs = w->wl.count;
    const size_t n = (size_t)w->count, nw = (size_t)w->wall_count, k = (size_t)h.pairs,
                 q = (size_t)h.wall_pairs;
    int ok = fwrite(&h, sizeof h, 1, f) == 1;
    const double *grain[] = {w->x_ref, w->y_ref, w->fx, w->fy, w->torque, w->force_mag};
    for (size_t a = 0; a < sizeof grain / sizeof grain[0]; ++a)
        ok = ok && write_doubles(f, grain[a], n);
    for (int a = 0; a < w->scratch_count; ++a)
        ok = ok && write_doubles(f, w->scratch[a], n);
    ok = ok && write_doubles(f, w->wall_ref_dx, nw) && write_doubles(f, w->wall_ref_dy, nw);
    ok = ok && (nw == 0 || fwrite(w->walls_ref, sizeof(SimWall), nw, f) == nw);
    if (w->nl.start)
        ok = ok && write_ints(f, w->nl.start, (size_t)w->mobile_count + 1);
    else {
        for (int i = 0; ok && i <= w->mobile_count; ++i) {
            int zero = 0;
            ok = fwrite(&zero, sizeof zero, 1, f) == 1;
        }
    }
    ok = ok && write_ints(f, w->nl.j, k);
    if (h.periodic)
        ok = ok && write_doubles(f, w->nl.shift, k);
    if (h.has_history)
        ok = ok && write_doubles(f, w->nl.hist_t, k) && write_doubles(f, w->nl.hist_r, k);
    ok = ok && write_ints(f, w->wl.grain, q) && write_ints(f, w->wl.wall, q);
    if (h.has_history)
        ok = ok && write_doubles(f, w->wl.hist_t, q) && write_doubles(f, w->wl.hist_r, q);
    return ok ? 0 : -1;
}

/* ------------------------------------------------------------------ reading */

static int read_doubles(FILE *f, double *a, size_t n)
{
    return n == 0 || fread(a, sizeof *a, n, f) == n;
}

static int key_compare(const void *a, const void *b)
{
    uint64_t ka = *(const uint64_t *)a, kb = *(const uint64_t *)b;
    return (ka > kb) - (ka < kb);
}

/* The world's grains put back into the saved order (by id): new index k holds the grain whose
 * id is ids[k]. -1 when an id is missing or out of memory. */
static int restore_order(SimWorld *w, const uint32_t *ids)
{
    const size_t n = (size_t)w->count;
    uint64_t *keys = malloc((n ? n : 1) * sizeof *keys); /* id << 32 | index, sorted */
    int *order = malloc((n ? n : 1) * sizeof *order);
    int ok = keys && order;
    for (size_t i = 0; ok && i < n; ++i)
        keys[i] = ((uint64_t)w->id[i] << 32) | (uint64_t)i;
    if (ok && n > 0)
        qsort(keys, n, sizeof *keys, key_compare);
    for (size_t k = 0; ok && k < n; ++k) {
        size_t lo = 0, hi = n; /* the first key whose id is >= ids[k] */
        while (lo < hi) {
            size_t mid = lo + (hi - lo) / 2;
            if ((keys[mid] >> 32) < ids[k])
                lo = mid + 1;
            else
                hi = mid;
        }
        ok = lo < n && (keys[lo] >> 32) == ids[k];
        order[k] = ok ? (int)(keys[lo] & 0xffffffffu) : 0;
    }
    ok = ok && sim_grains_permute(w, order, (int)n) == 0;
    free(keys);
    free(order);
    return ok ? 0 : -1;
}

/* What no written section holds: a time step, length or speed that is not a finite number of
 * its sign (a cell size of 0 made the grid set-up loop for ever), negative list sizes; NULL
 * when the header is sound. A header without the section's tag is not looked at (it is never
 * applied). */
static const char *header_problem(const ExactHeader *h)
{
    if (memcmp(h->tag, exact_tag, sizeof h->tag) != 0)
        return NULL;
    const double at_least_0[] = {h->def_skin,     h->skin,        h->skin_min,   h->skin_max,
                                 h->skin_density, h->disp_limit2, h->max_radius, h->wall_shift};
    for (size_t k = 0; k < sizeof at_least_0 / sizeof at_least_0[0]; ++k)
        if (!(at_least_0[k] >= 0.0) || !isfinite(at_least_0[k]))
            return "continuation section: a skin or radius not finite and >= 0";
    if (!(h->cell_size > 0.0) || !isfinite(h->cell_size))
        return "continuation section: a cell size not finite and > 0";
    if (!(h->dt > 0.0) || !isfinite(h->dt) || !isfinite(h->start_time) || !(h->guard_speed2 >= 0.0))
        return "continuation section: time step or guard out of range";
    if (h->pairs < 0 || h->wall_pairs < 0 || h->scratch_count < 0 || h->skin_probe < 0 ||
        h->build_step < 0 || h->rebuilds < 0)
        return "continuation section: a negative count";
    return NULL;
}

const char *sim_exact_check(FILE *f)
{
    ExactHeader h;
    if (fread(&h, sizeof h, 1, f) != 1)
        return "truncated state file (its continuation section)";
    return header_problem(&h);
}

/* 1 when the section fits this world (same grains, time step, integrator arrays, laws and skin
 * setting): only then does it continue exactly; else the world starts afresh from the grains. */
static int exact_fits(const SimWorld *w, const ExactHeader *h)
{
    return memcmp(h->tag, exact_tag, sizeof h->tag) == 0 &&
           memcmp(&h->dt, &w->dt, sizeof h->dt) == 0 && h->scratch_count == w->scratch_count &&
           h->periodic == periodic_of(w) && h->has_history == w->has_history &&
           memcmp(&h->def_skin, &w->def.skin, sizeof h->def_skin) == 0 && h->pairs >= 0 &&
           h->wall_pairs >= 0;
}

/* 1 when the rest of the file holds the arrays the header announces. */
static int section_fits_file(const SimWorld *w, FILE *f, const ExactHeader *h)
{
    const double n = w->count, nw = w->wall_count, m = w->mobile_count;
    const double per_pair = 4.0 + (h->periodic ? 8.0 : 0.0) + (h->has_history ? 16.0 : 0.0);
    const double per_wall_pair = 8.0 + (h->has_history ? 16.0 : 0.0);
    const double need = (6.0 + h->scratch_count) * n * 8.0 + nw * (16.0 + sizeof(SimWall)) +
                        (m + 1.0) * 4.0 + h->pairs * per_pair + h->wall_pairs * per_wall_pair;
    struct stat st;
    long here = ftell(f);
    return here >= 0 && fstat(fileno(f), &st) == 0 && need <= (double)st.st_size - (double)here;
}

static void apply_header(SimWorld *w, const ExactHeader *h)
{
    w->def.start_time = h->start_time;
    w->skin = h->skin;
    w->skin_min = h->skin_min;
    w->skin_max = h->skin_max;
    w->skin_density = h->skin_density;
    w->disp_limit2 = h->disp_limit2;
    w->max_radius = h->max_radius;
    w->cell_size = h->cell_size;
    w->wall_shift = h->wall_shift;
    w->guard_speed2 = h->guard_speed2; /* as the continuous run set it at its create */
    w->skin_probe = (long)h->skin_probe;
    w->build_step = (long)h->build_step;
    w->rebuilds = (long)h->rebuilds;
    w->guard_next = (long)h->guard_next;
    w->skin_auto = h->skin_auto;
    w->need_rebuild = h->need_rebuild;
    w->pending_removal = h->pending_removal;
    w->jump_grain = -1;
    w->drop_history = 0;
}

/* The arrays of the section into the world (in the saved order) and its lists. -1: truncated
 * (the world is then unusable), -2: out of memory. */
static int read_arrays(SimWorld *w, FILE *f, const ExactHeader *h)
{
    const size_t n = (size_t)w->count, nw = (size_t)w->wall_count, k = (size_t)h->pairs,
                 q = (size_t)h->wall_pairs, m = (size_t)w->mobile_count;
    double *grain[] = {w->x_ref, w->y_ref, w->fx, w->fy, w->torque, w->force_mag};
    int ok = 1;
    for (size_t a = 0; ok && a < sizeof grain / sizeof grain[0]; ++a)
        ok = read_doubles(f, grain[a], n);
    for (int a = 0; ok && a < w->scratch_count; ++a)
        ok = read_doubles(f, w->scratch[a], n);
    ok = ok && read_doubles(f, w->wall_ref_dx, nw) && read_doubles(f, w->wall_ref_dy, nw);
    ok = ok && (nw == 0 || fread(w->walls_ref, sizeof(SimWall), nw, f) == nw);
    if (!ok)
        return -1;
    SimListArrays l = {0};
    l.start = malloc((m + 1) * sizeof *l.start);
    l.j = malloc((k ? k : 1) * sizeof *l.j);
    l.shift = h->periodic ? malloc((k ? k : 1) * sizeof *l.shift) : NULL;
    l.hist_t = h->has_history ? malloc((k ? k : 1) * sizeof *l.hist_t) : NULL;
    l.hist_r = h->has_history ? malloc((k ? k : 1) * sizeof *l.hist_r) : NULL;
    l.wall_grain = malloc((q ? q : 1) * sizeof *l.wall_grain);
    l.wall = malloc((q ? q : 1) * sizeof *l.wall);
    l.wall_hist_t = h->has_history ? malloc((q ? q : 1) * sizeof *l.wall_hist_t) : NULL;
    l.wall_hist_r = h->has_history ? malloc((q ? q : 1) * sizeof *l.wall_hist_r) : NULL;
    l.pairs = h->pairs;
    l.wall_pairs = h->wall_pairs;
    int status =
        l.start && l.j && l.wall_grain && l.wall && (!h->periodic || l.shift) &&
                (!h->has_history || (l.hist_t && l.hist_r && l.wall_hist_t && l.wall_hist_r))
            ? 0
            : -2;
    if (status == 0) {
        ok = fread(l.start, sizeof *l.start, m + 1, f) == m + 1 &&
             (k == 0 || fread(l.j, sizeof *l.j, k, f) == k) &&
             (!h->periodic || read_doubles(f, l.shift, k)) &&
             (!h->has_history || (read_doubles(f, l.hist_t, k) && read_doubles(f, l.hist_r, k))) &&
             (q == 0 || (fread(l.wall_grain, sizeof *l.wall_grain, q, f) == q &&
                         fread(l.wall, sizeof *l.wall, q, f) == q)) &&
             (!h->has_history ||
              (read_doubles(f, l.wall_hist_t, q) && read_doubles(f, l.wall_hist_r, q)));
        status = !ok ? -1 : sim_neighbour_install(w, &l) != 0 ? -2 : 0;
    }
    free(l.start);
    free(l.j);
    free(l.shift);
    free(l.hist_t);
    free(l.hist_r);
    free(l.wall_grain);
    free(l.wall);
    free(l.wall_hist_t);
    free(l.wall_hist_r);
    return status;
}

int sim_exact_apply(SimWorld *w, FILE *f, const SimGrainSet *saved, long step, double time)
{
    ExactHeader h;
    if (fread(&h, sizeof h, 1, f) != 1 || header_problem(&h))
        return -1;
    if (!exact_fits(w, &h) || saved->count != w->count)
        return 0;
    if (!section_fits_file(w, f, &h))
        return -1; /* announces more than the file holds: refused before allocating */
    if (restore_order(w, saved->id) != 0)
        return -2;
    /* the saved positions of the mobile grains (the build at create may have wrapped them) and
     * every flag (a grain waiting for removal) */
    for (int i = 0; i < w->count; ++i) {
        if (i < w->mobile_count) {
            w->x[i] = saved->x[i];
            w->y[i] = saved->y[i];
        }
        w->flags[i] = saved->flags[i];
    }
    apply_header(w, &h);
    int status = read_arrays(w, f, &h);
    if (status != 0)
        return status;
    w->step = step;
    w->time = time;
    return 1;
}
