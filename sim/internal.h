/* SPDX-License-Identifier: MIT */
/* internal.h: sim's private world layout and the functions its sources share (never installed;
 * named apart from world.c, which defines only some of them). */
#ifndef SIM_INTERNAL_H
#define SIM_INTERNAL_H

#include "sim.h"

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* Per-pair constants (species pair p = s_i * SIM_MAX_SPECIES + s_j), mean of the two species. */
typedef struct PairParams {
    double k_n;     /* N/m */
    double mu;      /* friction coefficient */
    double gamma_s; /* kg/s */
    double k_t;     /* N/m */
    double mu_r;    /* m (fixed rolling law) */
    double k_r;     /* N m/rad (fixed rolling law) */
    double gamma_t; /* kg/s, the spring law's tangential dashpot */
} PairParams;

/* A pass of the step (contact pass, wall pass, integrator), chosen once at create from the
 * declared effects and laws. */
typedef void StageFn(SimWorld *world);

/* A loop body over the index range [begin, end); returns flags that the caller ORs (parallel.c). */
typedef int RangeFn(SimWorld *world, int begin, int end);

/* The one-thread contact pass with a drift fused into it (contact_pass.c, fused_pass): `drift`
 * moves and clears grains [begin, end) (begin a multiple of `align`) and returns 1 when one
 * passed the rebuild threshold. Returns 0 with the forces complete, or 1 with every grain
 * drifted and the forces to be evaluated anew after a rebuild. */
typedef int FusedFn(SimWorld *world, RangeFn *drift, int align);

/* The hot loops (sim/isa/: the contact passes and the integrators' steps), compiled once per
 * instruction set; isa.c picks the copy a new world uses (sim_isa, docs/dev/isa.md). */
typedef struct SimKernels {
    StageFn *(*contact_pass)(unsigned key); /* NULL for a key without an instance */
    StageFn *(*wall_pass)(unsigned key);
    FusedFn *(*fused_pass)(unsigned key);
    StageFn *(*integrator)(SimIntegrator integrator, int rotation);
    void (*integrator_finish)(SimWorld *world); /* a deferred closing kick, if any */
} SimKernels;

/* The most parts of the threaded fused contact pass (parts.c), and the spare doubles every grain
 * array has past its capacity: one cache line of sink per part (a part's scatter subtracts the
 * results of entries whose partner is shared there, grains.c), and one line between. */
enum { SIM_MAX_PARTS = 64, SIM_GRAIN_SLACK = 8 * (SIM_MAX_PARTS + 2) };

/* The plan of the threaded fused contact pass for the present list (parts.c builds it with the
 * list when the world has threads; count 0: not built, and the threaded separate passes run).
 * Part p owns mobile grains [first[p], first[p + 1]) and their entries, and runs as the one-thread
 * fused pass (sim/isa/contact_pass.c), writing only its own grains. A grain that entries of
 * another part reach is shared: every entry reaching it subtracts into its part's sink instead
 * (target), leaves its results in a slot, and after the parts a serial pass adds a shared
 * grain's slots and then its own sum in the serial scatter's order. */
typedef struct PartPlan {
    int count;
    int first[SIM_MAX_PARTS + 1];
    int head[SIM_MAX_PARTS];           /* [first[p], head[p]) holds part p's shared grains */
    int slot_first[SIM_MAX_PARTS + 1]; /* part p's entries fill slots [slot_first[p], ..[p+1]) */
    _Atomic int head_state[SIM_MAX_PARTS]; /* 0 not drifted, 1 being drifted, 2 drifted */
    _Atomic int abort;                     /* a part found a grain past the rebuild threshold */
    RangeFn *drift;                        /* the pass's drift and its alignment */
    int align;
    int *target;       /* per entry: the partner, or the sink of the entry's part */
    int *slot_entry;   /* per slot: its entry, ascending */
    double *slot_out;  /* 4 arrays of slot_capacity: a slot's fx, fy, f_t, M */
    int shared;        /* shared grains */
    int *shared_grain; /* ascending */
    int *shared_start; /* shared + 1: grain s's slots are shared_slot[shared_start[s] ..) */
    int *shared_slot;  /* ascending within a grain */
    int *mark;         /* per grain: the build's scratch */
    int target_capacity, slot_capacity, grain_capacity;
    /* The cut by measurement (parts.c, balance_shares): part p's share of the entries (all 0:
     * equal shares), and since the shares last moved, summed over the steps the parts ran
     * (`timed`): when part p's run began after the job's hand-over (its head drifted: a worker's
     * start lag and head), how long its run took (ns) and its entries. A part's sums are written
     * by the thread that runs it. */
    double share[SIM_MAX_PARTS];
    int shared_parts; /* the part count of `share` and the sums below */
    long long job_ns; /* the present job's hand-over, CLOCK_MONOTONIC ns */
    long long begin_ns[SIM_MAX_PARTS], run_ns[SIM_MAX_PARTS], entries[SIM_MAX_PARTS];
    int timed;
    int even_cut; /* 1: equal shares whatever the timing (tests of the plan's structure) */
} PartPlan;

/* Half neighbour list in CSR form over mobile grains i: entries k in [start[i], start[i+1]) hold
 * partners j > i (mobile or fixed). Per-entry constants are computed at the build. */
typedef struct NeighbourList {
    int capacity;
    int *start; /* mobile_count + 1 */
    int *j;
    double *gamma;  /* gamma_n of the pair, kg/s */
    uint8_t *pair;  /* species pair index */
    double *shift;  /* periodic x shift added to x_j - x_i, m (periodic only) */
    double *hist_t; /* tangential spring displacement xi_t, m (spring law only) */
    double *hist_r; /* rolling torque M, N m (rolling only) */
    /* Where the fused pass writes the new history (capacity each, history only), swapped with
     * hist_t and hist_r when it completes, so that a rebuild found mid-pass sees the old one. */
    double *hist_t_spare, *hist_r_spare;
    int *owner; /* i of entry k (the flat, vectorised force pass) */
    /* Per-entry results of that pass on several threads: 4 arrays (fx, fy, f_t, M) at a stride
     * of capacity, so out_capacity (what they hold) follows capacity, not the entry count; NULL
     * on one thread, whose passes keep a block's results on the stack. */
    double *out;
    /* The list transposed, for the threaded reduction (contact.c): the entries k whose partner
     * j is grain g are in_entry[in_start[g] .. in_start[g+1]), ascending k (the order in which
     * the serial scatter adds them to g). in_ready: built for the present grains. */
    int *in_start; /* in_capacity >= count + 1 */
    int *in_entry; /* out_capacity */
    int in_capacity, out_capacity, in_ready;
    PartPlan plan;
    struct ListBuild *build; /* the build's per-part candidates (neighbour.c) */
} NeighbourList;

/* Grain-wall candidate list: entries (grain, wall). */
typedef struct WallList {
    int count, capacity;
    int *grain;
    int *wall;
    double *gamma;
    uint8_t *pair;
    double *hist_t;
    double *hist_r;
} WallList;

/* The per-grain arrays, permuted, compacted and grown together (X-macros; the integrator's
 * scratch arrays below go with them). */
/* clang-format off */
#define SIM_GRAIN_DOUBLE_ARRAYS(X)                                                      \
    X(x) X(y) X(vx) X(vy) X(angle) X(omega) X(fx) X(fy) X(torque) X(radius)            \
    X(inv_mass) X(inv_inertia) X(mass) X(inertia) X(x_ref) X(y_ref) X(x_base)           \
    X(y_base) X(force_mag)
/* clang-format on */
#define SIM_GRAIN_INT_ARRAYS(X) X(species) X(motion)

/* Per-grain arrays an integrator keeps between force evaluations (half-step velocities, previous
 * positions, derivatives, start states). integrate.c names them per integrator; only the first
 * scratch_count are allocated (sim_integrator_scratch_count), the others stay NULL. */
enum { SIM_SCRATCH_MAX = 12 };

struct SimWorld {
    SimWorldDef def; /* copy; def.grains and def.walls point into the world's own storage */
    unsigned effects;
    int rotation;     /* 1 when a declared effect makes torques */
    int has_history;  /* tangential spring or rolling */
    int count;        /* all grains */
    int mobile_count; /* grains [0, mobile_count) integrate; the rest are fixed */
    int capacity;

    /* grain arrays (structure of arrays) */
    double *x, *y, *vx, *vy, *angle, *omega;
    double *fx, *fy, *torque;
    double *radius, *inv_mass, *inv_inertia, *mass, *inertia;
    double *x_ref, *y_ref;            /* positions at the last neighbour build */
    double *x_base, *y_base;          /* rest positions of fixed grains with motion */
    double *scratch[SIM_SCRATCH_MAX]; /* integrator state, see SIM_SCRATCH_MAX */
    int scratch_count;
    int *species, *motion;
    unsigned *flags;
    uint32_t *id;
    double *force_mag; /* frame: per-grain contact-force magnitude sum */

    /* walls */
    int wall_count;
    SimWall *walls_base; /* as defined */
    SimWall *walls;      /* current (moving) */
    /* Surface velocity of wall k (walls.h sim_wall_velocity): wall_v + wall_omega z x (q - wall_o),
     * from its motion's pose (sim.h SimPose). */
    double *wall_vx, *wall_vy, *wall_omega, *wall_ox, *wall_oy;
    double *wall_ref_dx, *wall_ref_dy; /* motion offsets at the last build, m */
    SimWall *walls_ref;                /* walls at the last build (rotating motions), m */
    /* Motion schedules by world time (sim_world_set_motion): motion m runs on the clock
     * t - motion_on[m] and holds its pose from motion_off[m] on. */
    double motion_on[SIM_MAX_MOTIONS], motion_off[SIM_MAX_MOTIONS];
    double wall_shift; /* largest wall displacement since the last build, m */
    /* What the grains do to each wall in the last wall pass (4 per wall: fx, fy, the sum of the
     * normal forces, the torque about the wall's centre; wall_touch: contacts), and the walls
     * that respond (sim.h SimWallBody; wall_body.c): their offset along the axis (m) and speed
     * (m/s), their angle (rad) and angular speed (rad/s). bodies is NULL when none responds; else
     * body_count = wall_count + grain_body_count entries, the grain bodies after the walls (their
     * loads too: wall_load and wall_touch hold body_count entries). body_rest: 4 per body, its
     * centre at rest (m), its length (m) and its moment of inertia (kg m^2). */
    double *wall_load;
    int *wall_touch;
    SimWallBody *bodies;
    int body_count;
    double *body_s, *body_u, *body_a, *body_w, *body_rest;
    /* wall_damp: per body, the sum over a servo wall's contacts in the last wall pass of their
     * normal damping coefficients projected on its axis, gamma_n (a_axis . n)^2 (Hertz: gamma_n
     * sqrt(xi)), N s/m (wall_body.c body_speed). body_flip: 3 per body, its servo's current
     * run of steps flipping between the caps, the steps counted in runs longer than
     * SIM_SERVO_FLIP_STEPS and the time the first such run was found (NaN: none). */
    double *wall_damp, *body_flip;
    /* a responding wall's motion across its axis, 4 per wall: its offset (x, y), m, and
     * velocity, m/s (zero without a motion; motion.c move_walls) */
    double *body_m;
    int pending_removal; /* grains flagged SIM_GRAIN_REMOVED wait for the next build */
    int drop_history;    /* the list refers to a state that was replaced: carry nothing over */
    int exact_restored;  /* loaded with a state's exact-continuation section (resume.c) */
    int jump_grain;      /* index of a grain that moved over half its radius in a step, or -1 */
    /* What ran out of memory in a pass that cannot return an error (neighbour build, removal,
     * sorting), or NULL. Sticky: sim_world_step reports it as SIM_ERROR_MEMORY from then on; the
     * lists are left empty, so every reader stays in bounds (docs/dev/errors.md). */
    const char *out_of_memory;
    struct HistoryStash
        *stash; /* history collected before a reorder (sim_neighbour_stash_history) */

    PairParams pairs[SIM_MAX_SPECIES * SIM_MAX_SPECIES];

    double dt, time;
    double contact_dt; /* dt of contact-history increments: dt, or 0 when re-evaluating */
    long step;
    double skin, cell_size; /* cell_size: smallest cell side, 2 r_max + skin_max, m */
    double cell_w, cell_h;  /* cell sides of the last build, m */
    double max_radius;
    double disp_limit2; /* (skin / 2)^2: a grain moved this far triggers a rebuild, m^2 */
    int need_rebuild;
    long rebuilds;
    long build_step; /* step of the last build */
    /* Automatic skin (world.c, skin_optimum): the range it moves in (skin_min = skin_max =
     * skin when the scene fixes it), the pairs per mobile grain per metre of gap below skin_max
     * counted at the last build, and the step of the next check. */
    int skin_auto;
    double skin_min, skin_max, skin_density;
    long skin_probe;
    /* velocity Verlet: sim_world_step asks to defer a step's closing kick into the next step's
     * opening loop (defer_kick); kick_pending says one is deferred. Never pending outside
     * sim_world_step. */
    int defer_kick, kick_pending;

    NeighbourList nl;
    WallList wl;

    /* cell grid of the last build */
    int ncx, ncy, cell_capacity;
    double grid_x0, grid_y0;
    int *cell_start, *cell_items, *cell_of;

    /* Threads of the step (sim_world_set_threads in world.c, default 1; the pool in parallel.c).
     * The threaded passes split their loops into fixed ranges whose results do not depend on the
     * split (sim_parallel_ranges). */
    int threads;
    struct SimPool *pool;             /* threads - 1 workers (parallel.c), NULL with one thread */
    struct SimPoolWorker *pool_slots; /* their arguments */

    /* stages chosen at create (sim_world_forces_at calls the passes, sim_world_step integrate),
     * from the kernels of the instruction set chosen then */
    const SimKernels *kernels;
    StageFn *contact_pass;
    StageFn *wall_pass;
    FusedFn *fused_pass; /* NULL: the separate passes always (tests/sim/test_fused.c) */
    StageFn *integrate;
    long fused_steps, fused_trips; /* steps whose drift ran fused; those that found a rebuild */
    unsigned contact_key; /* sim_contact_key at create (the passes of a run-time-key build) */

    /* sinks */
    long removed[SIM_MAX_SINKS];

    /* guard */
    double guard_speed2;
    long guard_next;
    /* what gravity alone could explain (guard messages only, not saved in states): the largest
     * initial and wall speed at guard_t0, the time of the guard's set-up */
    double guard_free_speed, guard_t0;

    struct {
        int valid, count, mobile_count;
        double time;
        long step;
        double *data;    /* x, y, vx, vy, angle, omega, radius per grain */
        int *ints;       /* species, motion per grain */
        unsigned *flags; /* per grain */
        uint32_t *ids;   /* per grain */
    } good;

    /* frame scratch */
    SimContact *contacts;
    int contact_count, contact_capacity;
    double time_scale;

    SimTiming timing;
    SimBodyForce body_force;
};

/* Internal flag of grains waiting to be compacted away at the next build. */
#define SIM_GRAIN_REMOVED (1u << 31)

/* Records the first allocation failure of a pass that has no error return (see out_of_memory). */
static inline void sim_world_out_of_memory(SimWorld *world, const char *what)
{
    if (!world->out_of_memory)
        world->out_of_memory = what;
}

/* motion.c */
/* Moves the walls and fixed grains that have a motion to their poses at world time t (their
 * velocities with them) and records how far walls moved since the last build (wall_shift). */
void sim_motion_move(SimWorld *world, double t);
/* wall_body.c */
/* Moves the responding walls one step on from the wall loads of the last force evaluation
 * (symplectic Euler; servo walls at the gain law's speed). */
void sim_wall_bodies_step(SimWorld *world);
/* Places the responding walls and grain bodies at their offsets (after create or a state load). */
void sim_wall_bodies_place(SimWorld *world);
/* Places responding wall k: its motion's offset (body_m) plus its offset along the axis (and
 * its angle when it turns). */
void sim_wall_body_place(SimWorld *world, int k);
/* Allocates the responding bodies of def (walls, then grain bodies) with their rest geometry;
 * nothing when none responds. -1: out of memory. */
int sim_wall_bodies_create(SimWorld *world, const SimWorldDef *def);
void sim_wall_bodies_free(SimWorld *world);
/* Why grains g cannot join the world (NULL when they can), with the body in *body: grains of an
 * active grain body (a body takes its grains while dormant, all at once), or a dormant body they
 * wake that fails the checks of sim_wall_bodies_problem against the world's grains and g. */
const char *sim_wall_bodies_join_problem(const SimWorld *world, const SimGrainSet *g, int *body,
                                         char *buf, size_t size);
/* Wakes the dormant grain bodies whose grains are now in the world: their rest geometry from
 * their grains where they were put, at rest (offset, speed, angle 0). */
void sim_wall_bodies_join(SimWorld *world);
/* NULL when the responding walls and grain bodies of def are valid at time step dt, else what is
 * wrong, with the body's index in *wall (wall_count + b: grain body b). */
const char *sim_wall_bodies_problem(const SimWorldDef *def, double dt, int *wall, char *buf,
                                    size_t size);
/* The responding bodies' footer of a state file (offsets, speeds, angles, their motions'
 * offsets and their rest geometry; docs/state-format.md): written when a body responds (0, -1 on
 * a write error); read from the file's end into the world, which places every body where the
 * saved run left it (at rest where it is defined when the file has none). */
int sim_wall_bodies_write(FILE *f, const SimWorld *world);
void sim_wall_bodies_read(SimWorld *world, FILE *f);
/* Records the walls' positions at a neighbour build (the reference of wall_shift). */
void sim_motion_mark_build(SimWorld *world);
/* Largest speed a motion of the definition gives a point within `size` of its centre, m/s. */
double sim_motion_speed_bound(const SimWorldDef *def, double size);
/* NULL when motion `index` of def is valid, else what is wrong. */
const char *sim_motion_problem(const SimWorldDef *def, int index);

/* world.c */
/* sim_world_create for grains restored from a checkpoint (sim_world_load): every check of
 * sim_world_create except the start-overlap bound, which is for new grains only. */
SimWorld *sim_world_create_restored(const SimWorldDef *def, SimError *error);
/* Moves prescribed grains and walls to `time`, rebuilds the lists when the skin is used up, and
 * computes all forces: contacts, walls, body forces (no gravity: the integrators add it). */
void sim_world_forces_at(SimWorld *world, double time);
/* A drift of the mobile grains that also clears their forces (`drift`, over ranges that are
 * multiples of `align`), then the forces at `time`: with the drift fused into the contact pass
 * (FusedFn; on threads, in the parts of NeighbourList.plan), or, when the fused pass cannot run,
 * over fixed ranges first and then the separate passes; the same bits either way. */
void sim_world_drift_forces_at(SimWorld *world, double time, RangeFn *drift, int align);
/* neighbour.c */
/* Rebuilds the lists; out of memory, it leaves them empty and sets world->out_of_memory. */
void sim_neighbour_build(SimWorld *world);
void sim_neighbour_free(SimWorld *world);
/* The threaded reduction's transposed list and result arrays for the present list, when the world
 * has threads (in_ready = 1); with one thread, or out of memory, in_ready = 0 (the serial scatter:
 * the same bits). */
void sim_neighbour_build_incoming(SimWorld *world);
/* parts.c */
/* The threaded fused pass's plan for the present list (NeighbourList.plan); count 0 with one
 * thread, a pile too small to cut, or out of memory (the threaded separate passes: same bits). */
void sim_parts_build(SimWorld *world);
void sim_parts_free(SimWorld *world);
/* Makes sure part q's shared grains are drifted: drifts them if no thread has begun to (returning
 * the drift's flag), or waits until the thread that has is done (returning 0). */
int sim_parts_drift_head(SimWorld *world, int q);
/// The monotonic clock, ns (the parts' timing for the cut by measurement, the workers' bounded
/// spin; sim/clock.c).
long long sim_now_ns(void);
double sim_def_worst_overlap(const SimWorldDef *def, int *first, int *second);
/* Collects contact history by ids now, for the next build (before grains are reordered); -1 when
 * out of memory (the world unchanged). */
int sim_neighbour_stash_history(SimWorld *world);

/* History records (24 bytes each: uint64 key, double t, double r) for checkpoints. */
enum { SIM_HISTORY_RECORD_SIZE = 24 };

/* The history of the current lists as records (malloc'd); -1 when out of memory. */
int sim_neighbour_history(const SimWorld *world, void **records, int *count, void **walls,
                          int *wall_count);
/* Installs saved history records for the next build; -1 when out of memory (nothing installed). */
int sim_neighbour_stash_records(SimWorld *world, const void *records, int count, const void *walls,
                                int wall_count);

/* The lists of a checkpoint (resume.c), as saved: the CSR starts (mobile_count + 1), the partner
 * of each pair entry, its periodic shift and history; the grain, wall and history of each wall
 * entry (shift and history arrays NULL when the world has none). */
typedef struct SimListArrays {
    int pairs, wall_pairs;
    int *start, *j;
    double *shift, *hist_t, *hist_r;
    int *wall_grain, *wall;
    double *wall_hist_t, *wall_hist_r;
} SimListArrays;

/* Installs saved lists in place of the present ones (their per-entry constants from the world's
 * materials); -1 when out of memory or an entry is out of range. */
int sim_neighbour_install(SimWorld *world, const SimListArrays *lists);

/* resume.c: the exact-continuation section of a state file (after the contact history). */
int sim_exact_write(FILE *f, const SimWorld *world);
/* Reads the section into a world created from the same file's grains (`saved`, in the file's
 * order; `step` and `time` from its header): 1 applied (the world continues as the saved one),
 * 0 the section does not fit this world's definition (another time step, integrator or laws:
 * the world starts afresh from the grains), -1 truncated, -2 out of memory. */
int sim_exact_apply(SimWorld *world, FILE *f, const SimGrainSet *saved, long step, double time);
/* Reads the section's header at f's position: NULL when sound, else what is wrong (a value no
 * written section holds, such as a cell size of 0; or the file ends first). */
const char *sim_exact_check(FILE *f);
/* world.c: rebuild the lists now (used after installing history). */
void sim_world_rebuild_now(SimWorld *world);
/* world.c: fills `error` (when not NULL) and returns `status`; step and grain -1. */
SimStatus sim_fail(SimError *error, SimStatus status, const char *field, const char *fmt, ...);
/* world.c: SIM_ERROR_INVALID when grains `g` (radius, species, flags) paired with the grains in
 * place have a stability limit below the world's time step. */
SimStatus sim_world_check_timing(const SimWorld *world, const SimGrainSet *g, SimError *error);
/* world.c: after grains were added or edited in place: the largest radius, the automatic skin's
 * range and the cell size follow them; the lists are built and the forces evaluated anew. */
void sim_world_grains_changed(SimWorld *world);
/* world.c: mass (kg) and moment of inertia (kg m^2) of a grain under the mass model. */
void sim_grain_mass_inertia(SimMassModel model, double density, double r, double *m,
                            double *inertia);
/* gamma_n of a pair of species (the mean of the two species' damping specifications) for a
 * pair stiffness k_n and an effective mass m_eff: the list build and the set-up timing. */
double sim_damping_gamma(const SimMaterial *materials, int species_i, int species_j, double k_n,
                         double m_eff);

/* isa.c: the kernels of the instruction set new worlds use (sim_isa). */
const SimKernels *sim_kernels(void);

/* sim/isa/ files are compiled once per instruction set with SIM_ISA_SUFFIX (_sse2, _avx2, _avx512;
 * _native in a SABLIER_NATIVE build; _generic off x86) appended to their external names. */
#define SIM_ISA_CAT2(a, b)   a##b
#define SIM_ISA_CAT(a, b)    SIM_ISA_CAT2(a, b)
#define SIM_ISA_SYMBOL(name) SIM_ISA_CAT(name, SIM_ISA_SUFFIX)
#ifdef SIM_ISA_SUFFIX
StageFn *SIM_ISA_SYMBOL(sim_contact_pass_select)(unsigned key);
StageFn *SIM_ISA_SYMBOL(sim_wall_pass_select)(unsigned key);
FusedFn *SIM_ISA_SYMBOL(sim_fused_pass_select)(unsigned key);
StageFn *SIM_ISA_SYMBOL(sim_integrator_select)(SimIntegrator integrator, int rotation);
void SIM_ISA_SYMBOL(sim_integrator_finish)(SimWorld *world);
#endif

/* contact.c */
unsigned sim_contact_key(const SimWorld *world);
int sim_contact_key_rotation(unsigned key);
/* 1 when the key's laws keep per-contact history (tangential spring, rolling resistance). */
int sim_contact_key_history(unsigned key);
/* Evaluates every contact without applying it (frame, energy, guard). Calls visit for each. */
typedef void ContactVisit(void *context, const SimContact *contact, double elastic_energy);
void sim_contacts_visit(SimWorld *world, ContactVisit *visit, void *context);
/* The largest overlap as a fraction of the smaller diameter, and its pair (*j = -1 - wall for a
 * wall; -1, -1 when nothing overlaps): the guard's scan, without the laws (contact.c). */
double sim_contacts_worst_overlap(const SimWorld *world, int *i, int *j);
/* 1 when that overlap exceeds def.guard_max_overlap, scanned on the world's threads. */
int sim_contacts_overlap_over_bound(SimWorld *world);

/* integrate.c */
/* How many scratch arrays (SimWorld.scratch) the integrator uses, with or without rotation. */
int sim_integrator_scratch_count(SimIntegrator integrator, int rotation);
void sim_integrator_start(SimWorld *world);
/* Applies a deferred closing kick (velocity Verlet), if any. */
void sim_integrator_finish(SimWorld *world);
double sim_stability_limit(SimIntegrator integrator, double omega, double zeta);

/* parallel.c */
/* Runs fn over [0, n) cut into chunks (bounds multiples of `align`, the last one ending at n),
 * on world->threads threads when threads > 1; returns the OR of the results. The cut and the
 * thread that runs a chunk change only who computes what: a body that writes only to its own
 * indices, from data no other range writes, gives the same bits for every thread count. */
int sim_parallel_ranges(SimWorld *world, RangeFn *fn, int n, int align);
/* Runs fn(world, u, u + 1) for every unit u of [0, n) on the world's threads, each first taking
 * its own contiguous run of units (sim_parallel_ranges' chunks of one); the OR of the results. */
int sim_parallel_units(SimWorld *world, RangeFn *fn, int n);
/* Replaces the world's threads by `threads` (its pool of threads - 1 workers; world->threads is
 * how many started, 1 when none could; sim_world_set_threads). */
void sim_parallel_start(SimWorld *world, int threads);
/* Stops and frees the world's threads, leaving one (sim_world_destroy). */
void sim_parallel_free(SimWorld *world);

/* stagger.c: blocks for arrays that one loop reads at the same index. A large block comes from
 * mmap at a page start plus the allocator's header (glibc: over 128 KiB), so every large array
 * would begin at the same offset in its page and element i of each fall into the same set of the
 * 8-way, 64-set L1. Array number k of a family begins sim_stagger_lead(k) bytes into its block
 * instead: 64 + 192 k (one line for the lead itself, then 3 lines per array), so up to 64 arrays
 * of one element size fall into 64 different sets. Only addresses change: the same bits. */
enum { SIM_STAGGER_LINES = 3 };

static inline size_t sim_stagger_lead(int k)
{
    return 64u * (1u + SIM_STAGGER_LINES * (size_t)k);
}

/* `data` (NULL, or from this function) grown to `bytes`, its contents kept as realloc keeps them;
 * a new block gets lead k, a grown one keeps its own (so blocks may swap owners, as the history
 * and its spare do). NULL when out of memory, `data` as it was. */
void *sim_stagger_grow(void *data, size_t bytes, int k);
void sim_stagger_free(void *data);
/* The lead of a block from sim_stagger_grow (0 for NULL): where its data begin in it. */
size_t sim_stagger_offset(const void *data);

/* grains.c */
int sim_grains_reserve(SimWorld *world, int capacity);
/* -1 when out of memory (the grains left as they were). */
int sim_grains_permute(SimWorld *world, const int *order, int count);
void sim_grains_free(SimWorld *world);
/* Drops grains flagged SIM_GRAIN_REMOVED (called by the neighbour build); -1 when out of memory
 * (nothing dropped). */
int sim_world_compact(SimWorld *world);

#endif
