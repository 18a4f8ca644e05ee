/* SPDX-License-Identifier: MIT */
/* contact_pass.c: the contact kernel, written once and instantiated per combination of the declared
 * laws, so that no per-contact `if` tests a disabled effect (the `key` argument is a compile-time
 * constant in every instantiation and the branches fold away). This file is compiled once per
 * instruction set (sim/CMakeLists.txt: SSE2, AVX2, AVX-512; its external names carry the set's
 * suffix, SIM_ISA_SYMBOL), with part of the folded keys, and again as contact_pass_upper.c with
 * the others (KEYS_LOWER, KEYS_UPPER below); sim/isa.c picks one copy at run time
 * (docs/dev/isa.md).
 *
 * Conventions (000 eqs. 3.1-3.5): n points from i to j, s = (n_y, -n_x),
 * v_s = (v_j - v_i).s + omega_i r_i + omega_j r_j. The force on i is -F_n n + F_t s, on j the
 * opposite; both torques are -r F_t (000 eq. 4.4; 004 §1.6). */
#include "sim/contact_scalar.h"
#include "sim/walls.h"

/* Vector values pass between static, always-inlined functions only: no ABI is exposed, so GCC's
 * note that 32-byte vectors change the ABI without AVX (builds without -march) does not apply. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

#include <math.h>
#include <string.h>

/* SIM_LANES contacts at a time (GCC/Clang vector extensions: SSE2, AVX or AVX-512 code as the
 * target allows, plain scalar code elsewhere). Bit operations give abs and copysign exactly. */
enum { SIM_LANES = 4 };

typedef double VecD __attribute__((vector_size(SIM_LANES * sizeof(double))));
typedef int64_t VecM __attribute__((vector_size(SIM_LANES * sizeof(int64_t))));
#define SIGN_BITS ((VecM){INT64_MIN, INT64_MIN, INT64_MIN, INT64_MIN})

KERNEL VecD sel_v(VecM m, VecD a, VecD b)
{
    return (VecD)((m & (VecM)a) | (~m & (VecM)b));
}

KERNEL VecD min_v(VecD a, VecD b)
{
    return sel_v(a < b, a, b);
}

KERNEL VecD abs_v(VecD a)
{
    return (VecD)((VecM)a & ~SIGN_BITS);
}

KERNEL VecD copysign_v(VecD magnitude, VecD sign)
{
    return (VecD)(((VecM)magnitude & ~SIGN_BITS) | ((VecM)sign & SIGN_BITS));
}

KERNEL VecD sqrt_v(VecD a)
{
    VecD r;
    for (int l = 0; l < SIM_LANES; ++l)
        r[l] = sqrt(a[l]);
    return r;
}

#define LAW_T     VecD
#define LAW(name) name##_v
#define LAW_ZERO  ((VecD){0.0, 0.0, 0.0, 0.0})
#define LAW_ONE   ((VecD){1.0, 1.0, 1.0, 1.0})
#include "sim/contact_laws.h"
#undef LAW_T
#undef LAW
#undef LAW_ZERO
#undef LAW_ONE

/* Lane l of the result is a[index[l]]. */
KERNEL VecD gather(const double *restrict a, const int *restrict index)
{
    VecD r;
    for (int l = 0; l < SIM_LANES; ++l)
        r[l] = a[index[l]];
    return r;
}

/* Lane l is field `off` (bytes) of pairs[index[l]]. */
KERNEL VecD gather_pair(const unsigned key, const PairParams *restrict pairs,
                        const int *restrict index, size_t off)
{
    VecD r;
    for (int l = 0; l < SIM_LANES; ++l)
        r[l] = *(const double *)((const char *)&pairs[(key & KEY_UNIFORM) ? 0 : index[l]] + off);
    return r;
}

/* Per-entry arrays: a full block (lanes == SIM_LANES, a constant in the main loop) holds
 * consecutive entries and moves as one vector; a short final block lane by lane. */
KERNEL VecD load(const double *restrict a, const int *restrict entry, const int lanes)
{
    VecD r;
    if (lanes == SIM_LANES) {
        memcpy(&r, a + entry[0], sizeof r);
        return r;
    }
    return gather(a, entry);
}

KERNEL void store(double *restrict a, const int *restrict entry, const int lanes, VecD v)
{
    if (lanes == SIM_LANES) {
        memcpy(a + entry[0], &v, sizeof v);
        return;
    }
    for (int l = 0; l < lanes; ++l)
        a[entry[l]] = v[l];
}

/* Where a pass writes the contacts' new history (tangential spring, rolling torque): in place,
 * or (the fused pass) into the spare arrays, swapped in once the pass has completed. */
typedef struct History {
    double *t, *r;
} History;

/* Where phase 1 puts its per-entry results and phase 2 reads them: entry k's four results (fx,
 * fy, f_t, M) at base[c * stride + k - k0], c = 0..3. nl.out whole for the threaded reduction
 * (which reads any entry); a block of FUSED_BLOCK entries on the stack for the one-thread passes,
 * which scatter each block while it is in L1: results streamed through the list-sized nl.out cost
 * two memory transfers of 24-32 bytes per entry and step on a pile larger than the cache. */
typedef struct Results {
    double *base;
    size_t stride;
    int k0;
} Results;

KERNEL Results results_whole(const SimWorld *world)
{
    return (Results){world->nl.out, (size_t)world->nl.capacity, 0};
}

/* Entries per block of the one-thread passes (a block's results: 16 KiB). */
enum { FUSED_BLOCK = 512 };

/* The results of the block of entries from k0 on, in `block` (4 * FUSED_BLOCK doubles). */
KERNEL Results results_block(double *block, const int k0)
{
    return (Results){block, FUSED_BLOCK, k0};
}

/* The grain-grain pass runs in two phases over the half list (style: data-parallel first, then
 * the scatter).
 * 1. pair_range: every entry k on its own, in one flat loop without branches, so that the compiler
 *    vectorises it (gathers of the partners' state, masks for the entries not in contact). Its
 *    results (`Results`): the force on j along x and y (the force on i is minus that), f_t, M.
 * 2. accumulate: adds them to the grains in the order of the scalar loop, so the sums (and the
 *    results, to the bit) do not depend on the vector width. */
/* Entries entry[0..SIM_LANES) of the half list (the last ones repeated in a short final block;
 * only the first `lanes` results are stored). */
KERNEL void pair_block(SimWorld *world, const unsigned key, const int *restrict entry,
                       const int lanes, const History out, const Results res)
{
    const size_t cap = res.stride;
    int slot[SIM_LANES];
    for (int l = 0; l < SIM_LANES; ++l)
        slot[l] = entry[l] - res.k0;
    const double dt = world->contact_dt;
    const unsigned law = key & KEY_TANGENTIAL;
    NeighbourList *nl = &world->nl;
    int i[SIM_LANES], j[SIM_LANES], p[SIM_LANES];
    for (int l = 0; l < SIM_LANES; ++l) {
        i[l] = nl->owner[entry[l]];
        j[l] = nl->j[entry[l]];
        p[l] = nl->pair[entry[l]];
    }
    VecD dx = gather(world->x, j) - gather(world->x, i);
    if (key & KEY_PERIODIC)
        dx += load(nl->shift, entry, lanes);
    const VecD dy = gather(world->y, j) - gather(world->y, i);
    const VecD ri = gather(world->radius, i), rj = gather(world->radius, j);
    const VecD rs = ri + rj;
    const VecD d2 = dx * dx + dy * dy;
    const VecM touching = d2 < rs * rs;
    const VecD d = sqrt_v(d2);
    const VecD inv = 1.0 / d;
    const VecD nx = dx * inv, ny = dy * inv;
    const VecD overlap = rs - d; /* 000 eq. 3.1 */
    const VecD dvx = gather(world->vx, j) - gather(world->vx, i);
    const VecD dvy = gather(world->vy, j) - gather(world->vy, i);
    const VecD v_n = dvx * nx + dvy * ny; /* 000 eq. 3.4 */
    const VecD k_n = gather_pair(key, world->pairs, p, offsetof(PairParams, k_n));
    VecD f_el;
    const VecD f_n = normal_force_v(key, k_n, load(nl->gamma, entry, lanes), overlap, v_n,
                                    0.5 * world->dt, &f_el);
    /* Event-aware onset: a pair about to touch within half a step already has a (weighted) normal
     * force; the tangential and rolling laws still act on overlapping pairs only. */
    const VecM acting = (key & KEY_EVENT) ? (touching | (f_n != 0.0)) : touching;
    VecD fxk = -f_n * nx, fyk = -f_n * ny;
    VecD f_t = ((VecD){0.0, 0.0, 0.0, 0.0});
    VecD wi = ((VecD){0.0, 0.0, 0.0, 0.0}), wj = ((VecD){0.0, 0.0, 0.0, 0.0});
    if (KEY_ROTATION(key)) {
        wi = gather(world->omega, i);
        wj = gather(world->omega, j);
    }
    if (law != SIM_TANGENTIAL_NONE) {
        const VecD sx = ny, sy = -nx;   /* 000 eq. 3.3 */
        VecD v_s = dvx * sx + dvy * sy; /* 000 eq. 3.5 */
        v_s += wi * ri + wj * rj;
        const VecD mu = gather_pair(key, world->pairs, p, offsetof(PairParams, mu));
        VecD k_t = ((VecD){0.0, 0.0, 0.0, 0.0}), gamma_s = ((VecD){0.0, 0.0, 0.0, 0.0}),
             spring = ((VecD){0.0, 0.0, 0.0, 0.0});
        if (law == SIM_TANGENTIAL_SPRING) {
            k_t = gather_pair(key, world->pairs, p, offsetof(PairParams, k_t));
            gamma_s = gather_pair(key, world->pairs, p, offsetof(PairParams, gamma_t));
            spring = load(nl->hist_t, entry, lanes);
        } else {
            gamma_s = gather_pair(key, world->pairs, p, offsetof(PairParams, gamma_s));
        }
        f_t = tangential_force_v(key, k_t, mu, gamma_s, v_s, f_n, f_el, dt, &spring);
        if (key & KEY_EVENT)
            f_t = sel_v(touching, f_t, ((VecD){0.0, 0.0, 0.0, 0.0}));
        if (law == SIM_TANGENTIAL_SPRING)
            store(out.t, entry, lanes, sel_v(touching, spring, ((VecD){0.0, 0.0, 0.0, 0.0})));
        fxk += f_t * sx;
        fyk += f_t * sy;
    }
    if (key & KEY_ROLLING) {
        VecD k_r, mu_r;
        if (key & KEY_CHORD) {
            const VecD chord = disk_chord_v(d, ri, rj);
            k_r = k_n * chord * chord;
            mu_r = gather_pair(key, world->pairs, p, offsetof(PairParams, mu)) * chord;
        } else {
            k_r = gather_pair(key, world->pairs, p, offsetof(PairParams, k_r));
            mu_r = gather_pair(key, world->pairs, p, offsetof(PairParams, mu_r));
        }
        VecD m_r = load(nl->hist_r, entry, lanes);
        const VecD m = rolling_torque_v(k_r, mu_r, wj - wi, f_el, dt, &m_r);
        store(out.r, entry, lanes, sel_v(touching, m_r, ((VecD){0.0, 0.0, 0.0, 0.0})));
        store(res.base + 3 * cap, slot, lanes, sel_v(touching, m, ((VecD){0.0, 0.0, 0.0, 0.0})));
    }
    store(res.base, slot, lanes, sel_v(acting, fxk, ((VecD){0.0, 0.0, 0.0, 0.0})));
    store(res.base + cap, slot, lanes, sel_v(acting, fyk, ((VecD){0.0, 0.0, 0.0, 0.0})));
    if (KEY_ROTATION(key))
        store(res.base + 2 * cap, slot, lanes, sel_v(touching, f_t, ((VecD){0.0, 0.0, 0.0, 0.0})));
}

/* Entries [k0, k1) of the half list: k0 is a multiple of SIM_LANES and so is k1 unless it is
 * the end of the list (sim_parallel_ranges' bounds), so only the list's last block is short. */
KERNEL void pair_range(SimWorld *world, const unsigned key, const int k0, const int k1,
                       const History out, const Results res)
{
    int entry[SIM_LANES];
    int k = k0;
    for (; k + SIM_LANES <= k1; k += SIM_LANES) {
        for (int l = 0; l < SIM_LANES; ++l)
            entry[l] = k + l;
        pair_block(world, key, entry, SIM_LANES, out, res);
    }
    if (k < k1) {
        for (int l = 0; l < SIM_LANES; ++l)
            entry[l] = k + l < k1 ? k + l : k1 - 1;
        pair_block(world, key, entry, k1 - k, out, res);
    }
}

/* The history arrays the pass updates in place. */
KERNEL History history_in_place(const SimWorld *world)
{
    return (History){world->nl.hist_t, world->nl.hist_r};
}

/* Phase 2. The scalar loop `for i: sum_i = 0; for k of i: sum_i += f_k; f_j -= f_k; then
 * f_i += sum_i` has a short inner loop of random trip count (a mispredicted exit per grain). Here
 * the entries run flat: the partial sums restart at each new owner (a select, not a branch), and
 * the sum just finished goes to its grain at the first entry of the next owner (a select of the
 * stored value). A partner is always above its owner (the half list), so every f_j -= f_k that
 * reaches grain g comes from an owner below g, before g's own entries: adding g's sum when its
 * run ends is the scalar loop's order, and the results are the same to the bit. (A grain that
 * owns no entry gets no `+= 0.0`: its sum starts at +0.0 and subtractions from +0.0 never give
 * -0.0, so adding 0.0 would leave its bits as they are.) nl.out keeps the per-entry results. */
/* The scatter's running state between two ranges of entries: the partial sums of the owner whose
 * entries the last range ended in, and that owner. */
typedef struct Scatter {
    double x, y, t;
    int owner;
} Scatter;

/* `partner`: where entry k's results are subtracted (nl.j, or a part's targets, which send the
 * entries that reach a shared grain to the part's sink). */
KERNEL void scatter_range(SimWorld *world, const unsigned key, const int k0, const int k1,
                          const Results res, Scatter *state, const int *restrict partner)
{
    const size_t cap = res.stride;
    const double *restrict radius = world->radius;
    double *restrict fx = world->fx, *restrict fy = world->fy, *restrict torque = world->torque;
    const int *restrict owner = world->nl.owner;
    const double *restrict out_x = res.base - res.k0, *restrict out_y = out_x + cap;
    const double *restrict out_t = out_x + 2 * cap, *restrict out_m = out_x + 3 * cap;
    const unsigned law = key & KEY_TANGENTIAL;

    double sum_x = state->x, sum_y = state->y, sum_t = state->t;
    int previous = state->owner;
    for (int k = k0; k < k1; ++k) {
        const int i = owner[k], j = partner[k];
        const int first = i != previous;
        const double px = fx[previous], py = fy[previous];
        fx[previous] = first ? px + sum_x : px;
        fy[previous] = first ? py + sum_y : py;
        sum_x = first ? 0.0 : sum_x;
        sum_y = first ? 0.0 : sum_y;
        if (KEY_ROTATION(key)) {
            const double pt = torque[previous];
            torque[previous] = first ? pt + sum_t : pt;
            sum_t = first ? 0.0 : sum_t;
        }
        previous = i;
        const double fxk = out_x[k], fyk = out_y[k];
        if (KEY_ROTATION(key)) {
            if (law != SIM_TANGENTIAL_NONE) {
                const double f_t = out_t[k];
                sum_t -= radius[i] * f_t; /* 000 eq. 4.4 */
                torque[j] -= radius[j] * f_t;
            }
            if (key & KEY_ROLLING) {
                const double m = out_m[k];
                sum_t -= m;
                torque[j] += m;
            }
        }
        sum_x += fxk;
        sum_y += fyk;
        fx[j] -= fxk;
        fy[j] -= fyk;
    }
    *state = (Scatter){sum_x, sum_y, sum_t, previous};
}

/* The last owner's sum, once every entry is scattered. */
KERNEL void scatter_finish(SimWorld *world, const unsigned key, const Scatter *state)
{
    world->fx[state->owner] += state->x;
    world->fy[state->owner] += state->y;
    if (KEY_ROTATION(key))
        world->torque[state->owner] += state->t;
}

/* Phase 1 then phase 2 over each block of FUSED_BLOCK entries of the list. */
KERNEL void grain_pass(SimWorld *world, const unsigned key)
{
    const int total = world->nl.start[world->mobile_count];
    if (total == 0)
        return;
    double block[4 * FUSED_BLOCK] __attribute__((aligned(64)));
    Scatter state = {0.0, 0.0, 0.0, world->nl.owner[0]};
    for (int k0 = 0; k0 < total; k0 += FUSED_BLOCK) {
        const int k1 = total - k0 > FUSED_BLOCK ? k0 + FUSED_BLOCK : total;
        const Results res = results_block(block, k0);
        pair_range(world, key, k0, k1, history_in_place(world), res);
        scatter_range(world, key, k0, k1, res, &state, world->nl.j);
    }
    scatter_finish(world, key, &state);
}

/* The one-thread contact pass with the velocity-Verlet drift fused into it
 * (sim_world_drift_forces_at): the entries run in blocks of FUSED_BLOCK, each block's phase 1 and
 * phase 2 in turn, and before a block, `drift` moves the mobile grains up to the largest partner it
 * names (a partner is always above its owner, so its owners too). The drift also clears the grains'
 * forces after reading them. Every grain is then drifted before any entry reads it, and cleared
 * before any entry adds to it: the same operations on the same values as the drift of every grain
 * followed by the whole pass, so the same bits, with each grain's data still in cache from its
 * drift when its entries use it (on a large pile the separate drift streamed every grain array from
 * memory once more per step). The new history goes to the spare arrays, swapped in at the end (only
 * those the key's laws write: the other stays as the list build left it). Returns 0, or 1 when a
 * drift reports a grain past the rebuild threshold: the drift then runs to the last grain, the
 * history is as it was, and the caller rebuilds the list and evaluates the forces anew (what the
 * separate passes do), discarding this pass's sums. */
/* A fused pass has completed: its new history (the arrays the key's laws write) becomes the
 * list's. */
KERNEL void swap_history(NeighbourList *nl, const unsigned key)
{
    if ((key & KEY_TANGENTIAL) == SIM_TANGENTIAL_SPRING) {
        double *t = nl->hist_t;
        nl->hist_t = nl->hist_t_spare;
        nl->hist_t_spare = t;
    }
    if (key & KEY_ROLLING) {
        double *r = nl->hist_r;
        nl->hist_r = nl->hist_r_spare;
        nl->hist_r_spare = r;
    }
}

/* What one run of the fused pass covers: the one-thread pass (every mobile grain, one part), or
 * part `part` of the plan (sim/parts.c). */
typedef struct FusedRun {
    int g0, g1;      /* its mobile grains, whose entries it runs and which it drifts */
    int front;       /* grains [g0, front) are drifted already (a part's head) */
    int part, parts; /* the heads of parts part + 1 .. parts - 1 are drifted before it reads them */
    const int *target;  /* where the scatter subtracts (scatter_range) */
    int slot, slot_end; /* the slots its entries that reach a shared grain fill, in entry order */
} FusedRun;

/* Copies the results of the block's entries that reach a shared grain to their slots. */
KERNEL int copy_slots(const PartPlan *pp, const unsigned key, int slot, const int slot_end,
                      const int k1, const Results res)
{
    const size_t cap = (size_t)pp->slot_capacity;
    for (; slot < slot_end && pp->slot_entry[slot] < k1; ++slot) {
        const int at = pp->slot_entry[slot] - res.k0;
        pp->slot_out[slot] = res.base[at];
        pp->slot_out[cap + slot] = res.base[res.stride + at];
        if (KEY_ROTATION(key))
            pp->slot_out[2 * cap + slot] = res.base[2 * res.stride + at];
        if (key & KEY_ROLLING)
            pp->slot_out[3 * cap + slot] = res.base[3 * res.stride + at];
    }
    return slot;
}

/* The largest mobile partner of entries [k0, k1), or 0 (selects without a branch, so that the
 * loop vectorises: a branch on `j < mobile` cost a sixth of the pass, mispredicted). */
KERNEL int last_mobile_partner(const int *restrict partner, const int k0, const int k1,
                               const int mobile)
{
    int last = 0;
    for (int k = k0; k < k1; ++k) {
        const int j = partner[k] < mobile ? partner[k] : 0;
        last = j > last ? j : last;
    }
    return last;
}

/* The contact pass with the velocity-Verlet drift fused into it (sim_world_drift_forces_at), over
 * the entries of grains [g0, g1): the entries run in blocks of FUSED_BLOCK, each block's phase 1
 * and phase 2 in turn, and before a block, `drift` moves the grains up to the largest mobile
 * grain it reads, owner or partner (rounded up to a multiple of `align`; fixed grains do not
 * drift, and a fixed partner no longer drifts every grain at once). The drift
 * also clears the grains' forces after reading them. Every grain is then drifted before any entry
 * reads it, and cleared before any entry adds to it: the same operations on the same values as
 * the drift of every grain followed by the whole pass, so the same bits, with each grain's data
 * still in cache from its drift when its entries use it (on a large pile the separate drift
 * streamed every grain array from memory once more per step). The new history goes to the spare
 * arrays, swapped in once every run has completed (only those the key's laws write: the other
 * stays as the list build left it). Returns 0, or 1 when a drift reports a grain past the rebuild
 * threshold (or, on several threads, another part has): the drift then runs to g1, the history
 * is as it was, and the caller rebuilds the list and evaluates the forces anew (what the separate
 * passes do), discarding this pass's sums. */
KERNEL int fused_run(SimWorld *world, const unsigned key, RangeFn *drift, const int align,
                     FusedRun run)
{
    NeighbourList *nl = &world->nl;
    PartPlan *pp = &nl->plan;
    const int mobile = world->mobile_count, k0 = nl->start[run.g0], k1 = nl->start[run.g1];
    const History spare = {nl->hist_t_spare, nl->hist_r_spare};
    Scatter state = {0.0, 0.0, 0.0, k1 > k0 ? nl->owner[k0] : 0};
    int front = run.front, next = run.part + 1, moved = 0;
    double block[4 * FUSED_BLOCK] __attribute__((aligned(64)));
    for (int b0 = k0; b0 < k1; b0 += FUSED_BLOCK) {
        const int b1 = k1 - b0 > FUSED_BLOCK ? b0 + FUSED_BLOCK : k1;
        /* the block reads its owners too: a block whose partners are all fixed grains names
         * no mobile partner, and its owners must still be drifted before it reads them */
        const int partner_last = last_mobile_partner(nl->j, b0, b1, mobile);
        const int last = partner_last > nl->owner[b1 - 1] ? partner_last : nl->owner[b1 - 1];
        if (last >= front && front < run.g1) {
            int to = (last / align + 1) * align;
            to = to < run.g1 ? to : run.g1;
            moved |= drift(world, front, to);
            front = to;
        }
        for (; next < run.parts && last >= pp->first[next]; ++next)
            moved |= sim_parts_drift_head(world, next);
        if (run.parts > 1 && !moved)
            moved = atomic_load_explicit(&pp->abort, memory_order_relaxed);
        if (moved)
            break;
        const Results res = results_block(block, b0);
        pair_range(world, key, b0, b1, spare, res);
        run.slot = copy_slots(pp, key, run.slot, run.slot_end, b1, res);
        scatter_range(world, key, b0, b1, res, &state, run.target);
    }
    if (moved && run.parts > 1)
        atomic_store_explicit(&pp->abort, 1, memory_order_relaxed);
    if (front < run.g1)
        moved |= drift(world, front, run.g1);
    if (!moved && k1 > k0)
        scatter_finish(world, key, &state);
    return moved;
}

/* fused_run for one key (one copy per key, called by both passes below). */
typedef int FusedRunFn(SimWorld *world, RangeFn *drift, int align, FusedRun run);

/* One thread: a single run over every mobile grain. */
KERNEL int fused_pass(SimWorld *world, const unsigned key, FusedRunFn *run, RangeFn *drift,
                      const int align)
{
    const FusedRun whole = {0, world->mobile_count, 0, 0, 1, world->nl.j, 0, 0};
    if (run(world, drift, align, whole))
        return 1;
    swap_history(&world->nl, key);
    return 0;
}

/* Several threads: part p of the plan, its head (shared grains) drifted first. */
KERNEL int fused_part(SimWorld *world, FusedRunFn *run, const int p)
{
    PartPlan *pp = &world->nl.plan;
    const int moved = sim_parts_drift_head(world, p);
    const FusedRun part = {pp->first[p], pp->first[p + 1],  pp->head[p],          p, pp->count,
                           pp->target,   pp->slot_first[p], pp->slot_first[p + 1]};
    const long long begin = sim_now_ns();
    const int rc = run(world, pp->drift, pp->align, part) | moved;
    if (!rc) { /* the cut by measurement (sim/parts.c); a pass cut short tells nothing */
        pp->begin_ns[p] += begin - pp->job_ns;
        pp->run_ns[p] += sim_now_ns() - begin;
        pp->entries[p] += world->nl.start[pp->first[p + 1]] - world->nl.start[pp->first[p]];
    }
    return rc;
}

/* The serial scatter's operations on a grain g from the entries whose partner is g, in the order
 * of list[from .. to) (ascending k): each entry's force subtracted, and its torque -r_g f_t then
 * +M. `out` holds the results in four arrays of `cap` (fx, fy, f_t, M), indexed by list's
 * values: nl.out by entry (the threaded gather) or the parts' slots (shared_fixup). */
KERNEL void subtract_partner_entries(const unsigned key, const double rg, const int *restrict list,
                                     const int from, const int to, const double *restrict out,
                                     const size_t cap, double *fxg, double *fyg, double *tg)
{
    const unsigned law = key & KEY_TANGENTIAL;
    double x = *fxg, y = *fyg, t = *tg;
    for (int q = from; q < to; ++q) {
        const int e = list[q];
        if (KEY_ROTATION(key)) {
            if (law != SIM_TANGENTIAL_NONE)
                t -= rg * out[2 * cap + e];
            if (key & KEY_ROLLING)
                t += out[3 * cap + e];
        }
        x -= out[e];
        y -= out[cap + e];
    }
    *fxg = x;
    *fyg = y;
    *tg = t;
}

/* After the parts: each shared grain gets its slots, in ascending k, subtracted from its cleared
 * force (+0.0, as the drift or clear_forces left it), then its own sum, which its part added to
 * that cleared force (so the force holds the sum itself): the serial scatter's operations in its
 * order (sim/parts.c). A grain that owns no entry gets no sum, as in the serial scatter. */
KERNEL void shared_fixup(SimWorld *world, const unsigned key)
{
    const PartPlan *pp = &world->nl.plan;
    const int mobile = world->mobile_count, *start = world->nl.start;
    for (int s = 0; s < pp->shared; ++s) {
        const int g = pp->shared_grain[s];
        double fxg = 0.0, fyg = 0.0, tg = 0.0;
        subtract_partner_entries(key, world->radius[g], pp->shared_slot, pp->shared_start[s],
                                 pp->shared_start[s + 1], pp->slot_out, (size_t)pp->slot_capacity,
                                 &fxg, &fyg, &tg);
        if (g < mobile && start[g + 1] > start[g]) {
            fxg += world->fx[g];
            fyg += world->fy[g];
            if (KEY_ROTATION(key))
                tg += world->torque[g];
        }
        world->fx[g] = fxg;
        world->fy[g] = fyg;
        if (KEY_ROTATION(key))
            world->torque[g] = tg;
    }
}

/* The fused pass on the plan's parts (run by `parts`, a per-key RangeFn over part indices). */
KERNEL int fused_parts(SimWorld *world, const unsigned key, RangeFn *parts, RangeFn *drift,
                       const int align)
{
    PartPlan *pp = &world->nl.plan;
    pp->drift = drift;
    pp->align = align;
    for (int p = 0; p < pp->count; ++p)
        atomic_store_explicit(&pp->head_state[p], 0, memory_order_relaxed);
    atomic_store_explicit(&pp->abort, 0, memory_order_relaxed);
    pp->job_ns = sim_now_ns();
    if (sim_parallel_units(world, parts, pp->count))
        return 1;
    ++pp->timed;
    shared_fixup(world, key);
    swap_history(&world->nl, key);
    return 0;
}

/* Phase 2 for threads (sim_world_set_threads): the same sums per grain, gathered instead of
 * scattered, so that grains [g0, g1) are written by one thread only. The serial loop above gives
 * grain g first the entries whose partner is g, in ascending k (each subtracted from fx[g], and
 * for torques -r_g f_t then +M, in that order), and then, for a mobile g, the partial sum of its
 * own entries (started at 0.0, adding fx_k; torque -r_g f_t - M per entry), added once (0.0 when
 * it owns none). The transposed list (nl.in_start, in_entry) holds the partner entries in
 * ascending k, so every addition below is one of the serial loop's, in its order: the results
 * are the same bits for any split of the grains. nl.out is only read here. */
KERNEL void reduce_range(SimWorld *world, const unsigned key, const int g0, const int g1)
{
    const int mobile = world->mobile_count;
    const size_t cap = (size_t)world->nl.capacity;
    const double *restrict radius = world->radius;
    double *restrict fx = world->fx, *restrict fy = world->fy, *restrict torque = world->torque;
    const int *restrict start = world->nl.start;
    const int *restrict in_start = world->nl.in_start, *restrict in_entry = world->nl.in_entry;
    const double *restrict out_x = world->nl.out, *restrict out_y = world->nl.out + cap;
    const double *restrict out_t = world->nl.out + 2 * cap;
    const double *restrict out_m = world->nl.out + 3 * cap;
    const unsigned law = key & KEY_TANGENTIAL;
    for (int g = g0; g < g1; ++g) {
        const double rg = radius[g];
        double fxg = fx[g], fyg = fy[g], tg = KEY_ROTATION(key) ? torque[g] : 0.0;
        subtract_partner_entries(key, rg, in_entry, in_start[g], in_start[g + 1], world->nl.out,
                                 cap, &fxg, &fyg, &tg);
        if (g < mobile) {
            const int first = start[g], end = start[g + 1];
            double sum_x = 0.0, sum_y = 0.0, sum_t = 0.0;
            for (int k = first; k < end; ++k) {
                if (KEY_ROTATION(key)) {
                    if (law != SIM_TANGENTIAL_NONE)
                        sum_t -= rg * out_t[k];
                    if (key & KEY_ROLLING)
                        sum_t -= out_m[k];
                }
                sum_x += out_x[k];
                sum_y += out_y[k];
            }
            const int any = end > first;
            fxg += any ? sum_x : 0.0;
            fyg += any ? sum_y : 0.0;
            if (KEY_ROTATION(key))
                tg += any ? sum_t : 0.0;
        }
        fx[g] = fxg;
        fy[g] = fyg;
        if (KEY_ROTATION(key))
            torque[g] = tg;
    }
}

/* The force (fx, fy) of a grain on wall w at the point (qx, qy), with its normal part f_n, added
 * to the wall's load (sim.h SimWallLoad): in the wall list's order, serial, so the same bits for
 * any thread count. */
static inline void wall_load_add(SimWorld *world, int w, double fx, double fy, double f_n,
                                 double qx, double qy)
{
    const SimWall *wall = &world->walls[w];
    const int arc = wall->shape == SIM_WALL_ARC;
    const double cx = arc ? wall->center_x : 0.5 * (wall->x0 + wall->x1);
    const double cy = arc ? wall->center_y : 0.5 * (wall->y0 + wall->y1);
    double *load = &world->wall_load[4 * w];
    load[0] += fx;
    load[1] += fy;
    load[2] += f_n;
    load[3] += (qx - cx) * fy - (qy - cy) * fx;
    world->wall_touch[w] += 1;
}

/* A servo wall's contact's normal dashpot, dF_n/dv_n (gamma_n; Hertz gamma_n sqrt(xi): the
 * normal law above), projected on the wall's axis twice (the load's part along the axis from the
 * speed along it), added to the wall's damping (internal.h wall_damp; wall_body.c body_speed)
 * in the wall list's order, as the load. The event-aware onset's phi < 1 is not applied: an
 * overestimate only slows the implicit law, never flips it. */
static inline void wall_damping_add(SimWorld *world, int w, const unsigned key, double gamma_n,
                                    double overlap, double nx, double ny)
{
    const SimWallBody *b = &world->bodies[w];
    const double along = nx * b->axis_x + ny * b->axis_y;
    const double c = (key & KEY_HERTZ) ? gamma_n * sqrt(overlap) : gamma_n;
    world->wall_damp[w] += c * along * along;
}

/* Grain-wall contacts: the wall acts as a partner of infinite mass, zero radius, no spin. */
KERNEL void wall_pass(SimWorld *world, const unsigned key)
{
    const WallList *wl = &world->wl;
    const double dt = world->contact_dt;
    const unsigned law = key & KEY_TANGENTIAL;
    for (int w = 0; w < world->wall_count; ++w) {
        world->wall_load[4 * w] = world->wall_load[4 * w + 1] = 0.0;
        world->wall_load[4 * w + 2] = world->wall_load[4 * w + 3] = 0.0;
        world->wall_touch[w] = 0;
        if (world->wall_damp)
            world->wall_damp[w] = 0.0;
    }
    for (int k = 0; k < wl->count; ++k) {
        const int i = wl->grain[k], w = wl->wall[k];
        const double ri = world->radius[i];
        double nx, ny;
        const double d =
            sim_wall_geometry(&world->walls[w], world->x[i], world->y[i], ri, &nx, &ny);
        const int touching = d < ri;
        if (!touching) {
            if (law == SIM_TANGENTIAL_SPRING)
                wl->hist_t[k] = 0.0;
            if (key & KEY_ROLLING)
                wl->hist_r[k] = 0.0;
            if (!(key & KEY_EVENT))
                continue;
        }
        const double overlap = ri - d;
        double wvx, wvy; /* the wall's surface velocity at the contact point */
        sim_wall_velocity(world, w, world->x[i] + d * nx, world->y[i] + d * ny, &wvx, &wvy);
        const double dvx = wvx - world->vx[i];
        const double dvy = wvy - world->vy[i];
        const double v_n = dvx * nx + dvy * ny;
        const PairParams *p = &world->pairs[wl->pair[k]];
        double f_el;
        const double f_n =
            normal_force_d(key, p->k_n, wl->gamma[k], overlap, v_n, 0.5 * world->dt, &f_el);
        if ((key & KEY_EVENT) && !touching) { /* within half a step of touching: normal only */
            world->fx[i] -= f_n * nx;
            world->fy[i] -= f_n * ny;
            wall_load_add(world, w, f_n * nx, f_n * ny, f_n, world->x[i] + d * nx,
                          world->y[i] + d * ny);
            continue;
        }
        double fxk = -f_n * nx, fyk = -f_n * ny;
        const double wi = KEY_ROTATION(key) ? world->omega[i] : 0.0;
        if (law != SIM_TANGENTIAL_NONE) {
            const double sx = ny, sy = -nx;
            double v_s = dvx * sx + dvy * sy + wi * ri;
            double dummy = 0.0;
            double *xi_t = (law == SIM_TANGENTIAL_SPRING) ? &wl->hist_t[k] : &dummy;
            const double damping = law == SIM_TANGENTIAL_SPRING ? p->gamma_t : p->gamma_s;
            const double f_t =
                tangential_force_d(key, p->k_t, p->mu, damping, v_s, f_n, f_el, dt, xi_t);
            fxk += f_t * sx;
            fyk += f_t * sy;
            if (KEY_ROTATION(key))
                world->torque[i] -= ri * f_t;
        }
        if (key & KEY_ROLLING) {
            const double chord = (key & KEY_CHORD) ? 2.0 * sqrt(fmax(ri * ri - d * d, 0.0)) : 0.0;
            const double k_r = (key & KEY_CHORD) ? p->k_n * chord * chord : p->k_r;
            const double mu_r = (key & KEY_CHORD) ? p->mu * chord : p->mu_r;
            /* relative rolling against the wall's own turning (a drum's omega) */
            const double w_wall = world->wall_omega[w];
            const double rel = w_wall != 0.0 ? w_wall - wi : -wi;
            world->torque[i] -= rolling_torque_d(k_r, mu_r, rel, f_el, dt, &wl->hist_r[k]);
        }
        world->fx[i] += fxk;
        world->fy[i] += fyk;
        wall_load_add(world, w, -fxk, -fyk, f_n, world->x[i] + d * nx, world->y[i] + d * ny);
        if (world->wall_damp && world->bodies[w].servo && (f_n > 0.0 || !(key & KEY_CLIP)))
            wall_damping_add(world, w, key, wl->gamma[k], overlap, nx, ny);
    }
}

/* One instantiation per key = 8 * high + low: low = tangential law (0..2) | rolling (4);
 * high = periodic | hertz << 1 | clip << 2 | chord << 3 | event << 4, chord only with rolling,
 * event only without hertz (sim_world_create refuses the pair): 108 keys in four groups of 18
 * or 36. */
/* clang-format off */
#define KEYS_LOW(X, h)  X(h, 0) X(h, 1) X(h, 2) X(h, 4) X(h, 5) X(h, 6)
#define KEYS_ROLL(X, h) X(h, 4) X(h, 5) X(h, 6)
/* The linear normal law with the step onset, without tensile clipping and with it: every
 * shipped scene (scenes/) and every bench_sim law is one of these 36 keys. */
#define KEYS_LINEAR(X)                                                                  \
    KEYS_LOW(X, 0) KEYS_LOW(X, 1) KEYS_ROLL(X, 8) KEYS_ROLL(X, 9)
#define KEYS_LINEAR_CLIP(X)                                                             \
    KEYS_LOW(X, 4) KEYS_LOW(X, 5) KEYS_ROLL(X, 12) KEYS_ROLL(X, 13)
/* The Hertz normal law, and the event-aware onset (docs/accuracy.md). */
#define KEYS_HERTZ(X)                                                                   \
    KEYS_LOW(X, 2) KEYS_LOW(X, 3) KEYS_LOW(X, 6) KEYS_LOW(X, 7)                        \
    KEYS_ROLL(X, 10) KEYS_ROLL(X, 11) KEYS_ROLL(X, 14) KEYS_ROLL(X, 15)
#define KEYS_EVENT(X)                                                                   \
    KEYS_LOW(X, 16) KEYS_LOW(X, 17) KEYS_LOW(X, 20) KEYS_LOW(X, 21)                    \
    KEYS_ROLL(X, 24) KEYS_ROLL(X, 25) KEYS_ROLL(X, 28) KEYS_ROLL(X, 29)
#define KEYS_ALL(X) KEYS_LINEAR(X) KEYS_LINEAR_CLIP(X) KEYS_HERTZ(X) KEYS_EVENT(X)

/* Which keys are folded (one copy each, the key a constant), in this file (KEYS_LOWER) and in
 * contact_pass_upper.c (KEYS_UPPER), the two halves compiled side by side by a two-core build;
 * the others (KEYS_RARE) share one copy that reads the key from the world at run time (same
 * source, same bits). sim/CMakeLists.txt chooses (docs/dev/isa.md, "Folded keys"):
 * SIM_ISA_KEY_AT_RUN_TIME folds none (the SSE2 copy by default, the sanitized and fuzz builds),
 * SIM_ISA_FOLD_ALL_KEYS all 108 (SABLIER_FOLD_ALL_KEYS), and by default the 36 linear keys. */
#if defined(SIM_ISA_KEY_AT_RUN_TIME)
#define KEYS_LOWER(X)
#define KEYS_UPPER(X)
#define KEYS_RARE(X) KEYS_ALL(X)
#elif defined(SIM_ISA_FOLD_ALL_KEYS)
#define KEYS_LOWER(X) KEYS_LINEAR(X) KEYS_HERTZ(X)
#define KEYS_UPPER(X) KEYS_LINEAR_CLIP(X) KEYS_EVENT(X)
#define KEYS_RARE(X)
#define SIM_ISA_NO_RARE_KEYS 1
#else
#define KEYS_LOWER(X) KEYS_LINEAR(X)
#define KEYS_UPPER(X) KEYS_LINEAR_CLIP(X)
#define KEYS_RARE(X) KEYS_HERTZ(X) KEYS_EVENT(X)
#endif
/* clang-format on */

/* The passes of one key: KEY is an expression of `world` (every function's parameter), a constant
 * in the folded copies. */
#define DEFINE_PASS(name, KEY)                                                                     \
    static int pair_range_##name(SimWorld *world, int begin, int end)                              \
    {                                                                                              \
        if (world->def.species_count == 1)                                                         \
            pair_range(world, (KEY) | KEY_UNIFORM, begin, end, history_in_place(world),            \
                       results_whole(world));                                                      \
        else                                                                                       \
            pair_range(world, (KEY), begin, end, history_in_place(world), results_whole(world));   \
        return 0;                                                                                  \
    }                                                                                              \
    static int reduce_range_##name(SimWorld *world, int begin, int end)                            \
    {                                                                                              \
        reduce_range(world, (KEY), begin, end);                                                    \
        return 0;                                                                                  \
    }                                                                                              \
    static void grain_pass_##name(SimWorld *world)                                                 \
    {                                                                                              \
        if (world->threads > 1 && world->nl.in_ready) {                                            \
            sim_parallel_ranges(world, pair_range_##name, world->nl.start[world->mobile_count],    \
                                SIM_LANES);                                                        \
            sim_parallel_ranges(world, reduce_range_##name, world->count, 1);                      \
        } else if (world->def.species_count == 1) {                                                \
            grain_pass(world, (KEY) | KEY_UNIFORM);                                                \
        } else {                                                                                   \
            grain_pass(world, (KEY));                                                              \
        }                                                                                          \
    }                                                                                              \
    __attribute__((noinline)) static int fused_run_##name(SimWorld *world, RangeFn *drift,         \
                                                          int align, FusedRun run)                 \
    {                                                                                              \
        if (world->def.species_count == 1)                                                         \
            return fused_run(world, (KEY) | KEY_UNIFORM, drift, align, run);                       \
        return fused_run(world, (KEY), drift, align, run);                                         \
    }                                                                                              \
    static int part_range_##name(SimWorld *world, int begin, int end)                              \
    {                                                                                              \
        int moved = 0;                                                                             \
        for (int p = begin; p < end; ++p)                                                          \
            moved |= fused_part(world, fused_run_##name, p);                                       \
        return moved;                                                                              \
    }                                                                                              \
    static int fused_pass_##name(SimWorld *world, RangeFn *drift, int align)                       \
    {                                                                                              \
        if (world->threads > 1 && world->nl.plan.count > 0)                                        \
            return fused_parts(world, (KEY), part_range_##name, drift, align);                     \
        return fused_pass(world, (KEY), fused_run_##name, drift, align);                           \
    }                                                                                              \
    static void wall_pass_##name(SimWorld *world)                                                  \
    {                                                                                              \
        wall_pass(world, (KEY));                                                                   \
    }

#define GRAIN_ENTRY(h, l)     [(h)*8 + (l)] = grain_pass_##h##_##l,
#define WALL_ENTRY(h, l)      [(h)*8 + (l)] = wall_pass_##h##_##l,
#define FUSED_ENTRY(h, l)     [(h)*8 + (l)] = fused_pass_##h##_##l,
#define DEFINE_KEY_PASS(h, l) DEFINE_PASS(h##_##l, (unsigned)((h)*8 + (l)))

/* The upper half's passes (contact_pass_upper.c), NULL for a key of the lower half. */
StageFn *SIM_ISA_SYMBOL(sim_contact_pass_upper)(unsigned key);
StageFn *SIM_ISA_SYMBOL(sim_wall_pass_upper)(unsigned key);
FusedFn *SIM_ISA_SYMBOL(sim_fused_pass_upper)(unsigned key);

#if defined(SIM_CONTACT_UPPER)
#if defined(SIM_ISA_KEY_AT_RUN_TIME)
#error "contact_pass_upper.c is not built with SIM_ISA_KEY_AT_RUN_TIME (sim/CMakeLists.txt)"
#endif
KEYS_UPPER(DEFINE_KEY_PASS)
static StageFn *const grain_passes[KEY_COUNT] = {KEYS_UPPER(GRAIN_ENTRY)};
static StageFn *const wall_passes[KEY_COUNT] = {KEYS_UPPER(WALL_ENTRY)};
static FusedFn *const fused_passes[KEY_COUNT] = {KEYS_UPPER(FUSED_ENTRY)};

StageFn *SIM_ISA_SYMBOL(sim_contact_pass_upper)(unsigned key)
{
    return grain_passes[key];
}

StageFn *SIM_ISA_SYMBOL(sim_wall_pass_upper)(unsigned key)
{
    return wall_passes[key];
}

FusedFn *SIM_ISA_SYMBOL(sim_fused_pass_upper)(unsigned key)
{
    return fused_passes[key];
}
#else
KEYS_LOWER(DEFINE_KEY_PASS)
#if !defined(SIM_ISA_NO_RARE_KEYS)
/* One copy of each pass for the keys that are not folded, its key read at run time from the
 * world (sim_contact_key at create). The source and the arithmetic are the folded copies' (a
 * branch on the key runs or not; nothing is contracted or reordered), so the bits are too (the
 * golden tests run both kinds of key on every path); what goes is the compile time of their
 * folded copies, and in the sanitized build the instrumentation of them. */
DEFINE_PASS(any, world->contact_key)
#endif
#define ANY_GRAIN(h, l) [(h)*8 + (l)] = grain_pass_any,
#define ANY_WALL(h, l)  [(h)*8 + (l)] = wall_pass_any,
#define ANY_FUSED(h, l) [(h)*8 + (l)] = fused_pass_any,
static StageFn *const grain_passes[KEY_COUNT] = {KEYS_LOWER(GRAIN_ENTRY) KEYS_RARE(ANY_GRAIN)};
static StageFn *const wall_passes[KEY_COUNT] = {KEYS_LOWER(WALL_ENTRY) KEYS_RARE(ANY_WALL)};
static FusedFn *const fused_passes[KEY_COUNT] = {KEYS_LOWER(FUSED_ENTRY) KEYS_RARE(ANY_FUSED)};
#if defined(SIM_ISA_KEY_AT_RUN_TIME)
#define UPPER(kind, key) NULL
#else
#define UPPER(kind, key) SIM_ISA_SYMBOL(sim_##kind##_pass_upper)(key)
#endif

StageFn *SIM_ISA_SYMBOL(sim_contact_pass_select)(unsigned key)
{
    if (key >= KEY_COUNT)
        return NULL;
    return grain_passes[key] ? grain_passes[key] : UPPER(contact, key);
}

StageFn *SIM_ISA_SYMBOL(sim_wall_pass_select)(unsigned key)
{
    if (key >= KEY_COUNT)
        return NULL;
    return wall_passes[key] ? wall_passes[key] : UPPER(wall, key);
}

FusedFn *SIM_ISA_SYMBOL(sim_fused_pass_select)(unsigned key)
{
    if (key >= KEY_COUNT)
        return NULL;
    return fused_passes[key] ? fused_passes[key] : UPPER(fused, key);
}
#endif
