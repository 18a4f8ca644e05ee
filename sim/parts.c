/* SPDX-License-Identifier: MIT */
/* parts.c: the plan of the threaded fused contact pass (internal.h PartPlan; the pass itself is
 * sim/isa/contact_pass.c, fused_parts). The mobile grains are cut into parts, one per thread, that
 * share the list's entries so that they end together (measured: balance_shares; equal shares
 * until a plan has been timed); each part runs as the one-thread fused pass does (the
 * drift of its grains just ahead of its entries, phase 1 into a block on the stack, the flat
 * scatter), and writes only its own grains, so the parts run side by side without a reduction.
 *
 * What keeps the bits: the serial scatter gives grain g first every entry whose partner is g, in
 * ascending k (owners below g), then g's own sum. A grain reached by entries of a part other than
 * its own (a mobile grain just past a cut, a fixed grain reached from two parts) is shared: every
 * entry that reaches it subtracts into its part's sink (a cache line past the grain arrays,
 * never read) and leaves its four results in a slot (numbered in entry order); its own part adds
 * its own sum to its cleared force as usual, which gives that sum exactly (a sum that starts at
 * +0.0 is never -0.0, and +0.0 + s = s). After the parts, contact_pass.c's shared_fixup adds, for
 * each shared grain, its slots in ascending k to +0.0 and then its own sum: the serial loop's
 * additions in the serial loop's order. Shared mobile grains sit at the start of their part (a
 * partner is above its owner, within the list's reach), in its head, which is drifted before
 * anything else of the part and before another part reads it (sim_parts_drift_head).
 *
 * Against the threaded separate passes (a drift pass, phase 1 into nl.out, the transposed-list
 * gather) this keeps the one-thread pass's traffic: each grain's data come from memory once per
 * step, no per-entry results go through memory but the slots' (360 of 15 852 entries on the
 * 7000-grain pile on two threads, 3599 of 158 520 on the 70 000-grain one), and the step is one
 * job with one wait. docs/dev/scaling.md has the measurements. */
#include "internal.h"

#include <sched.h>
#include <stdlib.h>
#include <string.h>

/* Parts per thread: one. Two (a thread that finishes early could take a delayed one's second
 * part: sim_parallel_units helps as sim_parallel_ranges does) were 3-6 % slower on 2 threads on
 * the 7000-grain pile, quiet and with a competing process alike (docs/dev/scaling.md): each cut
 * adds a row of shared grains and a head to wait for. Parts are at least PART_MIN_GRAINS grains
 * and start at multiples of PART_ALIGN grains (one cache line of each double array, so that no
 * two parts write one line). */
enum { PARTS_PER_THREAD = 1, PART_MIN_GRAINS = 32, PART_ALIGN = 8 };

/* A grain's mark while the plan is built: its part (a mobile grain's own; for a fixed grain the
 * first part that reaches it, -1 before any), with SHARED set once another part reaches it. */
enum { SHARED = 1 << 30 };

void sim_parts_free(SimWorld *world)
{
    PartPlan *pp = &world->nl.plan;
    free(pp->target);
    free(pp->slot_entry);
    free(pp->slot_out);
    free(pp->shared_grain);
    free(pp->shared_start);
    free(pp->shared_slot);
    free(pp->mark);
    memset(pp, 0, sizeof *pp);
}

/* Resizes *a to n items of `size` bytes; -1 out of memory (*a then as it was). */
static int resize(void **a, int n, size_t size)
{
    void *p = realloc(*a, (size_t)n * size);
    if (!p)
        return -1;
    *a = p;
    return 0;
}

/* The plan's arrays grown for `grains` grains, `entries` list entries and `slots` slots (each
 * group shares one capacity); -1 out of memory. */
static int reserve(PartPlan *pp, int grains, int entries, int slots)
{
    if (grains > pp->grain_capacity) {
        if (resize((void **)&pp->mark, grains, sizeof(int)) != 0 ||
            resize((void **)&pp->shared_grain, grains, sizeof(int)) != 0 ||
            resize((void **)&pp->shared_start, grains + 1, sizeof(int)) != 0)
            return -1;
        pp->grain_capacity = grains;
    }
    if (entries > pp->target_capacity) {
        if (resize((void **)&pp->target, entries, sizeof(int)) != 0)
            return -1;
        pp->target_capacity = entries;
    }
    if (slots > pp->slot_capacity) {
        if (resize((void **)&pp->slot_entry, slots, sizeof(int)) != 0 ||
            resize((void **)&pp->shared_slot, slots, sizeof(int)) != 0 ||
            resize((void **)&pp->slot_out, slots, 4 * sizeof(double)) != 0)
            return -1;
        pp->slot_capacity = slots;
    }
    return 0;
}

/* The cut by measurement. With the last plan's timing (at least BALANCE_MIN_STEPS steps), part p
 * began its run b_p after the hand-over and took c_p per entry: the parts all end together when
 * part p holds n_p = (T - b_p) / c_p entries, T = (N + sum b_p / c_p) / sum 1 / c_p for the N
 * entries. The shares move halfway to those n_p / N (the timing is noisy), each within
 * [SHARE_MIN, SHARE_MAX] of an equal share. Which grains a part holds changes no result
 * (the bits are the same for any cut), only when the parts end. On the 7000-grain pile on two
 * threads the worker begins its run about 3.6 us after the calling thread (its start lag and its
 * head's drift), but runs an entry in 5.5 ns where the calling thread takes 7.4, so the worker
 * ends up with 55 % of the entries; equal shares left the calling thread waiting
 * (docs/dev/scaling.md, "The cut by measurement"). */
enum { BALANCE_MIN_STEPS = 20 };

#define SHARE_MIN 0.5
#define SHARE_MAX 1.5

/* The shares halfway to those that end every part at `end` (ns after the hand-over), n entries
 * per step in all, part p beginning at b[p] and taking c[p] ns an entry. */
static void move_shares(PartPlan *pp, int parts, double end, double n, const double *b,
                        const double *c)
{
    double sum = 0.0;
    for (int p = 0; p < parts; ++p) {
        const double old = pp->share[p] > 0.0 ? pp->share[p] : 1.0 / parts;
        double want = (end - b[p]) / c[p] / n;
        want = want > SHARE_MIN / parts ? want : SHARE_MIN / parts;
        want = want < SHARE_MAX / parts ? want : SHARE_MAX / parts;
        pp->share[p] = 0.5 * (old + want);
        sum += pp->share[p];
    }
    for (int p = 0; p < parts; ++p)
        pp->share[p] /= sum;
}

static void balance_shares(PartPlan *pp, int parts)
{
    if (pp->shared_parts != parts || pp->even_cut) {
        memset(pp->share, 0, sizeof pp->share);
        pp->shared_parts = parts;
        pp->timed = 0;
    }
    const int timed = pp->timed;
    if (timed == 0 || timed >= BALANCE_MIN_STEPS) { /* the sums start again */
        double n = 0.0, inv = 0.0, lead = 0.0, b[SIM_MAX_PARTS], c[SIM_MAX_PARTS];
        int usable = timed > 0;
        for (int p = 0; p < parts && usable; ++p) {
            usable = pp->entries[p] > 0 && pp->run_ns[p] > 0;
            b[p] = usable ? (double)pp->begin_ns[p] / timed : 0.0;
            c[p] = usable ? (double)pp->run_ns[p] / (double)pp->entries[p] : 0.0;
            n += (double)pp->entries[p] / (timed > 0 ? timed : 1);
            inv += usable ? 1.0 / c[p] : 0.0;
            lead += usable ? b[p] / c[p] : 0.0;
        }
        pp->timed = 0;
        memset(pp->begin_ns, 0, sizeof pp->begin_ns);
        memset(pp->run_ns, 0, sizeof pp->run_ns);
        memset(pp->entries, 0, sizeof pp->entries);
        if (usable)
            move_shares(pp, parts, (n + lead) / inv, n, b, c);
    }
}

/* The cut: part p's first grain is the first multiple of PART_ALIGN whose entries start at or
 * after the shares of parts 0 .. p - 1 of the list (p / parts of it while no part is measured). */
static void cut_parts(PartPlan *pp, const int *start, int mobile, int parts)
{
    const int total = start[mobile];
    pp->first[0] = 0;
    int g = 0;
    double before = 0.0;
    for (int p = 1; p < parts; ++p) {
        before += pp->share[p - 1];
        const long long want =
            pp->share[0] > 0.0 ? (long long)(total * before) : (long long)total * p / parts;
        while (g < mobile && start[g] < want)
            g += PART_ALIGN;
        g = g < mobile ? g : mobile;
        pp->first[p] = g;
    }
    pp->first[parts] = mobile;
}

/* Marks the shared grains (mark: SHARED set) and returns how many entries reach them. */
static int mark_shared(const SimWorld *world, PartPlan *pp, int parts)
{
    const int mobile = world->mobile_count, *start = world->nl.start, *partner = world->nl.j;
    int *mark = pp->mark;
    for (int p = 0; p < parts; ++p)
        for (int g = pp->first[p]; g < pp->first[p + 1]; ++g)
            mark[g] = p;
    for (int g = mobile; g < world->count; ++g)
        mark[g] = -1;
    for (int p = 0; p < parts; ++p)
        for (int k = start[pp->first[p]]; k < start[pp->first[p + 1]]; ++k) {
            const int j = partner[k], m = mark[j];
            if (m < 0)
                mark[j] = p; /* a fixed grain's first part */
            else if ((m & (SHARED - 1)) != p)
                mark[j] = m | SHARED;
        }
    int slots = 0;
    for (int k = 0; k < start[mobile]; ++k)
        slots += (mark[partner[k]] & SHARED) != 0 && mark[partner[k]] >= 0;
    return slots;
}

/* The entries' targets and slots, the parts' heads, and the shared grains with their slots. */
static void fill_plan(const SimWorld *world, PartPlan *pp, int parts)
{
    const int mobile = world->mobile_count, n = world->count;
    const int *start = world->nl.start, *partner = world->nl.j;
    int *mark = pp->mark;
    int q = 0;
    for (int p = 0; p < parts; ++p) {
        pp->slot_first[p] = q;
        const int sink = n + PART_ALIGN * (p + 1); /* a line apart from the grains and each other */
        for (int k = start[pp->first[p]]; k < start[pp->first[p + 1]]; ++k) {
            const int j = partner[k];
            if (mark[j] >= 0 && (mark[j] & SHARED)) {
                pp->target[k] = sink;
                pp->slot_entry[q++] = k;
            } else {
                pp->target[k] = j;
            }
        }
    }
    pp->slot_first[parts] = q;
    for (int p = 0; p < parts; ++p)
        pp->head[p] = pp->first[p];
    int s = 0;
    for (int g = 0; g < n; ++g) {
        if (mark[g] < 0 || !(mark[g] & SHARED)) {
            mark[g] = -1;
            continue;
        }
        if (g < mobile) {
            const int p = mark[g] & (SHARED - 1);
            pp->head[p] = g + 1 > pp->head[p] ? g + 1 : pp->head[p];
        }
        pp->shared_grain[s] = g;
        mark[g] = s++;
    }
    pp->shared = s;
    for (int p = 0; p < parts; ++p) {
        int h = (pp->head[p] + PART_ALIGN - 1) / PART_ALIGN * PART_ALIGN;
        pp->head[p] = h < pp->first[p + 1] ? h : pp->first[p + 1];
    }
    /* a counting sort of the slots by grain, filled in slot order (ascending k per grain) */
    int *at = pp->shared_start;
    memset(at, 0, (size_t)(s + 1) * sizeof *at);
    for (int i = 0; i < q; ++i)
        ++at[mark[partner[pp->slot_entry[i]]] + 1];
    for (int t = 0; t < s; ++t)
        at[t + 1] += at[t];
    for (int i = 0; i < q; ++i)
        pp->shared_slot[at[mark[partner[pp->slot_entry[i]]]]++] = i;
    for (int t = s; t > 0; --t)
        at[t] = at[t - 1];
    at[0] = 0;
}

void sim_parts_build(SimWorld *world)
{
    PartPlan *pp = &world->nl.plan;
    pp->count = 0;
    const int mobile = world->mobile_count;
    if (world->threads <= 1 || !world->nl.start || mobile <= 0 || world->nl.start[mobile] == 0)
        return;
    int parts = world->threads * PARTS_PER_THREAD;
    parts = parts < SIM_MAX_PARTS ? parts : SIM_MAX_PARTS;
    parts = parts < mobile / PART_MIN_GRAINS ? parts : mobile / PART_MIN_GRAINS;
    if (parts < 2)
        return;
    balance_shares(pp, parts);
    if (reserve(pp, world->count, world->nl.start[mobile], 0) != 0)
        return;
    cut_parts(pp, world->nl.start, mobile, parts);
    const int slots = mark_shared(world, pp, parts);
    if (reserve(pp, world->count, world->nl.start[mobile], slots > 0 ? slots : 1) != 0)
        return;
    fill_plan(world, pp, parts);
    pp->count = parts;
}

int sim_parts_drift_head(SimWorld *world, int q)
{
    PartPlan *pp = &world->nl.plan;
    int expected = 0;
    if (atomic_compare_exchange_strong_explicit(&pp->head_state[q], &expected, 1,
                                                memory_order_acquire, memory_order_acquire)) {
        const int moved =
            pp->head[q] > pp->first[q] ? pp->drift(world, pp->first[q], pp->head[q]) : 0;
        atomic_store_explicit(&pp->head_state[q], 2, memory_order_release);
        return moved;
    }
    /* Another thread is drifting it (a few hundred grains at most): spin, giving the core away
     * now and then in case that thread waits for one. */
    for (unsigned checks = 1; atomic_load_explicit(&pp->head_state[q], memory_order_acquire) != 2;
         ++checks)
        if (checks % 1024 == 0)
            sched_yield();
    return 0;
}
