/* SPDX-License-Identifier: MIT */
/* neighbour.c: linked cells plus a Verlet list with a skin. At each build the grains are re-sorted
 * by cell (mobile first, then fixed), the half list is rebuilt in CSR form with per-pair constants,
 * and contact history is carried over by stable grain ids, so it survives rebuilds, sorting and
 * removal. O(N) time and memory. */
#include "internal.h"
#include "walls.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct HistoryRecord {
    uint64_t key; /* (low id << 32) | high id, or (id << 32) | wall for wall contacts */
    double t, r;  /* tangential stretch; rolling torque oriented low id -> high id */
} HistoryRecord;

_Static_assert(sizeof(HistoryRecord) == SIM_HISTORY_RECORD_SIZE, "checkpoint record layout");

struct HistoryStash {
    HistoryRecord *records, *walls;
    int count, wall_count;
};

static uint64_t pair_key(uint32_t a, uint32_t b)
{
    return a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
}

static int record_compare(const void *a, const void *b)
{
    uint64_t ka = ((const HistoryRecord *)a)->key, kb = ((const HistoryRecord *)b)->key;
    return (ka > kb) - (ka < kb);
}

static const HistoryRecord *record_find(const HistoryRecord *records, int count, uint64_t key)
{
    int lo = 0, hi = count - 1;
    while (lo <= hi) {
        int mid = lo + (hi - lo) / 2;
        if (records[mid].key == key)
            return &records[mid];
        if (records[mid].key < key)
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return NULL;
}

/* Out of memory the build cannot return an error (it runs inside a step): the growers below
 * leave the array as it was, record the failure (world->out_of_memory, which sim_world_step
 * reports) and the build ends with empty lists. */
#define GROW_TO(array, grown)                                                                      \
    do {                                                                                           \
        void *grown_ = (grown);                                                                    \
        if (!grown_) {                                                                             \
            sim_world_out_of_memory(world, "the neighbour list");                                  \
            return -1;                                                                             \
        }                                                                                          \
        (array) = grown_;                                                                          \
    } while (0)
#define GROW(array, count)                                                                         \
    GROW_TO(array, realloc(array, ((count) > 0 ? (count) : 1) * sizeof *(array)))

/* The per-entry arrays the contact pass reads at one entry index are staggered blocks
 * (sim_stagger_grow, internal.h; docs/dev/scaling.md, "the list's arrays staggered"), numbered: */
enum {
    LIST_J,
    LIST_OWNER,
    LIST_GAMMA,
    LIST_PAIR,
    LIST_SHIFT,
    LIST_HIST_T,
    LIST_HIST_R,
    LIST_HIST_T_SPARE,
    LIST_HIST_R_SPARE
};

#define GROW_STAGGERED(array, count, k)                                                            \
    GROW_TO(array, sim_stagger_grow(array, (count) * sizeof *(array), k))

static int list_reserve(SimWorld *world, int capacity)
{
    NeighbourList *nl = &world->nl;
    if (capacity <= nl->capacity)
        return 0;
    size_t n = (size_t)capacity;
    GROW_STAGGERED(nl->j, n, LIST_J);
    GROW_STAGGERED(nl->gamma, n, LIST_GAMMA);
    GROW_STAGGERED(nl->pair, n, LIST_PAIR);
    GROW_STAGGERED(nl->owner, n, LIST_OWNER);
    if (world->effects & SIM_EFFECT_PERIODIC_X)
        GROW_STAGGERED(nl->shift, n, LIST_SHIFT);
    if (world->has_history) {
        GROW_STAGGERED(nl->hist_t, n, LIST_HIST_T);
        GROW_STAGGERED(nl->hist_r, n, LIST_HIST_R);
        GROW_STAGGERED(nl->hist_t_spare, n, LIST_HIST_T_SPARE);
        GROW_STAGGERED(nl->hist_r_spare, n, LIST_HIST_R_SPARE);
    }
    nl->capacity = capacity;
    return 0;
}

static int wall_list_reserve(SimWorld *world, int capacity)
{
    WallList *wl = &world->wl;
    if (capacity <= wl->capacity)
        return 0;
    size_t n = (size_t)capacity;
    GROW(wl->grain, n);
    GROW(wl->wall, n);
    GROW(wl->gamma, n);
    GROW(wl->pair, n);
    if (world->has_history) {
        GROW(wl->hist_t, n);
        GROW(wl->hist_r, n);
    }
    wl->capacity = capacity;
    return 0;
}

/* The pair build runs in parts, one per thread (the grains [mobile p / P, mobile (p + 1) / P)),
 * in two passes over the threads: the first finds each grain's partners (the cell search, most
 * of the build) into its part's sink, the second, once the counts give every grain its place,
 * writes the list's entries (partner, owner, species pair, damping, shift, history). The list is
 * the concatenation in grain order whatever the number of parts: the same bits on any thread
 * count. The first part's sink is the list itself, so one thread needs no more memory than the
 * serial build did; the other parts' sinks keep their arrays between builds (4 bytes per entry,
 * 12 with a periodic x). Serial, the build kept the other thread waiting for 1-2 % of a
 * 2-thread step's time (docs/dev/scaling.md). */
typedef struct ListSink {
    int *j;
    double *shift; /* periodic x only */
    int count, capacity;
    long wide, touching; /* the automatic skin's counts (build_pairs) */
} ListSink;

struct ListBuild {
    int parts;
    ListSink *sinks;
    const HistoryRecord *records; /* the history to carry over, sorted by key */
    int record_count;
};

static void build_free(struct ListBuild *b)
{
    if (!b)
        return;
    for (int p = 0; p < b->parts; ++p) {
        free(b->sinks[p].j);
        free(b->sinks[p].shift);
    }
    free(b->sinks);
    free(b);
}

/* The build's parts for the world's thread count (their sinks kept while it stays the same);
 * NULL when out of memory. */
static struct ListBuild *build_parts(SimWorld *world)
{
    NeighbourList *nl = &world->nl;
    const int parts = world->threads > 1 ? world->threads : 1;
    if (nl->build && nl->build->parts == parts)
        return nl->build;
    build_free(nl->build);
    nl->build = calloc(1, sizeof *nl->build);
    if (nl->build) {
        nl->build->sinks = calloc((size_t)parts, sizeof *nl->build->sinks);
        if (!nl->build->sinks) {
            free(nl->build);
            nl->build = NULL;
        } else {
            nl->build->parts = parts;
        }
    }
    return nl->build;
}

void sim_neighbour_free(SimWorld *world)
{
    NeighbourList *nl = &world->nl;
    free(nl->start);
    sim_stagger_free(nl->j);
    sim_stagger_free(nl->gamma);
    sim_stagger_free(nl->pair);
    sim_stagger_free(nl->shift);
    sim_stagger_free(nl->owner);
    free(nl->out);
    free(nl->in_start);
    free(nl->in_entry);
    sim_parts_free(world);
    build_free(nl->build);
    nl->build = NULL;
    sim_stagger_free(nl->hist_t);
    sim_stagger_free(nl->hist_r);
    sim_stagger_free(nl->hist_t_spare);
    sim_stagger_free(nl->hist_r_spare);
    WallList *wl = &world->wl;
    free(wl->grain);
    free(wl->wall);
    free(wl->gamma);
    free(wl->pair);
    free(wl->hist_t);
    free(wl->hist_r);
    free(world->cell_start);
    free(world->cell_items);
    free(world->cell_of);
    if (world->stash) {
        free(world->stash->records);
        free(world->stash->walls);
        free(world->stash);
    }
}

/* gamma_n of a pair from the two species' damping specifications, mean of the two.
 * 000 eq. 3.25 with t_n = pi / omega_d solved for gamma: gamma = 2 zeta sqrt(k m_eff),
 * zeta = -ln e / sqrt(pi^2 + ln^2 e); 004 eq. 1.11: gamma = 2 f sqrt(k m_eff). */
double sim_damping_gamma(const SimMaterial *materials, int species_i, int species_j, double k_n,
                         double m_eff)
{
    double root = sqrt(k_n * m_eff);
    int s[2] = {species_i, species_j};
    double sum = 0.0;
    for (int k = 0; k < 2; ++k) {
        const SimMaterial *m = &materials[s[k]];
        switch (m->damping_mode) {
        case SIM_DAMPING_GAMMA:
            sum += m->normal_damping;
            break;
        case SIM_DAMPING_RESTITUTION: {
            double le = log(m->restitution);
            sum += 2.0 * (-le / sqrt(SIM_PI * SIM_PI + le * le)) * root;
            break;
        }
        case SIM_DAMPING_CRITICAL:
            sum += 2.0 * m->critical_fraction * root;
            break;
        }
    }
    return 0.5 * sum;
}

/* gamma_n of a list entry: the pair's k_n, m_eff from the inverse masses (0 for a fixed grain or
 * a wall). */
static double pair_gamma(const SimWorld *world, int species_i, int species_j, double inv_mass_i,
                         double inv_mass_j)
{
    const PairParams *p = &world->pairs[species_i * SIM_MAX_SPECIES + species_j];
    double inv = inv_mass_i + inv_mass_j;
    double m_eff = inv > 0.0 ? 1.0 / inv : 0.0;
    return sim_damping_gamma(world->def.materials, species_i, species_j, p->k_n, m_eff);
}

static int cell_index(double t, int n)
{
    if (t >= 0.0 && t < (double)n)
        return (int)t;
    return t >= (double)n ? n - 1 : 0; /* also NaN -> 0 */
}

/* Grid over the grains; periodic x uses the domain. Cells are at least 2 r_max + skin wide, and
 * the cell count is capped so that a stray grain far away cannot make the grid huge. */
static int grid_setup(SimWorld *world)
{
    const int n = world->count;
    const int periodic = (world->effects & SIM_EFFECT_PERIODIC_X) != 0;
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int i = 0; i < n; ++i) {
        double x = world->x[i], y = world->y[i];
        if (x < x0)
            x0 = x;
        if (x > x1)
            x1 = x;
        if (y < y0)
            y0 = y;
        if (y > y1)
            y1 = y;
    }
    if (!(x1 >= x0) || !(y1 >= y0)) { /* no grains or NaN: one cell */
        x0 = y0 = 0.0;
        x1 = y1 = 1.0;
    }
    if (periodic) {
        x0 = world->def.domain_x0;
        x1 = world->def.domain_x1;
    }
    double cell = world->cell_size;
    double max_cells = 4.0 * n + 1024.0;
    double nx = periodic ? floor((x1 - x0) / cell) : floor((x1 - x0) / cell) + 1.0;
    double ny = floor((y1 - y0) / cell) + 1.0;
    if (nx < 1.0)
        nx = 1.0;
    while (!(nx * ny <= max_cells)) { /* coarsen */
        cell *= 2.0;
        if (!isfinite(cell)) { /* grains spread over more than DBL_MAX: one cell */
            nx = ny = 1.0;
            break;
        }
        nx = periodic ? floor((x1 - x0) / cell) : floor((x1 - x0) / cell) + 1.0;
        ny = floor((y1 - y0) / cell) + 1.0;
        if (nx < 1.0)
            nx = 1.0;
    }
    world->ncx = (int)nx;
    world->ncy = (int)ny;
    world->grid_x0 = x0;
    world->grid_y0 = y0;
    world->cell_w = periodic ? (x1 - x0) / nx : cell;
    world->cell_h = cell;
    int cells = world->ncx * world->ncy;
    if (cells + 1 > world->cell_capacity) {
        GROW(world->cell_start, (size_t)cells + 1);
        world->cell_capacity = cells + 1;
    }
    return 0;
}

static void grid_fill(SimWorld *world)
{
    const int n = world->count, cells = world->ncx * world->ncy;
    int *start = world->cell_start;
    memset(start, 0, (size_t)(cells + 1) * sizeof *start);
    for (int i = 0; i < n; ++i) {
        int cx = cell_index((world->x[i] - world->grid_x0) / world->cell_w, world->ncx);
        int cy = cell_index((world->y[i] - world->grid_y0) / world->cell_h, world->ncy);
        int c = cy * world->ncx + cx;
        world->cell_of[i] = c;
        ++start[c + 1];
    }
    for (int c = 0; c < cells; ++c)
        start[c + 1] += start[c];
    /* Fill in index order so each cell lists its grains ascending (deterministic). */
    int *fill = world->cell_items; /* temporarily: running position per cell kept in start */
    for (int i = 0; i < n; ++i)
        fill[start[world->cell_of[i]]++] = i;
    for (int c = cells; c > 0; --c)
        start[c] = start[c - 1];
    start[0] = 0;
}

/* Mobile grains in cell order, then fixed grains in cell order. */
static int spatial_sort(SimWorld *world)
{
    const int n = world->count, mobile = world->mobile_count;
    int *order = malloc((size_t)(n > 0 ? n : 1) * sizeof *order);
    if (!order) {
        sim_world_out_of_memory(world, "sorting the grains");
        return -1;
    }
    int m = 0, f = mobile;
    for (int k = 0; k < n; ++k) {
        int i = world->cell_items[k];
        if (i < mobile)
            order[m++] = i;
        else
            order[f++] = i;
    }
    int rc = sim_grains_permute(world, order, n);
    free(order);
    if (rc != 0)
        sim_world_out_of_memory(world, "sorting the grains");
    return rc;
}

/* The history of the current lists by ids, sorted: pair records returned, wall records in *walls
 * (both malloc'd; NULL when there is none). -1 in *status when out of memory. */
static HistoryRecord *collect_history(const SimWorld *world, int *count, HistoryRecord **walls,
                                      int *wall_count, int *status)
{
    *count = *wall_count = 0;
    *walls = NULL;
    *status = 0;
    if (!world->has_history || !world->nl.start || world->drop_history)
        return NULL;
    const NeighbourList *nl = &world->nl;
    int total = nl->start[world->mobile_count];
    HistoryRecord *records = malloc((size_t)(total > 0 ? total : 1) * sizeof *records);
    HistoryRecord *wr = malloc((size_t)(world->wl.count > 0 ? world->wl.count : 1) * sizeof *wr);
    if (!records || !wr) {
        free(records);
        free(wr);
        *status = -1;
        return NULL;
    }
    int c = 0;
    for (int i = 0; i < world->mobile_count; ++i) {
        for (int k = nl->start[i]; k < nl->start[i + 1]; ++k) {
            if (nl->hist_t[k] == 0.0 && nl->hist_r[k] == 0.0)
                continue;
            uint32_t a = world->id[i], b = world->id[nl->j[k]];
            records[c].key = pair_key(a, b);
            records[c].t = nl->hist_t[k];
            records[c].r = a < b ? nl->hist_r[k] : -nl->hist_r[k];
            ++c;
        }
    }
    int w = 0;
    for (int k = 0; k < world->wl.count; ++k) {
        if (world->wl.hist_t[k] == 0.0 && world->wl.hist_r[k] == 0.0)
            continue;
        wr[w].key = ((uint64_t)world->id[world->wl.grain[k]] << 32) | (uint32_t)world->wl.wall[k];
        wr[w].t = world->wl.hist_t[k];
        wr[w].r = world->wl.hist_r[k];
        ++w;
    }
    qsort(records, (size_t)c, sizeof *records, record_compare);
    qsort(wr, (size_t)w, sizeof *wr, record_compare);
    *count = c;
    *walls = wr;
    *wall_count = w;
    return records;
}

/* Appends partner j (with its periodic shift) to a part's sink; the first part's sink is the list
 * itself (its entries are where the partners are found, so one thread needs no sink, and several
 * need sinks for all parts but the first). -1 when out of memory. */
static int sink_push(SimWorld *world, ListSink *sink, int first, int periodic, int j, double shift)
{
    if (first) {
        NeighbourList *nl = &world->nl;
        if (sink->count == nl->capacity && list_reserve(world, 2 * nl->capacity) != 0)
            return -1;
        nl->j[sink->count] = j;
        if (periodic)
            nl->shift[sink->count] = shift;
        ++sink->count;
        return 0;
    }
    if (sink->count == sink->capacity) {
        const int capacity = 2 * sink->capacity + 256;
        int *grown = realloc(sink->j, (size_t)capacity * sizeof *grown);
        if (grown)
            sink->j = grown;
        double *shifts = grown && periodic ? realloc(sink->shift, (size_t)capacity * sizeof *shifts)
                                           : sink->shift;
        if (!grown || (periodic && !shifts))
            return -1;
        sink->shift = shifts;
        sink->capacity = capacity;
    }
    sink->j[sink->count] = j;
    if (periodic)
        sink->shift[sink->count] = shift;
    ++sink->count;
    return 0;
}

/* The partners j > i within rs + skin of the grains [i0, i1) into a sink, their count per grain in
 * nl.start[i + 1]. The automatic skin also counts the pairs within skin_max (the grid's cells are
 * that wide, so the loop visits them all) to learn how the list grows with the skin. */
static int find_partners(SimWorld *world, ListSink *sink, int first, int i0, int i1)
{
    const int periodic = (world->effects & SIM_EFFECT_PERIODIC_X) != 0;
    const double span = world->def.domain_x1 - world->def.domain_x0;
    const double skin = world->skin;
    const double reach = world->skin_auto ? world->skin_max : skin;
    int *start = world->nl.start;
    sink->count = 0;
    sink->wide = sink->touching = 0;
    for (int i = i0; i < i1; ++i) {
        const int before = sink->count;
        const double xi = world->x[i], yi = world->y[i], ri = world->radius[i];
        const int c = world->cell_of[i];
        const int cx = c % world->ncx, cy = c / world->ncx;
        for (int oy = -1; oy <= 1; ++oy) {
            int ny = cy + oy;
            if (ny < 0 || ny >= world->ncy)
                continue;
            for (int ox = -1; ox <= 1; ++ox) {
                int nx = cx + ox;
                double shift = 0.0;
                if (nx < 0 || nx >= world->ncx) {
                    if (!periodic)
                        continue;
                    shift = nx < 0 ? -span : span;
                    nx = nx < 0 ? world->ncx - 1 : 0;
                }
                int cell = ny * world->ncx + nx;
                for (int q = world->cell_start[cell]; q < world->cell_start[cell + 1]; ++q) {
                    int j = world->cell_items[q];
                    if (j <= i)
                        continue;
                    double dx = world->x[j] + shift - xi, dy = world->y[j] - yi;
                    const double rs = ri + world->radius[j], d2 = dx * dx + dy * dy;
                    if (world->skin_auto) {
                        if (d2 >= (rs + reach) * (rs + reach))
                            continue;
                        ++sink->wide;
                        sink->touching += d2 < rs * rs;
                    }
                    double cut = rs + skin;
                    if (d2 >= cut * cut)
                        continue;
                    if (sink_push(world, sink, first, periodic, j, shift) != 0)
                        return -1;
                }
            }
        }
        start[i + 1] = sink->count - before;
    }
    return 0;
}

/* The list's entries of the grains [i0, i1) from their sink, at the places nl.start gives. */
static void write_entries(SimWorld *world, const ListSink *sink, int first, int i0, int i1)
{
    const struct ListBuild *b = world->nl.build;
    const int periodic = (world->effects & SIM_EFFECT_PERIODIC_X) != 0;
    NeighbourList *nl = &world->nl;
    const int *partner = first ? nl->j : sink->j; /* the first part's are in place */
    const double *shift = first ? nl->shift : sink->shift;
    int s = 0;
    for (int i = i0; i < i1; ++i) {
        const int si = world->species[i];
        for (int k = nl->start[i]; k < nl->start[i + 1]; ++k, ++s) {
            const int j = partner[s], sj = world->species[j];
            nl->j[k] = j;
            nl->owner[k] = i;
            nl->pair[k] = (uint8_t)(si * SIM_MAX_SPECIES + sj);
            nl->gamma[k] = pair_gamma(world, si, sj, world->inv_mass[i], world->inv_mass[j]);
            if (periodic)
                nl->shift[k] = shift[s];
            if (world->has_history) {
                const HistoryRecord *h = b->record_count
                                             ? record_find(b->records, b->record_count,
                                                           pair_key(world->id[i], world->id[j]))
                                             : NULL;
                nl->hist_t[k] = h ? h->t : 0.0;
                nl->hist_r[k] = h ? (world->id[i] < world->id[j] ? h->r : -h->r) : 0.0;
            }
        }
    }
}

static int part_first(const SimWorld *world, int p)
{
    return (int)((long long)world->mobile_count * p / world->nl.build->parts);
}

/* The two passes over parts [begin, end) (sim_parallel_units): 1 when a sink ran out of memory. */
static int find_parts(SimWorld *world, int begin, int end)
{
    int failed = 0;
    for (int p = begin; p < end; ++p)
        failed |= find_partners(world, &world->nl.build->sinks[p], p == 0, part_first(world, p),
                                part_first(world, p + 1)) != 0;
    return failed;
}

static int write_parts(SimWorld *world, int begin, int end)
{
    for (int p = begin; p < end; ++p)
        write_entries(world, &world->nl.build->sinks[p], p == 0, part_first(world, p),
                      part_first(world, p + 1));
    return 0;
}

/* The half list in CSR form, on the world's threads (ListSink above). */
static int build_pairs(SimWorld *world, const HistoryRecord *records, int record_count)
{
    const int mobile = world->mobile_count;
    NeighbourList *nl = &world->nl;
    struct ListBuild *b = build_parts(world);
    /* nl->start holds capacity + 1 entries (sim_grains_reserve) */
    if (!b || (nl->capacity < 4 * mobile + 16 && list_reserve(world, 4 * mobile + 16) != 0)) {
        sim_world_out_of_memory(world, "the neighbour list");
        return -1;
    }
    b->records = records;
    b->record_count = record_count;
    if (sim_parallel_units(world, find_parts, b->parts) != 0) {
        sim_world_out_of_memory(world, "the neighbour list");
        return -1;
    }
    long wide = 0, touching = 0;
    for (int p = 0; p < b->parts; ++p) {
        wide += b->sinks[p].wide;
        touching += b->sinks[p].touching;
    }
    nl->start[0] = 0;
    for (int i = 0; i < mobile; ++i)
        nl->start[i + 1] += nl->start[i];
    int capacity = nl->capacity;
    while (capacity < nl->start[mobile])
        capacity *= 2;
    if (list_reserve(world, capacity) != 0)
        return -1;
    sim_parallel_units(world, write_parts, b->parts);
    b->records = NULL;
    if (world->skin_auto) {
        const double reach = world->skin_max;
        world->skin_density =
            mobile > 0 && reach > 0.0 ? (double)(wide - touching) / ((double)mobile * reach) : 0.0;
    }
    return 0;
}

/* The list transposed (NeighbourList.in_start, in_entry) and the per-entry results of the
 * threaded pass (nl.out): a counting sort of the entries by partner, filled in entry order so that
 * each grain's entries stay ascending. Built for a world with threads only (one thread scatters
 * block by block and needs neither: 4 + 32 bytes per entry less). They only speed the pass up: out
 * of memory, in_ready stays 0 and the serial scatter gives the same bits. */
void sim_neighbour_build_incoming(SimWorld *world)
{
    NeighbourList *nl = &world->nl;
    nl->in_ready = 0;
    nl->plan.count = 0;
    if (world->threads <= 1 || !nl->start)
        return;
    sim_parts_build(world);
    const int n = world->count, total = nl->start[world->mobile_count];
    if (n + 1 > nl->in_capacity) {
        int *grown = realloc(nl->in_start, ((size_t)n + 1) * sizeof *grown);
        if (!grown)
            return;
        nl->in_start = grown;
        nl->in_capacity = n + 1;
    }
    /* nl.out holds its four results at a stride of the list's capacity (results_whole), so it
     * follows the capacity, not the entry count: a build may grow the capacity with the mobile
     * count (grains added mid-run) while the entries still fit the old size. */
    if (nl->capacity > nl->out_capacity) {
        const size_t cap = (size_t)nl->capacity; /* >= total */
        int *entry = realloc(nl->in_entry, cap * sizeof *entry);
        if (entry)
            nl->in_entry = entry;
        double *out = entry ? realloc(nl->out, 4 * cap * sizeof *out) : NULL;
        if (!out)
            return;
        nl->out = out;
        nl->out_capacity = nl->capacity;
    }
    int *in = nl->in_start;
    memset(in, 0, (size_t)(n + 1) * sizeof *in);
    for (int k = 0; k < total; ++k)
        ++in[nl->j[k] + 1];
    for (int g = 0; g < n; ++g)
        in[g + 1] += in[g];
    /* in[g] runs as the fill position of g, then everything moves up one place */
    for (int k = 0; k < total; ++k)
        nl->in_entry[in[nl->j[k]]++] = k;
    for (int g = n; g > 0; --g)
        in[g] = in[g - 1];
    in[0] = 0;
    nl->in_ready = 1;
}

static int build_walls(SimWorld *world, const HistoryRecord *records, int record_count)
{
    WallList *wl = &world->wl;
    wl->count = 0;
    if (world->wall_count == 0)
        return 0;
    for (int i = 0; i < world->mobile_count; ++i) {
        double cut = world->radius[i] + world->skin;
        for (int w = 0; w < world->wall_count; ++w) {
            if (sim_wall_distance2(&world->walls[w], world->x[i], world->y[i], world->radius[i]) >=
                cut * cut)
                continue;
            if (wl->count >= wl->capacity && wall_list_reserve(world, 2 * wl->capacity + 64) != 0)
                return -1;
            int k = wl->count++;
            int sw = world->walls[w].species;
            wl->grain[k] = i;
            wl->wall[k] = w;
            wl->pair[k] = (uint8_t)(world->species[i] * SIM_MAX_SPECIES + sw);
            wl->gamma[k] = pair_gamma(world, world->species[i], sw, world->inv_mass[i], 0.0);
            if (world->has_history) {
                uint64_t key = ((uint64_t)world->id[i] << 32) | (uint32_t)w;
                const HistoryRecord *h =
                    record_count ? record_find(records, record_count, key) : NULL;
                wl->hist_t[k] = h ? h->t : 0.0;
                wl->hist_r[k] = h ? h->r : 0.0;
            }
        }
    }
    return 0;
}

int sim_neighbour_install(SimWorld *world, const SimListArrays *l)
{
    const int mobile = world->mobile_count, n = world->count;
    NeighbourList *nl = &world->nl;
    if (l->start[0] != 0 || l->start[mobile] != l->pairs)
        return -1;
    for (int i = 0; i < mobile; ++i)
        if (l->start[i + 1] < l->start[i])
            return -1;
    if (list_reserve(world, l->pairs + 1) != 0 || wall_list_reserve(world, l->wall_pairs + 1) != 0)
        return -1;
    for (int i = 0; i < mobile; ++i) {
        nl->start[i] = l->start[i];
        for (int k = l->start[i]; k < l->start[i + 1]; ++k) {
            const int j = l->j[k];
            if (j <= i || j >= n)
                return -1;
            const int si = world->species[i], sj = world->species[j];
            nl->j[k] = j;
            nl->owner[k] = i;
            nl->pair[k] = (uint8_t)(si * SIM_MAX_SPECIES + sj);
            nl->gamma[k] = pair_gamma(world, si, sj, world->inv_mass[i], world->inv_mass[j]);
            if (l->shift)
                nl->shift[k] = l->shift[k];
            if (l->hist_t) {
                nl->hist_t[k] = l->hist_t[k];
                nl->hist_r[k] = l->hist_r[k];
            }
        }
    }
    nl->start[mobile] = l->pairs;
    WallList *wl = &world->wl;
    for (int k = 0; k < l->wall_pairs; ++k) {
        const int i = l->wall_grain[k], w = l->wall[k];
        if (i < 0 || i >= mobile || w < 0 || w >= world->wall_count)
            return -1;
        const int sw = world->walls[w].species;
        wl->grain[k] = i;
        wl->wall[k] = w;
        wl->pair[k] = (uint8_t)(world->species[i] * SIM_MAX_SPECIES + sw);
        wl->gamma[k] = pair_gamma(world, world->species[i], sw, world->inv_mass[i], 0.0);
        if (l->wall_hist_t) {
            wl->hist_t[k] = l->wall_hist_t[k];
            wl->hist_r[k] = l->wall_hist_r[k];
        }
    }
    wl->count = l->wall_pairs;
    sim_neighbour_build_incoming(world);
    return 0;
}

/* History records of the current lists (for checkpoints): `*records` and `*walls` are malloc'd.
 * -1 when out of memory. */
int sim_neighbour_history(const SimWorld *world, void **records, int *count, void **walls,
                          int *wall_count)
{
    HistoryRecord *w = NULL;
    int status;
    *records = collect_history(world, count, &w, wall_count, &status);
    *walls = w;
    return status;
}

/* Installs saved records (arrays of {uint64 key, double t, double r}) for the next build. */
int sim_neighbour_stash_records(SimWorld *world, const void *records, int count, const void *walls,
                                int wall_count)
{
    struct HistoryStash *s = calloc(1, sizeof *s);
    if (!s)
        return -1;
    s->records = malloc((size_t)(count > 0 ? count : 1) * sizeof *s->records);
    s->walls = malloc((size_t)(wall_count > 0 ? wall_count : 1) * sizeof *s->walls);
    if (!s->records || !s->walls) {
        free(s->records);
        free(s->walls);
        free(s);
        return -1;
    }
    memcpy(s->records, records, (size_t)count * sizeof *s->records);
    memcpy(s->walls, walls, (size_t)wall_count * sizeof *s->walls);
    s->count = count;
    s->wall_count = wall_count;
    qsort(s->records, (size_t)count, sizeof *s->records, record_compare);
    qsort(s->walls, (size_t)wall_count, sizeof *s->walls, record_compare);
    if (world->stash) {
        free(world->stash->records);
        free(world->stash->walls);
        free(world->stash);
    }
    world->stash = s;
    return 0;
}

int sim_neighbour_stash_history(SimWorld *world)
{
    struct HistoryStash *s = calloc(1, sizeof *s);
    if (!s)
        return -1;
    int status;
    s->records = collect_history(world, &s->count, &s->walls, &s->wall_count, &status);
    if (status != 0) {
        free(s);
        return -1;
    }
    if (world->stash) { /* an older stash is superseded */
        free(world->stash->records);
        free(world->stash->walls);
        free(world->stash);
    }
    world->stash = s;
    return 0;
}

void sim_neighbour_build(SimWorld *world)
{
    int record_count, wall_record_count;
    HistoryRecord *wall_records, *records;
    if (world->stash) {
        records = world->stash->records;
        record_count = world->stash->count;
        wall_records = world->stash->walls;
        wall_record_count = world->stash->wall_count;
        free(world->stash);
        world->stash = NULL;
    } else {
        int status;
        records = collect_history(world, &record_count, &wall_records, &wall_record_count, &status);
        if (status != 0)
            sim_world_out_of_memory(world, "collecting the contact history");
    }
    world->drop_history = 0;
    int failed = world->out_of_memory != NULL || sim_world_compact(world) != 0;

    if (world->effects & SIM_EFFECT_PERIODIC_X) { /* wrap mobile grains into [x0, x1) */
        const double x0 = world->def.domain_x0, span = world->def.domain_x1 - x0;
        for (int i = 0; i < world->mobile_count; ++i) {
            double x = world->x[i];
            if (x < x0 || x >= x0 + span) {
                double wrapped = x - span * floor((x - x0) / span);
                if (!(wrapped < x0 + span)) /* rounding at the upper edge */
                    wrapped = x0;
                world->x[i] = wrapped;
            }
        }
    }

    /* cell_items and cell_of hold capacity entries (sim_grains_reserve) */
    failed = failed || grid_setup(world) != 0;
    if (!failed) {
        grid_fill(world);
        failed = spatial_sort(world) != 0;
    }
    world->nl.in_ready = 0;
    world->nl.plan.count = 0;
    if (!failed) {
        grid_fill(world); /* same cells, new indices */
        failed = build_pairs(world, records, record_count) != 0 ||
                 build_walls(world, wall_records, wall_record_count) != 0;
        if (!failed)
            sim_neighbour_build_incoming(world);
    }
    free(records);
    free(wall_records);
    if (failed) { /* empty lists: every reader stays in bounds; the step reports the failure */
        memset(world->nl.start, 0, (size_t)(world->mobile_count + 1) * sizeof *world->nl.start);
        world->wl.count = 0;
        world->nl.in_ready = 0; /* the contact pass takes the serial scatter */
        world->nl.plan.count = 0;
        sim_world_out_of_memory(world, "the neighbour build");
    }

    memcpy(world->x_ref, world->x, (size_t)world->count * sizeof(double));
    memcpy(world->y_ref, world->y, (size_t)world->count * sizeof(double));
    world->wall_shift = 0.0;
    world->need_rebuild = 0;
    ++world->rebuilds;
}

/* Largest overlap ratio xi / d_min between two grains of a definition (set-up check), found with
 * the same cell grid as the neighbour build. Coincident centres count as infinite overlap; NAN
 * when out of memory. */
double sim_def_worst_overlap(const SimWorldDef *def, int *first, int *second)
{
    const SimGrainSet *g = &def->grains;
    SimWorld t;
    memset(&t, 0, sizeof t);
    *first = *second = -1;
    if (g->count < 2)
        return 0.0;
    size_t n = (size_t)g->count;
    t.count = g->count;
    t.effects = def->effects & SIM_EFFECT_PERIODIC_X;
    t.def.domain_x0 = def->domain_x0;
    t.def.domain_x1 = def->domain_x1;
    t.x = malloc(n * sizeof(double));
    t.y = malloc(n * sizeof(double));
    t.cell_items = malloc(n * sizeof(int));
    t.cell_of = malloc(n * sizeof(int));
    if (!t.x || !t.y || !t.cell_items || !t.cell_of) {
        free(t.x);
        free(t.y);
        free(t.cell_items);
        free(t.cell_of);
        return NAN;
    }
    double r_max = 0.0;
    for (int i = 0; i < g->count; ++i) {
        t.x[i] = g->x[i];
        t.y[i] = g->y[i];
        r_max = g->radius[i] > r_max ? g->radius[i] : r_max;
    }
    if (t.effects) { /* wrap into the domain as the build does */
        const double x0 = def->domain_x0, span = def->domain_x1 - x0;
        for (int i = 0; i < g->count; ++i)
            t.x[i] = t.x[i] - span * floor((t.x[i] - x0) / span);
    }
    t.cell_size = 2.0 * r_max;
    if (grid_setup(&t) != 0) {
        free(t.x);
        free(t.y);
        free(t.cell_items);
        free(t.cell_of);
        free(t.cell_start);
        return NAN;
    }
    grid_fill(&t);
    const double span = def->domain_x1 - def->domain_x0;
    double worst = 0.0;
    for (int i = 0; i < g->count; ++i) {
        int fixed_i = g->flags && (g->flags[i] & SIM_GRAIN_FIXED);
        int c = t.cell_of[i], cx = c % t.ncx, cy = c / t.ncx;
        for (int oy = -1; oy <= 1; ++oy)
            for (int ox = -1; ox <= 1; ++ox) {
                int nx = cx + ox, ny = cy + oy;
                double shift = 0.0;
                if (ny < 0 || ny >= t.ncy)
                    continue;
                if (nx < 0 || nx >= t.ncx) {
                    if (!t.effects)
                        continue;
                    shift = nx < 0 ? -span : span;
                    nx = nx < 0 ? t.ncx - 1 : 0;
                }
                int cell = ny * t.ncx + nx;
                for (int q = t.cell_start[cell]; q < t.cell_start[cell + 1]; ++q) {
                    int j = t.cell_items[q];
                    if (j <= i || (fixed_i && g->flags && (g->flags[j] & SIM_GRAIN_FIXED)))
                        continue;
                    double dx = t.x[j] + shift - t.x[i], dy = t.y[j] - t.y[i];
                    double d = sqrt(dx * dx + dy * dy), rs = g->radius[i] + g->radius[j];
                    if (d >= rs)
                        continue;
                    double dmin = 2.0 * (g->radius[i] < g->radius[j] ? g->radius[i] : g->radius[j]);
                    double ratio = d > 0.0 ? (rs - d) / dmin : (double)INFINITY;
                    if (ratio > worst) {
                        worst = ratio;
                        *first = i;
                        *second = j;
                    }
                }
            }
    }
    free(t.x);
    free(t.y);
    free(t.cell_items);
    free(t.cell_of);
    free(t.cell_start);
    return worst;
}
