/* SPDX-License-Identifier: MIT */
/* sim.h: the one public header of sablier's physics library (2D soft-disk DEM).
 *
 * Depends on the C library and libm only. Usage:
 *
 *     SimWorldDef def = sim_world_def_default();
 *     def.time_step = 1e-5;
 *     def.grains = my_grains;                  // SimGrainSet, copied at create
 *     SimError err;
 *     SimWorld *world = sim_world_create(&def, &err);
 *     if (!world) { fprintf(stderr, "%s: %s\n", err.field, err.message); }
 *     SimStatus s = sim_world_step(world, 1000, &err);
 *     SimEnergy e = sim_world_energy(world);
 *     sim_world_destroy(world);
 *
 * Units are SI unless a scene uses normalised units; every field names its unit.
 * Conventions (000 eqs. 3.1-3.5): n points from i to j, s = (n_y, -n_x), omega is
 * counter-clockwise positive, gravity points along -y.
 */
#ifndef SIM_H
#define SIM_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SIM_VERSION "0.1.0"

/// pi for every layer (strict C17 has no M_PI).
#define SIM_PI 3.14159265358979323846

/* ---------------------------------------------------------------- effects */

/// Physical effects a scene can declare; an undeclared effect costs nothing at run time.
typedef enum SimEffect {
    SIM_EFFECT_FRICTION = 1u << 0,   ///< tangential contact force (law in SimMaterial)
    SIM_EFFECT_ROLLING = 1u << 1,    ///< rolling resistance torque (004 ch. 4)
    SIM_EFFECT_PERIODIC_X = 1u << 2, ///< periodic boundary in x
    SIM_EFFECT_VIBRATION = 1u << 3,  ///< walls and fixed grains with prescribed motion
    SIM_EFFECT_FLUID_DRAG = 1u << 4, ///< user body-force stage (SimBodyForce)
    SIM_EFFECT_REMOVAL = 1u << 5,    ///< sinks that remove grains
} SimEffect;

/// Parse an effect name ("friction", "rolling_resistance", "periodic_x", "vibration",
/// "fluid_drag", "removal"); returns 0 when unknown.
unsigned sim_effect_from_name(const char *name);
/// Name of one effect bit, or NULL.
const char *sim_effect_name(unsigned effect);

/* ---------------------------------------------------------------- contact laws */

typedef enum SimNormalLaw {
    SIM_NORMAL_LINEAR = 0, ///< F_n = k_n xi + gamma_n dxi/dt (000 eq. 3.6; 004 eq. 1.9)
    SIM_NORMAL_HERTZ = 1,  ///< F_n = sqrt(xi) (k_n xi + gamma_n dxi/dt), Hertz-type xi^{3/2}
} SimNormalLaw;

typedef enum SimTangentialLaw {
    SIM_TANGENTIAL_NONE = 0,
    SIM_TANGENTIAL_REGULARISED = 1, ///< F_t = -min(gamma_s|v_s|, mu|F_n|) sgn(v_s) (000 eq. 3.28)
    SIM_TANGENTIAL_SPRING = 2, ///< Cundall-Strack spring, |F_t| <= mu k_n xi (004 eqs. 1.12-1.13)
} SimTangentialLaw;

typedef enum SimRollingLaw {
    SIM_ROLLING_OFF = 0,
    SIM_ROLLING_CHORD =
        1, ///< k_r = k_n l_c^2, mu_r = mu l_c from the contact chord l_c (004 ch. 4)
    SIM_ROLLING_FIXED = 2, ///< fixed rolling stiffness k_r (004 ch. 4)
} SimRollingLaw;

/// Where within a step the contact's onset and release are placed (docs/accuracy.md, "Event-aware
/// onset"). STEP: the force acts from the first step with an overlap (first order in e_n).
/// EVENT: each force evaluation is the mean of the force over the step around it, with the
/// overlap's linear trajectory locating touch and release inside the step (second order in e_n
/// with velocity Verlet; linear normal law; velocity Verlet, symplectic Euler, Stormer-Verlet).
typedef enum SimOnset {
    SIM_ONSET_STEP = 0,
    SIM_ONSET_EVENT = 1,
} SimOnset;

/// How normal damping is given.
typedef enum SimDampingMode {
    SIM_DAMPING_GAMMA = 0,       ///< gamma_n given directly, kg/s
    SIM_DAMPING_RESTITUTION = 1, ///< e_n given; gamma_n per pair from m_eff (000 eq. 3.25)
    SIM_DAMPING_CRITICAL = 2,    ///< fraction of critical damping, gamma_n = 2 f sqrt(k_n m_eff)
} SimDampingMode;

/// Material of one species. Pair parameters are the arithmetic mean of the two species' values,
/// except the friction coefficients mu and mu_r: harmonic mean (zero when either is zero).
typedef struct SimMaterial {
    double density;          ///< rho, kg/m^3 (disk mass model: kg/m^2)
    double normal_stiffness; ///< k_n, N/m (Hertz: N/m^1.5)
    SimDampingMode damping_mode;
    double normal_damping;       ///< gamma_n, kg/s (when damping_mode is GAMMA)
    double restitution;          ///< e_n in (0, 1] (when damping_mode is RESTITUTION)
    double critical_fraction;    ///< fraction of critical damping (when damping_mode is CRITICAL)
    double friction;             ///< mu, Coulomb coefficient, dimensionless
    double tangential_damping;   ///< gamma_s, kg/s, regularised Coulomb (000 eq. 3.28)
    double tangential_stiffness; ///< k_t, N/m, Cundall-Strack spring
    double rolling_friction;     ///< mu_r, m: cap |M_r| <= mu_r k_n xi (004 eq. 4.1; FIXED law)
    double rolling_stiffness;    ///< k_r, N m/rad (004 eq. 4.2; FIXED law)
    double spring_damping;       ///< gamma_t, kg/s, the spring law's tangential dashpot (Luding
                                 ///< 2008); 0: none
} SimMaterial;

/// Contact model: one law per category, the same for all pairs.
typedef struct SimContactModel {
    SimNormalLaw normal;
    SimTangentialLaw tangential; ///< used only with SIM_EFFECT_FRICTION
    SimRollingLaw rolling;       ///< used only with SIM_EFFECT_ROLLING
    int clip_tensile;            ///< 1: normal force never attractive (000 [GAP], our default 1)
    SimOnset onset;              ///< SIM_ONSET_STEP (default) or SIM_ONSET_EVENT
} SimContactModel;

/* ---------------------------------------------------------------- grains, walls */

typedef enum SimMassModel {
    SIM_MASS_DISK = 0,   ///< m = rho pi r^2, I = m r^2 / 2 (2D native; rho in kg/m^2)
    SIM_MASS_SPHERE = 1, ///< m = rho 4/3 pi r^3, I = 2/5 m r^2 (thesis 000 convention)
} SimMassModel;

/// Mass of a grain of `radius` (m) and `density` (kg/m^3 for spheres, kg/m^2 for disks) under
/// `model`, kg: the engine's own expression (the same bits as the world's masses).
double sim_grain_mass(SimMassModel model, double density, double radius);

/// Grain flags.
enum {
    SIM_GRAIN_FIXED = 1u << 0, ///< does not integrate; infinite mass in contacts
};

/// Input grains (structure of arrays; the arrays are copied by sim_world_create).
/// Optional arrays may be NULL (zeros).
typedef struct SimGrainSet {
    int count;
    const double *x, *y;   ///< centre, m
    const double *radius;  ///< m
    const double *vx, *vy; ///< m/s, optional
    const double *angle;   ///< rad, optional
    const double *omega;   ///< rad/s, optional
    const int *species;    ///< index into materials, optional (0)
    const unsigned *flags; ///< SIM_GRAIN_*, optional (0)
    const int *motion;     ///< index into motions for fixed grains, -1 = still; optional
    const uint32_t *id;    ///< stable ids; optional (0..count-1)
} SimGrainSet;

/// Kinds of prescribed motion (SIM_EFFECT_VIBRATION). Every kind is a rigid motion of the
/// walls and fixed grains that use it: a rotation by theta(t) about the origin, then a
/// translation T(t), p(t) = R(theta) p_0 + T (sim_motion_pose).
typedef enum SimMotionKind {
    SIM_MOTION_SINUSOIDAL = 0, ///< offset amplitude sin(2 pi frequency tau + phase) along direction
    SIM_MOTION_VELOCITY = 1,   ///< constant velocity (velocity_x, velocity_y): offset v tau
    SIM_MOTION_ROTATION = 2,   ///< rotation about (center_x, center_y) at angular_velocity
    SIM_MOTION_COMPOSE = 3,    ///< parts[0], then parts[1], ... applied in turn (parts defined
                               ///< before this motion: lower indices)
} SimMotionKind;

#define SIM_MOTION_MAX_PARTS 4

/// A prescribed motion and its schedule. The motion's own time is tau = t - t_0 - start, where
/// t_0 is when it was enabled (0 from the start; sim_world_set_motion). Before tau = 0 nothing
/// moves; over the first `ramp` seconds the speed (VELOCITY, ROTATION) or the amplitude
/// (SINUSOIDAL) grows linearly from 0 to its full value; at tau = stop - start the motion stops
/// where it is (velocity zero). All-zero schedule fields: running from t_0, never stopping.
typedef struct SimMotion {
    double amplitude;   ///< m (SINUSOIDAL)
    double frequency;   ///< Hz (SINUSOIDAL)
    double phase;       ///< rad (SINUSOIDAL)
    double direction_x; ///< unit vector, dimensionless (SINUSOIDAL)
    double direction_y;
    SimMotionKind kind;
    double velocity_x, velocity_y;   ///< m/s (VELOCITY)
    double center_x, center_y;       ///< rotation centre, m (ROTATION)
    double angular_velocity;         ///< rad/s, counter-clockwise positive (ROTATION)
    double start;                    ///< s after t_0 at which the motion starts
    double ramp;                     ///< s of linear ramp-up from start (0 = none)
    double stop;                     ///< s after t_0 at which it stops (0 = never); > start
    int part_count;                  ///< COMPOSE: number of parts
    int parts[SIM_MOTION_MAX_PARTS]; ///< COMPOSE: motion indices, each lower than this one's
} SimMotion;

/// A rigid pose p = R(angle) p_0 + (x, y), and its rate: the velocity of the point now at q is
/// (vx, vy) + omega z x (q - (x, y)).
typedef struct SimPose {
    double angle, x, y;   ///< rad, m, m
    double omega, vx, vy; ///< rad/s, m/s, m/s
} SimPose;

/// The pose of motion `index` of `motions` at its own time tau (the schedule applied; tau < 0:
/// the identity). Composite motions combine their parts (each part at the same tau).
SimPose sim_motion_pose(const SimMotion *motions, int index, double tau);

typedef enum SimWallShape {
    SIM_WALL_SEGMENT = 0, ///< straight segment (x0, y0)-(x1, y1)
    SIM_WALL_ARC = 1,     ///< circular arc about (center_x, center_y)
} SimWallShape;

/// Which side of an arc grains touch.
typedef enum SimWallSide {
    SIM_WALL_BOTH = 0,    ///< either side (and the ends)
    SIM_WALL_INSIDE = 1,  ///< only grains inside the circle (a drum): pushed towards the centre
    SIM_WALL_OUTSIDE = 2, ///< only grains outside (an obstacle): pushed away from the centre
} SimWallSide;

/// A wall: a straight segment from (x0, y0) to (x1, y1) whose both sides and ends grains touch,
/// or a circular arc of `radius` about (center_x, center_y) from angle0 counter-clockwise to
/// angle1 (angle1 - angle0 >= 2 pi: the full circle), touched on `side`.
typedef struct SimWall {
    double x0, y0, x1, y1; ///< m (segments)
    int species;           ///< material index
    int motion;            ///< index into motions, -1 = still
    SimWallShape shape;
    SimWallSide side;          ///< arcs
    double center_x, center_y; ///< arc centre, m
    double radius;             ///< arc radius, m
    double angle0, angle1;     ///< arc span, rad
} SimWall;

/// A wall that responds to the grains (a piston, a servo-controlled wall): it translates as one
/// rigid body along the unit direction `axis`, which points from the wall into the grains it
/// holds. Its normal load N is the force of the grains on it against the axis, -F.axis, and its
/// normal stress N / length (force per length in 2D). Without a servo it is a free body of
/// `mass`: m du/dt = F.axis + force.axis (+ m g.axis with `gravity`). With a servo its speed
/// along the axis is set each step by the gain law of Yade's TriaxialStressController and of
/// PFC's servo-controlled walls (Itasca, PFC2D manual, "servo-control"):
///     u = gain (target - measured), |u| <= max_speed,
/// measured = N / length (servo_stress) or N (servo_force); the wall moves into the grains
/// while they push less than the target. The contacts' normal dashpots make the measured load
/// depend on the speed itself, N = N_el + c u (c the sum over the wall's contacts of their
/// normal damping coefficients, projected on the axis): a wall's servo (servo_explicit 0) takes
/// the new speed from the linearised backward Euler step of that dependence,
///     u = gain (target - N + c' u_old) / (1 + gain c'), c' = c (force) or c / length (stress),
/// u_old the speed the contacts saw (the same fixed point, u = 0 at N = target; no feedback
/// through the dashpots at any gain). Stability (sim_wall_servo_time): a wall touching
/// grains of diameter >= d with contact stiffness k_n stiffens by about k_n / d per length, so
/// the error shrinks by a factor 1 - dt / tau each step with tau = d / (gain k_n) (stress;
/// d / (gain k_n length) for a force); dt > tau overshoots and dt > 2 tau diverges, so a gain
/// with dt > tau is refused. With the explicit law (servo_explicit 1, and a grain body's) the
/// contacts' damping feeds the wall speed back too (sim_wall_servo_damping): a gain at which one
/// contact's dashpot flips the speed is refused, and a speed that flips between the caps
/// +-max_speed on consecutive steps for more than SIM_SERVO_FLIP_STEPS steps is counted
/// (SimWallLoad servo_flips).
/// With `rotation` the body also turns about its centre (a segment's midpoint, an arc's centre,
/// a grain body's area-weighted centroid at rest), counterclockwise positive:
/// I domega/dt = T, T the torque of the grains' contact forces about that centre, integrated
/// by the same symplectic Euler as the translation (omega from T, then the angle from omega).
/// I is `inertia` when > 0, else from the mass and the geometry: m L^2 / 12 for a segment
/// (a thin rod about its midpoint), m R^2 for an arc (a thin ring about its centre), for a grain
/// body m sum_i a_i (|c_i - c|^2 + r_i^2 / 2) / sum_i a_i (the mass spread over the grains'
/// discs by area a_i = pi r_i^2). The servo drives the translation only.
/// The same struct declares a grain body (SimWorldDef.grain_bodies, a rough piston): the fixed
/// grains whose motion is SIM_GRAIN_BODY(b) move as one rigid body; its load is the sum of the
/// contact forces of the mobile grains on them, its length their extent across the axis.
typedef struct SimWallBody {
    int active;              ///< 0: the wall is still or follows its motion (the rest unused)
    double axis_x, axis_y;   ///< unit direction of its motion, into the grains; (0, 0): it
                             ///< does not translate (hinged at its centre: rotation, no servo)
    double mass;             ///< kg (free body; unused with a servo)
    double force_x, force_y; ///< applied force, N (its part along the axis acts)
    int gravity;             ///< 1: the world's gravity acts on the mass
    int servo;               ///< 0 none, 1 target stress, 2 target force
    double target;           ///< N/m (stress) or N (force)
    double gain;             ///< servo gain, m/s per N/m (stress) or per N (force)
    double max_speed;        ///< servo speed cap, m/s
    /// The length a stress target is taken over (measured = N / length; docs/scenes.md,
    /// "servo"): 0 the body's own length (a wall's; a grain body's extent across its axis), 1
    /// `length` (m), 2 the current distance across the axis between walls `between[0]` and
    /// `between[1]` (segments parallel to the axis: the sample's width between them, as Yade's
    /// TriaxialStressController takes the box size).
    int length_kind;
    double length;  ///< m (length_kind 1)
    int between[2]; ///< wall indices (length_kind 2)
    int rotation;   ///< 1: it also turns freely about its centre
    double inertia; ///< moment of inertia about its centre, kg m^2; 0: from the mass
    /// How the servo's speed treats the contacts' normal dashpots: 0 implicit for a wall (the
    /// speed solved together with the dashpot part of the load it causes, linearised backward
    /// Euler; explicit for a grain body, whose contacts are grain pairs), 1 explicit (the gain
    /// law on the load as measured; a gain whose dashpots flip the speed is refused).
    int servo_explicit;
} SimWallBody;

/// The motion index that makes a fixed grain a member of grain body b (SimWorldDef.grain_bodies).
#define SIM_GRAIN_BODY(b) (-2 - (b))

/// What the grains do to a wall in the last force evaluation, and where it is.
typedef struct SimWallLoad {
    double fx, fy;     ///< total force of the grains on the wall, N
    double normal;     ///< sum of the contacts' normal forces (>= 0 pushing), N
    double tangential; ///< segments: F along (x0, y0) -> (x1, y1); arcs: torque / radius, N
    double torque;     ///< about the wall's centre (segment midpoint, arc centre), N m
    double length;     ///< segment length or arc length, m
    double x, y;       ///< the wall's centre now, m
    double offset;     ///< responding walls: displacement along the axis, m (else 0)
    double speed;      ///< responding walls: speed along the axis, m/s (else 0)
    int contacts;      ///< grains touching it
    /// servos: the steps spent in flipping runs (the speed at +max_speed and -max_speed on
    /// consecutive steps for more than SIM_SERVO_FLIP_STEPS steps: the load then alternates
    /// between two values every step, and a mean over rows a multiple of 2 steps apart reads
    /// one of them), counted since the run began (0: never)
    long servo_flips;
    double servo_flip_time; ///< the time the first flipping run was found, s (NaN: never)
} SimWallLoad;

/// The flipping run a servo's speed must exceed to count (SimWallLoad servo_flips), steps.
#define SIM_SERVO_FLIP_STEPS 20

/// Contact distance from a grain of `radius` at (x, y) to the wall: the distance to a segment;
/// for an arc the distance to the circle on the touched side (negative for a centre pushed past
/// a one-sided arc, HUGE_VAL on its far side), m. Overlap = radius - distance.
double sim_wall_contact_distance(const SimWall *wall, double x, double y, double radius);
/// The point at s in [0, 1] along the wall (from (x0, y0) or angle0), m.
void sim_wall_point(const SimWall *wall, double s, double *x, double *y);
/// A box around the wall (arcs: their whole circle), m.
void sim_wall_bounds(const SimWall *wall, double *x0, double *y0, double *x1, double *y1);

typedef enum SimSinkShape {
    SIM_SINK_BELOW = 0, ///< remove grains with y < level
    SIM_SINK_ABOVE = 1, ///< y > level
    SIM_SINK_LEFT = 2,  ///< x < level
    SIM_SINK_RIGHT = 3, ///< x > level
    SIM_SINK_RECT = 4,  ///< centre inside [x0, x1] x [y0, y1]
} SimSinkShape;

/// A region where mobile grains are removed; the removed grains are counted per sink.
typedef struct SimSink {
    SimSinkShape shape;
    double level;          ///< m (BELOW/ABOVE/LEFT/RIGHT)
    double x0, y0, x1, y1; ///< m (RECT)
} SimSink;

/* ---------------------------------------------------------------- integrators */

typedef enum SimIntegrator {
    SIM_INTEGRATOR_VELOCITY_VERLET = 0,  ///< default, second order, symplectic
    SIM_INTEGRATOR_SYMPLECTIC_EULER = 1, ///< 000 eqs. 4.16-4.17, first order
    SIM_INTEGRATOR_STORMER_VERLET = 2,   ///< 000 eqs. 4.18-4.19 (position Verlet)
    SIM_INTEGRATOR_GEAR = 3,             ///< Gear predictor-corrector, third order (002)
    SIM_INTEGRATOR_RK4 = 4,              ///< classical Runge-Kutta
    SIM_INTEGRATOR_COUNT
} SimIntegrator;

/// "velocity_verlet", "symplectic_euler", "stormer_verlet", "gear", "rk4"; -1 when unknown.
int sim_integrator_from_name(const char *name);
const char *sim_integrator_name(SimIntegrator integrator);

/* ---------------------------------------------------------------- body-force extension */

/// View handed to a body-force stage (fluid drag): mobile grains only, forces to add to.
typedef struct SimBodyForceView {
    int count;
    double time;                                   ///< s
    const double *x, *y, *vx, *vy, *radius, *mass; ///< m, m/s, m, kg
    double *fx, *fy;                               ///< N, add to these
} SimBodyForceView;

/// A body-force stage, called once per force evaluation when SIM_EFFECT_FLUID_DRAG is declared.
typedef struct SimBodyForce {
    void (*apply)(void *context, const SimBodyForceView *view);
    void *context;
} SimBodyForce;

/* ---------------------------------------------------------------- world definition */

#define SIM_MAX_SPECIES 8
#define SIM_MAX_MOTIONS 8
#define SIM_MAX_SINKS   16

typedef struct SimWorldDef {
    unsigned effects; ///< SimEffect bits
    SimContactModel contact;
    SimMassModel mass_model;
    int species_count;
    SimMaterial materials[SIM_MAX_SPECIES];
    double gravity_x, gravity_y; ///< m/s^2 (default 0, -9.806)
    SimIntegrator integrator;
    double time_step;         ///< dt, s; 0 = choose from steps_per_contact
    double steps_per_contact; ///< used when time_step is 0 (default 50)
    double max_dt_fraction;   ///< refuse dt > fraction * t_c,min; 0 = use the stability limit only
    double skin;              ///< Verlet skin, m; 0 = automatic (0.01-0.2 mean diameter)
    double domain_x0, domain_x1; ///< periodic x range, m (SIM_EFFECT_PERIODIC_X)
    SimGrainSet grains;
    int wall_count;
    const SimWall *walls;
    const SimWallBody *wall_bodies; ///< wall_count entries, or NULL: no wall responds
    /// Rigid groups of fixed grains that respond (rough pistons): body b holds the fixed grains
    /// whose motion is SIM_GRAIN_BODY(b); every entry active. A body whose group has no grain
    /// is dormant (it neither moves nor is checked) until its grains join, all at once, by
    /// sim_world_add_grains: it then moves from where they were put, at rest.
    const SimWallBody *grain_bodies;
    int grain_body_count;
    int motion_count;
    SimMotion motions[SIM_MAX_MOTIONS]; ///< refused when a motion's speed bound times dt exceeds
                                        ///< half the smallest mobile radius (wall-speed limit)
    int sink_count;
    SimSink sinks[SIM_MAX_SINKS];
    SimBodyForce body_force;    ///< SIM_EFFECT_FLUID_DRAG
    double guard_max_overlap;   ///< stop when xi / d_min of a pair exceeds this (default 0.5)
    double guard_max_speed;     ///< stop when a grain exceeds this speed, m/s; 0 = automatic
                                ///< (docs/physics.md, "Guard": a flow accelerating without
                                ///< bound is told apart from a numerical blow-up)
    int guard_every;            ///< steps between guard checks (default 100)
    double max_initial_overlap; ///< refuse start overlaps of new grains above this fraction of
                                ///< d_min (0.1); restored grains (sim_world_load) are exempt
    double length_scale;        ///< D of t* = t / sqrt(D/g) and E* = E/(m g D), m (0 = mean d)
    double start_time;          ///< s
} SimWorldDef;

/// Defaults: every field physically valid (no grains).
SimWorldDef sim_world_def_default(void);
/// The servo's time scale tau of wall `wall` (SimWallBody), s: INFINITY without a servo or
/// without mobile grains. A time step above tau is refused (sim_world_def_validate).
double sim_wall_servo_time(const SimWorldDef *def, int wall);
/// 1 when body `wall` (a wall, or grain body wall - wall_count) has a servo on the implicit law
/// (SimWallBody servo_explicit 0 on a wall), else 0.
int sim_wall_servo_implicit(const SimWorldDef *def, int wall);
/// The servo's damping feedback of wall `wall` per contact (dimensionless): how much a wall speed
/// set at one step changes the next through one contact's normal dashpot, gain gamma_n / length
/// (stress; gain gamma_n for a force); 0 without a servo or on the implicit law (which solves the
/// dashpots' part with the new speed: no feedback). With n contacts the factor is n times
/// this, and at 1 or more the wall's speed flips sign every step: a factor >= 1 for one contact
/// is refused, and `sablier check` warns when a row of the smallest grains along the wall
/// (*row contacts) would reach 1.
double sim_wall_servo_damping(const SimWorldDef *def, int wall, double *row);
SimMaterial sim_material_default(void);

/* ---------------------------------------------------------------- status and errors */

typedef enum SimStatus {
    SIM_OK = 0,
    SIM_ERROR_INVALID = 2,  ///< bad definition (maps to exit status 2)
    SIM_ERROR_UNSTABLE = 1, ///< NaN, overlap beyond bound, blow-up (exit status 1)
    SIM_ERROR_IO = 3,       ///< file could not be read or written
    SIM_ERROR_MEMORY = 4,   ///< out of memory (docs/dev/errors.md; maps to exit status 2)
} SimStatus;

/// Error report: field is a dotted path into SimWorldDef ("time_step", "materials[1].restitution",
/// "grains[12]"), so a scene loader can map it back to a file line.
typedef struct SimError {
    SimStatus status;
    char field[64];
    char message[400];
    long step;  ///< step at which a run failed, -1 if none
    long grain; ///< stable id of the grain involved, -1 if none
} SimError;

/* ---------------------------------------------------------------- world */

typedef struct SimWorld SimWorld;

/// Contact-time figures of the declared laws, for the stiffest, lightest pair.
typedef struct SimTiming {
    double contact_time_min;  ///< t_c of the worst pair, s (000 eq. 3.22; Hertz at v = 1 m/s)
    double stability_limit;   ///< largest stable dt of the integrator in a dense packing, s
    double time_step;         ///< dt in use, s
    double steps_per_contact; ///< t_c,min / dt
    double restitution;       ///< e_n of the worst pair, exp(-pi zeta / sqrt(1 - zeta^2)) (linear)
} SimTiming;

/// Checks a definition without building a world (same checks as create).
SimStatus sim_world_def_validate(const SimWorldDef *def, SimError *error);
/// Timing figures of a definition (valid or not, as long as materials and grains are readable).
SimTiming sim_world_def_timing(const SimWorldDef *def);

SimWorld *sim_world_create(const SimWorldDef *def, SimError *error);
void sim_world_destroy(SimWorld *world);

/// Advance by `steps` time steps. Returns SIM_OK or SIM_ERROR_UNSTABLE (error filled; the world is
/// rolled back to the last good guard check, so saving it then saves the last good state), or
/// SIM_ERROR_MEMORY when memory ran out in the step or in an edit before it (neighbour lists,
/// removal, sorting): that world cannot continue and is only fit for sim_world_destroy.
SimStatus sim_world_step(SimWorld *world, long steps, SimError *error);

double sim_world_time(const SimWorld *world); ///< s
long sim_world_step_count(const SimWorld *world);
double sim_world_time_step(const SimWorld *world);
unsigned sim_world_effects(const SimWorld *world);
SimTiming sim_world_timing(const SimWorld *world);
int sim_world_grain_count(const SimWorld *world); ///< all grains, mobile and fixed
int sim_world_mobile_count(const SimWorld *world);
/// The Verlet skin in use, m (it changes at list builds when the skin is automatic).
double sim_world_skin(const SimWorld *world);
/// Neighbour-list builds so far (the one at creation included).
long sim_world_list_builds(const SimWorld *world);
/// Entries of the neighbour list now: the grain pairs within the cut-off and the skin, each once
/// (the contact pass's work per step grows with them).
long sim_world_list_entries(const SimWorld *world);
/// Threads of the physics step (default 1; values below 1 mean 1): the world keeps threads - 1
/// POSIX worker threads until destroyed (fewer when the system refuses some; sim_world_threads
/// says how many run). The contact forces, their per-grain sums and the velocity-Verlet
/// integration run over fixed ranges, and every sum is taken in the same order as with one
/// thread: the results are the same bits whatever the count. The list build, sorting, wall
/// contacts, body forces and the other integrators stay on the calling thread.
void sim_world_set_threads(SimWorld *world, int threads);
int sim_world_threads(const SimWorld *world);
/// The CPUs this process may run on: its affinity mask's count (taskset, a batch system's
/// cgroup), else the online CPUs; at least 1. What `--threads auto`, a movie's drawing bands
/// and llvmpipe's threads stay within.
int sim_cpu_count(void);

/// The clocks a run, a renderer or a benchmark times itself with.
typedef enum SimClock {
    SIM_CLOCK_WALL = 0,    ///< monotonic wall time (CLOCK_MONOTONIC)
    SIM_CLOCK_PROCESS = 1, ///< CPU time of the process, all threads (CLOCK_PROCESS_CPUTIME_ID)
    SIM_CLOCK_THREAD = 2   ///< CPU time of the calling thread (CLOCK_THREAD_CPUTIME_ID)
} SimClock;

/// The reading of `clock`, s (a difference of two readings is a duration; their origin is the
/// system's). An unknown value reads the wall clock.
double sim_clock_seconds(SimClock clock);

/* ---------------------------------------------------------------- instruction sets */

/// The instruction sets of the hot loops (contact passes, integrator steps): each is compiled
/// once per set and one copy is chosen at run time, so one binary runs on any x86-64 at the
/// speed of its CPU. Every path gives the same bits (no FMA, exactly rounded operations;
/// docs/dev/isa.md).
typedef enum SimIsa {
    SIM_ISA_BASELINE = 0, ///< "sse2" on x86-64 ("generic" elsewhere): runs everywhere
    SIM_ISA_AVX2 = 1,     ///< "avx2"
    SIM_ISA_AVX512 = 2,   ///< "avx512": AVX-512 F and VL
    SIM_ISA_NATIVE = 3,   ///< "native": a -DSABLIER_NATIVE=ON build, its only path
    SIM_ISA_COUNT = 4
} SimIsa;

/// "sse2", "avx2", "avx512", "native" (the baseline is "generic" off x86); NULL out of range.
const char *sim_isa_name(SimIsa isa);
/// The set named `name` (sim_isa_name's words), or -1.
int sim_isa_from_name(const char *name);
/// 1 when the set is compiled into this library and this CPU runs it.
int sim_isa_supported(SimIsa isa);
/// The set that worlds created from now on use: the one sim_isa_set chose, else the environment
/// variable SABLIER_ISA when it names a supported set, else the fastest supported one.
SimIsa sim_isa(void);
/// Chooses the set for the worlds created afterwards (worlds already created keep theirs).
/// SIM_ERROR_INVALID, nothing changed, when the set is not supported. Not for use while another
/// thread creates worlds.
SimStatus sim_isa_set(SimIsa isa);

/* ---------------------------------------------------------------- frame view */

/// One contact, counted once.
typedef struct SimContact {
    int i, j;                ///< frame indices; j = -1 - wall index for a wall contact
    double normal_force;     ///< F_n, N (positive = repulsive)
    double tangential_force; ///< F_t along s, N
    double overlap;          ///< xi, m
    double x, y;             ///< contact point, m
    double nx, ny;           ///< unit normal n from grain i towards j (or the wall)
} SimContact;

/// Transient read-only view of the state: valid until the next call that changes the world.
/// Arrays have `count` entries in frame order (mobile grains first, then fixed grains).
typedef struct SimFrame {
    int count;
    int mobile_count;
    long step;
    double time;                          ///< s
    double time_scale;                    ///< sqrt(D/g) for t* = t / time_scale, s (0 if unknown)
    const double *x, *y, *angle, *radius; ///< m, m, rad, m
    const double *vx, *vy, *omega;        ///< m/s, rad/s
    const int *species;
    const unsigned *flags;
    const uint32_t *id;
    const double *force; ///< per-grain sum of contact-force magnitudes, N (000 figs. 6.16-7.2)
    const double *fx,
        *fy;              ///< per-grain contact + body force of the last evaluation (no gravity), N
    const double *torque; ///< per-grain torque of the last evaluation, N m
    int contact_count;
    const SimContact *contacts;
    int wall_count;
    const SimWall *walls; ///< current positions (moving walls displaced)
    int periodic;         ///< 1 when x is periodic over [domain_x0, domain_x1]
    double domain_x0, domain_x1;
} SimFrame;

/// Fills a frame view; computes per-grain forces and the contact list.
void sim_world_frame(SimWorld *world, SimFrame *frame);

/// A consumer of frames (renderers, writers, hashers). Must copy what it keeps.
typedef struct SimFrameSink {
    int (*consume)(void *context, const SimFrame *frame); ///< nonzero = stop the run
    void *context;
} SimFrameSink;

/* ---------------------------------------------------------------- diagnostics */

typedef struct SimEnergy {
    double kinetic;    ///< sum 1/2 m v^2, J
    double potential;  ///< sum m g y (relative to y = 0), J
    double rotational; ///< sum 1/2 I omega^2, J
    double elastic;    ///< sum over contacts of the spring energy, J
    double total;      ///< J
    int mobile;        ///< grains counted
    int contacts;      ///< contacts in force
} SimEnergy;

SimEnergy sim_world_energy(SimWorld *world);
/// Mean coordination number of mobile grains (contacts per grain, wall contacts included); NAN
/// when out of memory.
double sim_world_coordination(SimWorld *world);
/// Packing fraction (area of disks in the region / area of the region), disks clipped exactly.
double sim_world_packing_fraction(const SimWorld *world, double x0, double y0, double x1,
                                  double y1);
/// Largest xi / min(d_i, d_j) over current contacts.
double sim_world_max_overlap_ratio(SimWorld *world);
/// Total contact force exerted by mobile grains on the fixed grains of a species (species < 0: all
/// fixed grains), N.
void sim_world_fixed_load(SimWorld *world, int species, double *fx, double *fy);
/// Mean diameter and mean mass of mobile grains (for t* and E*, 000 §6.2).
void sim_world_means(const SimWorld *world, double *diameter, double *mass);
/// Grains removed by each sink so far.
long sim_world_removed_count(const SimWorld *world, int sink);
/// Sum of mobile-grain momentum, kg m/s.
void sim_world_momentum(const SimWorld *world, double *px, double *py);
/// FNV-1a hash of positions, velocities and angles of all grains (determinism checks).
uint64_t sim_world_hash(const SimWorld *world);

/* ---------------------------------------------------------------- analysis */

/// Lucy kernel of cutoff radius c, normalised over the plane (Lucy 1977; the MercuryCG default,
/// Weinhart et al. 2012): W(r) = 5 / (pi c^2) (1 + 3 s)(1 - s)^3 with s = r / c for r < c, else
/// 0 (also 0 when c <= 0); 1/m^2. The one coarse-graining kernel of app/ and render/.
double sim_kernel_lucy(double r, double c);

/* ================================================================ coarse graining (sim/coarse.c)
 * Continuum fields from a frame by kernel coarse-graining (Goldhirsch 2010; Weinhart et al. 2012,
 * "From discrete particles to continuum fields near a boundary", Granular Matter 14: 289), the
 * one implementation of the app's measures (app/output/measures.c) and of render's velocity field.
 * Mobile grains only; contacts between a mobile grain and a fixed grain or a wall count.
 *
 *     SimCoarseDef cd = sim_coarse_def_default();
 *     cd.geometry = SIM_COARSE_PROFILE_Y; cd.x0 = 0; cd.x1 = 1; cd.y0 = 0; cd.ny = 40;
 *     cd.cell_y = 0.05; cd.width = 0.1; cd.contacts = 1;
 *     SimCoarse *cg = sim_coarse_create(&cd, &err);
 *     sim_world_frame(world, &frame); sim_world_masses(world, mass);
 *     sim_coarse_add(cg, &frame, mass, 0.0, 0.0);           // one sample (repeat to average)
 *     sim_coarse_field(cg, SIM_CG_SYY, syy);                 // per node, averaged over samples
 *
 * Stress sign: compression positive (sigma_yy of a pile at rest = weight above per width). In
 * 2D, densities are per unit area (kg/m^2) and stresses per unit length (N/m). */

/// Kernels; `width` is the cutoff radius c for both.
typedef enum SimKernel {
    SIM_KERNEL_LUCY = 0,     ///< W = 5/(pi c^2) (1 + 3 s)(1 - s)^3, s = r / c (Lucy 1977)
    SIM_KERNEL_GAUSSIAN = 1, ///< sigma = c / 3, cut at c and renormalised (1 - e^-4.5)
} SimKernel;

/// Kernel value W(r) of cutoff radius c, normalised over the plane, 1/m^2 (0 for r >= c, c <= 0).
double sim_kernel(SimKernel kernel, double r, double c);
/// The same kernel integrated over x at height y (psi(y) = int W(sqrt(x^2 + y^2)) dx, exact:
/// closed forms for Lucy and the cut Gaussian), 1/m: the kernel of the 1D profiles.
double sim_kernel_1d(SimKernel kernel, double y, double c);

typedef enum SimCoarseGeometry {
    SIM_COARSE_GRID = 0,      ///< nx x ny nodes at cell centres x0 + (i + 1/2) cell_x, ...
    SIM_COARSE_PROFILE_Y = 1, ///< ny bins along y, averaged over x in [x0, x1]
    SIM_COARSE_PROFILE_X = 2, ///< nx bins along x, averaged over y in [y0, y1]
} SimCoarseGeometry;

/// Upper bound of nodes of one coarse-grained field (16 doubles per node).
#define SIM_COARSE_MAX_NODES (1 << 20)

typedef struct SimCoarseDef {
    SimKernel kernel;
    double width; ///< kernel cutoff radius c, m (>= the cell side when normalise is 1)
    SimCoarseGeometry geometry;
    double x0, y0;         ///< lower-left corner of node cell (0, 0), m
    double cell_x, cell_y; ///< node spacing, m (PROFILE_Y: cell_x unused; PROFILE_X: cell_y)
    int nx, ny;            ///< nodes (PROFILE_Y: nx unused; PROFILE_X: ny unused)
    double x1, y1; ///< averaging strip of a profile: PROFILE_Y over x in [x0, x1], PROFILE_X over
                   ///< y in [y0, y1], m (a grid ignores them)
    int contacts;  ///< 1: contact stress, coordination and fabric too (reads frame contacts)
    /// 1: each point's weights are divided by their sum over the infinite node lattice (times the
    /// cell area), so the field integrates to the grains' totals exactly (to rounding) wherever
    /// the support lies inside the nodes; 0: the plain kernel values (render's field).
    int normalise;
} SimCoarseDef;

/// Accumulated sums per node (averaged over samples by sim_coarse_field).
typedef enum SimCoarseField {
    SIM_CG_PHI = 0, ///< packing fraction sum pi r_i^2 W
    SIM_CG_RHO,     ///< density sum m_i W, kg/m^2
    SIM_CG_JX,      ///< momentum density sum m_i v_i W, kg/(m s)
    SIM_CG_JY,
    SIM_CG_VX, ///< V = j / rho, m/s (0 where rho = 0)
    SIM_CG_VY,
    SIM_CG_T,   ///< granular temperature tr(sigma_k) / (2 rho), m^2/s^2 (Weinhart et al. 2012)
    SIM_CG_KXX, ///< kinetic stress sum m v'v' W = sum m v v W - j j / rho, N/m (v' = v - V(r))
    SIM_CG_KXY,
    SIM_CG_KYY,
    SIM_CG_CXX, ///< contact stress sum_c f_a r_b int_0^1 W(r - r_i + s r_ic) ds, N/m (a, b)
    SIM_CG_CXY,
    SIM_CG_CYX,
    SIM_CG_CYY,
    SIM_CG_SXX, ///< total stress, contact + kinetic, N/m
    SIM_CG_SXY,
    SIM_CG_SYX,
    SIM_CG_SYY,
    SIM_CG_P,   ///< pressure (sxx + syy) / 2, N/m
    SIM_CG_Z,   ///< coordination sum z_i W / sum W (wall and fixed-grain contacts included)
    SIM_CG_FXX, ///< fabric sum_i (sum_c n n) W / sum W (trace = z)
    SIM_CG_FXY,
    SIM_CG_FYY,
    SIM_CG_FIELD_COUNT
} SimCoarseField;

/// "phi", "rho", "jx", "jy", "vx", "vy", "T", "kxx", ... "sxx", "sxy", "syx", "syy", "p", "z",
/// "fxx", "fxy", "fyy"; -1 when unknown.
int sim_coarse_field_from_name(const char *name);
const char *sim_coarse_field_name(SimCoarseField field);
/// Unit of a field ("1", "kg/m^2", "N/m", ...).
const char *sim_coarse_field_unit(SimCoarseField field);
/// 1 when the field needs the contacts (SimCoarseDef.contacts).
int sim_coarse_field_needs_contacts(SimCoarseField field);

typedef struct SimCoarse SimCoarse;

SimCoarseDef sim_coarse_def_default(void);
/// NULL with SIM_ERROR_INVALID (width <= 0, no nodes, too many nodes, width below the cell side
/// when normalising) or SIM_ERROR_MEMORY.
SimCoarse *sim_coarse_create(const SimCoarseDef *def, SimError *error);
void sim_coarse_destroy(SimCoarse *cg);
/// Nodes and the position of node k (profiles: the other coordinate is the strip's middle), m.
int sim_coarse_nodes(const SimCoarse *cg);
void sim_coarse_node(const SimCoarse *cg, int k, double *x, double *y);
/// Adds one sample of a frame: mass[i] per frame index (kg; NULL: pi r^2), velocities taken
/// relative to (frame_vx, frame_vy) (a moving box's frame), m/s. Periodic frames wrap in x.
/// SIM_OK or SIM_ERROR_MEMORY (the sample is then not counted).
SimStatus sim_coarse_add(SimCoarse *cg, const SimFrame *frame, const double *mass, double frame_vx,
                         double frame_vy);
int sim_coarse_samples(const SimCoarse *cg);
/// Forgets every sample.
void sim_coarse_clear(SimCoarse *cg);
/// The accumulated sums behind the fields (sim_coarse_sum_count doubles), copied out or back
/// in with the number of samples they hold: a run continued from a checkpoint (sablier run
/// --resume) goes on with the same bits.
long sim_coarse_sum_count(const SimCoarse *cg);
void sim_coarse_get_sums(const SimCoarse *cg, double *sums);
void sim_coarse_set_sums(SimCoarse *cg, const double *sums, int samples);
/// The field at every node, from the sums averaged over the samples (0 without samples).
void sim_coarse_field(const SimCoarse *cg, SimCoarseField field, double *out);
/// Masses of the world's grains in frame order (count = sim_world_grain_count), kg.
void sim_world_masses(const SimWorld *world, double *mass);

/// Flux counter through a segment (sim/coarse.c): mobile grains whose centre crossed it between
/// two updates, +1 from the left of the directed segment (x0, y0) -> (x1, y1) to its right (a
/// segment drawn left to right counts downward flow positive), -1 back.
typedef struct SimFlux SimFlux;
SimFlux *sim_flux_create(double x0, double y0, double x1, double y1);
void sim_flux_destroy(SimFlux *flux);
/// Compares every mobile grain's centre with its position at the last update (by stable id;
/// new grains are only recorded). Call every step for an exact count. SIM_OK or
/// SIM_ERROR_MEMORY.
SimStatus sim_flux_update(SimFlux *flux, const SimWorld *world);
/// Signed grains and mass (kg) that crossed since creation.
void sim_flux_totals(const SimFlux *flux, long *count, double *mass);
/// Sets the totals (a run continued from a checkpoint: the counter updated once at the
/// checkpoint's world, then these totals, counts on as the uninterrupted one).
void sim_flux_set_totals(SimFlux *flux, long count, double mass);

/// Free surface: for each of `bins` equal bins over [x0, x1], the highest top (y + r) of a mobile
/// grain whose centre lies in the bin, m; NAN for an empty bin (000 §5.4).
void sim_world_surface_profile(const SimWorld *world, double x0, double x1, int bins,
                               double *heights);
/// Mean local hexatic order |psi_6| of mobile grains with at least two neighbours closer than
/// 1.1 (r_i + r_j); about 1 for a triangular crystal, about 0.4-0.6 for a random packing; NAN
/// when out of memory.
double sim_world_hexatic_order(SimWorld *world);

/// Static-equilibrium test of thesis 004 §3.1 (all criteria must hold).
typedef struct SimEquilibrium {
    int equilibrium;      ///< 1 when every criterion holds
    double kinetic_max;   ///< largest translational kinetic energy of a grain, J
    double kinetic_bound; ///< tolerance * m_min g d, J
    double base_force;    ///< vertical force of mobile grains on fixed grains and walls, N
    double weight;        ///< total weight of mobile grains, N
    double force_bound;   ///< tolerance * m_min g, N
    int sliding_contacts; ///< contacts at the Coulomb cap slipping faster than sqrt(tol g d)
    int underconnected;   ///< mobile grains with fewer than two contacts
} SimEquilibrium;

/// Evaluates the criteria with the given relative tolerance (thesis: 1e-6).
SimEquilibrium sim_world_equilibrium(SimWorld *world, double tolerance);

/// Arch search of thesis 004 §2.5 over a frame's contact graph, with the one-sided bug fixed:
/// the keystone is the lowest mobile grain with |x - center_x| < d_mean/2; each branch walks to
/// the lowest grain within a window of one diameter beside and below the current grain, which
/// must touch it, until a grain touching a fixed grain or wall; both branches must reach the base
/// on their own and the arch must have at least three grains. With check_forces, every link
/// between consecutive arch grains must carry a positive normal force.
/// Writes the frame indices of the arch grains, left to right, into members (up to
/// max_members) and returns their number, or 0 when there is no arch.
int sim_frame_find_arch(const SimFrame *frame, double center_x, int check_forces, int *members,
                        int max_members);

/* ---------------------------------------------------------------- editing */

/// Remove mobile grains whose centre lies in the rectangle; returns how many.
int sim_world_remove_rect(SimWorld *world, double x0, double y0, double x1, double y1);
/// Remove the grains with these stable ids (mobile or fixed); returns how many were found.
int sim_world_remove_ids(SimWorld *world, const uint32_t *ids, int count);
/// Add grains to a running world (rain-like deposition, 004 §3.1). Their ids must not be in use;
/// without ids they get fresh ones above every id in use. Returns SIM_OK, SIM_ERROR_INVALID
/// (bad grain, unknown species, an overlap above max_initial_overlap with a grain present, a pair
/// of a new grain with a grain in place whose stability limit is below the time step, grains of
/// a grain body that already moves, a dormant grain body they wake that fails its checks) or
/// SIM_ERROR_MEMORY (the world unchanged, unless the failure came in the rebuild after the
/// addition: then sim_world_step reports it too).
SimStatus sim_world_add_grains(SimWorld *world, const SimGrainSet *grains, SimError *error);
/// Set every velocity and angular velocity to zero.
void sim_world_freeze(SimWorld *world);
/// Writes grains in place between steps (a servo, a shaker, a caller's hook). `values->id` names
/// the grains by stable id (`count` of them); without ids, `count` must be
/// sim_world_grain_count and the values are in frame order. Each non-NULL array is written: x
/// and y together (centre, m), vx and vy together (m/s), angle (rad), omega (rad/s), radius (m:
/// mass and moment of inertia follow), flags (SIM_GRAIN_FIXED or 0: a grain made fixed stops
/// where it is, without motion; a grain set free keeps its place; the frame order then changes).
/// Velocities given to fixed grains are ignored; species and motion must be NULL. The lists are
/// then built and the forces evaluated at the new state, and the integrator restarts, as after
/// sim_world_freeze. SIM_ERROR_INVALID, nothing changed: an unknown id, a value that is not
/// finite, a radius <= 0, an unknown flag, a pair whose stability limit falls below the time step.
/// SIM_ERROR_MEMORY: out of memory (after the writes: the world is only fit for destroy).
SimStatus sim_world_set_grains(SimWorld *world, const SimGrainSet *values, SimError *error);
/// What the grains do to wall `wall` in the last force evaluation (SimWallLoad); -1 when out of
/// range. wall_count + b is grain body b (SimWorldDef.grain_bodies): fx, fy and torque sum the
/// contact forces on its grains (torque about its centre), normal is -F.axis, tangential the
/// force across the axis, length its extent across the axis, contacts its grains that touch.
int sim_world_wall_load(const SimWorld *world, int wall, SimWallLoad *load);
/// Changes gravity from now on (a stage's own `gravity`), m/s^2.
void sim_world_set_gravity(SimWorld *world, double gravity_x, double gravity_y);
/// Schedules motion `motion` by world time: it runs on its own clock tau = t - on from t = on
/// (its schedule then applies: SimMotion.start, ramp, stop), and from t = off on it holds the
/// pose it had at off, at rest (off = INFINITY: never). on = INFINITY: never enabled (at rest
/// where it was defined). At create every motion has on = 0, off = INFINITY. A stage's
/// `motions` list calls this (app/run/run.c). Out-of-range indices are ignored.
void sim_world_set_motion(SimWorld *world, int motion, double on, double off);

/* ---------------------------------------------------------------- checkpoints */

/// Opens `path` for reading (binary) only when it is a regular file. The file is opened without
/// blocking and checked with fstat before anything is read, so a FIFO (which would wait for a
/// writer), a device, a socket or a folder never blocks a command: each is refused. Every input
/// file of sablier is opened through this. NULL on failure, with a short reason in *why (when
/// why is not NULL): "it is a folder", "not a regular file (a FIFO, socket or device)" (errno
/// 0), or strerror of the failing call (errno kept).
FILE *sim_open_input(const char *path, const char **why);
/// 0 when `path` may receive an output: nothing is there yet, or a regular file (which the
/// output replaces by a rename). -1 with a reason in *why (when not NULL) for anything else: a
/// symbolic link, a FIFO, a device, a socket or a folder is never replaced by an output (errno
/// ELOOP, EISDIR or EEXIST).
int sim_output_target(const char *path, const char **why);
/// Opens PATH.tmp for writing (binary), for an output renamed to PATH once complete: refused
/// (sim_output_target) when PATH is not a regular file; whatever was at PATH.tmp (a stale file, a
/// link, a FIFO) is removed and PATH.tmp made anew as a regular file, so an output never writes
/// through a link or into a special file. NULL on failure, with a reason in *why (when not NULL).
FILE *sim_open_output(const char *path, const char **why);

/// Saves the whole state (grains, walls, time, contact history, sink counts) atomically
/// (written to path.tmp, then renamed).
SimStatus sim_world_save(SimWorld *world, const char *path, SimError *error);
/// Restores the contact history (tangential springs, rolling torques, by grain ids) and the sink
/// counts of a saved state into a world built from that state's grains (sim_state_load), so that
/// a stage started from a checkpoint continues with its contacts as they were.
SimStatus sim_world_restore_contacts(SimWorld *world, const char *path, SimError *error);
/// Reads the grains of a saved state into `grains` (arrays malloc'd; free with sim_grain_set_free),
/// with its walls (malloc'd) and time. Used to start a stage from a previous stage's checkpoint.
SimStatus sim_state_load(const char *path, SimGrainSet *grains, SimWall **walls, int *wall_count,
                         double *time, SimError *error);
void sim_grain_set_free(SimGrainSet *grains);
/// A world from `def` with the grains, walls and start time of the state saved at `path` (def's
/// own grains, walls and start time are not used; the contact history is not restored: see
/// sim_world_restore_contacts). A version-2 state whose time step, integrator arrays, laws and
/// skin setting fit `def` continues exactly as the saved world (its grain order, lists, forces,
/// contact history, step count and time: docs/state-format.md); any other starts afresh from
/// the grains at the saved time, step 0. NULL on failure: error->status is SIM_ERROR_IO when the
/// file cannot be read, another status when the state does not fit `def`. Restored grains are
/// exempt from def.max_initial_overlap (grain-grain and grain-wall): the bound is for new grains
/// (sim_world_create, sim_world_add_grains), while a state the engine saved must reload whatever
/// its overlaps (a deep or soft pile settles above the bound); every other check of
/// sim_world_create applies, and the run guard watches overlaps from then on.
SimWorld *sim_world_load(const char *path, const SimWorldDef *def, SimError *error);

/* ---------------------------------------------------------------- builders */

/// Deterministic RNG (xoshiro256**), seeded by splitmix64.
typedef struct SimRng {
    uint64_t s[4];
} SimRng;

void sim_rng_seed(SimRng *rng, uint64_t seed);
uint64_t sim_rng_next(SimRng *rng);
double sim_rng_uniform(SimRng *rng); ///< [0, 1)

/// A growable grain set owned by the caller (the arrays behind a SimGrainSet).
typedef struct SimGrainBuffer {
    int count, capacity;
    double *x, *y, *radius, *vx, *vy, *angle, *omega;
    int *species, *motion;
    unsigned *flags;
    uint32_t *id;
} SimGrainBuffer;

void sim_grain_buffer_init(SimGrainBuffer *buffer);
void sim_grain_buffer_free(SimGrainBuffer *buffer);
/// Append one grain (at rest); returns its index.
int sim_grain_buffer_add(SimGrainBuffer *buffer, double x, double y, double radius, int species,
                         unsigned flags, int motion);
/// The buffer as a SimGrainSet (pointers into the buffer).
SimGrainSet sim_grain_buffer_view(const SimGrainBuffer *buffer);

/// A row of touching fixed grains of radius r from (x0, y) to (x1, y).
void sim_build_fixed_row(SimGrainBuffer *buffer, double x0, double x1, double y, double radius,
                         int species, int motion);
/// A column of touching fixed grains of radius r from (x, y0) to (x, y1).
void sim_build_fixed_column(SimGrainBuffer *buffer, double x, double y0, double y1, double radius,
                            int species, int motion);

/// Rain-like lattice (000 §6.1): rows and columns with mean gaps and random offsets.
typedef struct SimRainDef {
    double x0, x1, y0, y1; ///< region to fill, m
    double radius_mean;    ///< r_med, m
    double polydispersity; ///< uniform half-width as a fraction of r_med (0.08)
    double pitch_radius;   ///< r used for the lattice pitch (000: r_max), m
    double column_gap;     ///< mean gap between columns, m (000: 0.005 r_max)
    double row_gap;        ///< mean gap between rows, m (000: 0.75 r_max)
    double column_jitter;  ///< random offset, fraction of pitch (000: 0.05)
    double row_jitter;     ///< random offset, fraction of pitch (000: 0.08)
    int max_count;         ///< stop after this many grains (0 = fill)
    int species;
    double species_fraction[SIM_MAX_SPECIES]; ///< optional mixture (all zero = `species` only)
    double species_radius[SIM_MAX_SPECIES]; ///< radius per species when mixing, m (0 = radius_mean)
} SimRainDef;

/// Fills the region; returns the number of grains added.
int sim_build_rain(SimGrainBuffer *buffer, const SimRainDef *def, SimRng *rng);
/// Thesis 000 §6.1 rain over [x0, x1] x [y0, y1]: r_med 0.08 m, 8 % uniform polydispersity,
/// pitch from r_max = 0.105 m, column and row gaps 0.005 and 0.75 r_max, jitters 5 % and 8 %.
SimRainDef sim_rain_def_thesis000(double x0, double x1, double y0, double y1, int max_count);
/// A container of touching fixed grains of radius r: a floor from x0 to x1 at height y0 and two
/// side columns from y0 + 2 r up to wall_top.
void sim_build_fixed_box(SimGrainBuffer *buffer, double x0, double x1, double y0, double wall_top,
                         double radius, int species);

/* ================================================================ fluid column (002 ch. 6)
 * Section owned by the sediment work (sim/fluid.c). A horizontally averaged 1D fluid u_x(y, t)
 * over a periodic bed (002 eqs. 26-37): rho_f (1 - phi) du/dt = d tau / dy + f, with
 * tau = rho_f (nu + l^2 |du/dy|) du/dy, Prandtl mixing length with van Driest damping (002 eq. 37),
 * no slip at y0, imposed stress rho_f u*^2 at y1, and f the force per unit volume the grains
 * exert on the fluid. Solved implicitly (backward Euler, Newton-linearised mixing-length stress,
 * Thomas algorithm), so no explicit step limit applies. The grains feel drag (002 eqs. 23-25)
 * and buoyancy through a ready-made SimBodyForce (effect fluid_drag).
 *
 *     SimFluidDef fd = sim_fluid_def_default();
 *     fd.y0 = 0; fd.y1 = 40; fd.cells = 400; fd.width = 50; ...
 *     SimFluid *fluid = sim_fluid_create(&fd, &err);
 *     def.effects |= SIM_EFFECT_FLUID_DRAG;
 *     def.body_force = sim_fluid_body_force(fluid);   // steps the fluid as the world advances
 */

/// Volume and frontal-area convention of the grain-fluid forces (notes 002 errata 7).
typedef enum SimFluidGeometry {
    SIM_FLUID_DISK = 0,   ///< per unit depth: volume pi d^2/4, frontal length d (mass model disk)
    SIM_FLUID_SPHERE = 1, ///< spheres: volume pi d^3/6, frontal area pi d^2/4 (002 eqs. 22-23)
} SimFluidGeometry;

typedef struct SimFluidDef {
    double y0, y1;               ///< column bottom (no slip) and top (imposed stress), m
    int cells;                   ///< layers of height (y1 - y0) / cells (002: about d / 10)
    double width;                ///< x width of the periodic bed, m
    double depth;                ///< slice thickness turning 2D areas into volumes: 1 for disk
                                 ///< (densities per unit depth), 2/3 d for sphere, m
    double density;              ///< rho_f, same convention as the grain density, kg/m^3
    double viscosity;            ///< nu, kinematic viscosity, m^2/s
    double shear_velocity;       ///< u*: top stress rho_f u*^2, m/s
    int turbulent;               ///< 1: nu_t = l^2 |du/dy| (002 eqs. 35, 37); 0: laminar
    double kappa;                ///< von Karman constant (0.4)
    double van_driest;           ///< R_vD of the damping 1 - exp(-(y - y_b) u* / (nu R_vD)) (26)
    double bed_fraction;         ///< y_b = top of the highest layer with phi >= this (0.4)
    double drag_c_inf;           ///< C_d^inf of C_d = (sqrt(C_inf) + sqrt(R_c / Re_p))^2 (0.5)
    double drag_reynolds;        ///< R_c (24)
    int buoyancy;                ///< 1: grains feel -rho_f V g (002 eq. 22, pressure part)
    double gravity_x, gravity_y; ///< for buoyancy, m/s^2
    SimFluidGeometry geometry;   ///< SIM_FLUID_DISK or SIM_FLUID_SPHERE
    double time_step;            ///< DEM dt for the drag limiter before the first step, s
    int drag_limit;              ///< 1: drag c (u - v) scaled to m (1 - exp(-c dt / m)) / dt
} SimFluidDef;

typedef struct SimFluid SimFluid;

/// One view of the column; arrays valid until the next call that changes the fluid.
typedef struct SimFluidProfile {
    int cells;
    double y0, dy;                ///< m; layer k spans [y0 + k dy, y0 + (k + 1) dy]
    const double *y;              ///< layer centres, m
    const double *u;              ///< fluid velocity, m/s
    const double *solid_fraction; ///< phi per layer (area fraction of mobile grains)
    const double *stress; ///< fluid shear stress at the cells + 1 faces (face k at y0 + k dy), Pa
    const double *grain_force; ///< x-force per unit volume of fluid on grains, per layer, N/m^3
    const double
        *grain_velocity; ///< area-weighted mean grain x-velocity per layer (0 if none), m/s
    double bed_level;    ///< y_b of the mixing length, m
    double time;         ///< s
} SimFluidProfile;

SimFluidDef sim_fluid_def_default(void);
SimStatus sim_fluid_def_validate(const SimFluidDef *def, SimError *error);
SimFluid *sim_fluid_create(const SimFluidDef *def, SimError *error);
void sim_fluid_destroy(SimFluid *fluid);
const SimFluidDef *sim_fluid_def(const SimFluid *fluid);

/// Advances the column by dt with the grains given per layer (all may be NULL: no grains):
/// solid_fraction phi_k, and the grain force on the fluid f_k = source_k - rate_k u_k(t + dt)
/// (rate in kg/(m^3 s), source in N/m^3), treated implicitly so a stiff drag cannot overshoot.
void sim_fluid_step(SimFluid *fluid, double dt, const double *solid_fraction, const double *rate,
                    const double *source);
void sim_fluid_profile(const SimFluid *fluid, SimFluidProfile *profile);
double sim_fluid_time(const SimFluid *fluid);
/// Fluid velocity at height y (linear between centres; 0 at y0; top value above), m/s.
double sim_fluid_velocity_at(const SimFluid *fluid, double y);
/// Sets the velocity of every layer (count = cells), e.g. to start from a steady profile.
void sim_fluid_set_velocity(SimFluid *fluid, const double *u);
/// Changes u* (a step in Shields number).
void sim_fluid_set_shear_velocity(SimFluid *fluid, double shear_velocity);
/// The column's whole evolving state (sim_fluid_state_count doubles: its time, shear velocity,
/// profiles and the grain coupling recorded at the last force evaluation), copied out or back in:
/// a run continued from a checkpoint (sablier run --resume) goes on with the same bits.
long sim_fluid_state_count(const SimFluid *fluid);
void sim_fluid_get_state(const SimFluid *fluid, double *state);
void sim_fluid_set_state(SimFluid *fluid, const double *state);
/// Largest explicit (forward Euler) step dy^2 / (2 (nu + nu_t,max)) for the current profile: what
/// an explicit scheme would need; the implicit solver itself has no limit, s.
double sim_fluid_explicit_limit(const SimFluid *fluid);

/// Body-force stage for SIM_EFFECT_FLUID_DRAG: at each force evaluation it first advances the
/// fluid to the evaluation time (with the grain coupling of the previous evaluation), then adds
/// drag (002 eqs. 23-25) from the local, area-weighted fluid velocity and buoyancy to every mobile
/// grain, and records the grains' reaction per layer for the next fluid step.
SimBodyForce sim_fluid_body_force(SimFluid *fluid);

/// Steady reference (002 eq. 45): RK4 integration in y of (nu + l^2 |u'|) u' = u*^2 from
/// u(bed_level) = 0, with l measured from bed_level; u = 0 below it. Writes u at the `count`
/// heights y (any order).
void sim_fluid_steady_reference(const SimFluidDef *def, double bed_level, const double *y,
                                int count, double *u);
/// Drag coefficient C_d = (sqrt(C_inf) + sqrt(R_c / Re_p))^2 (002 eq. 24); Re_p > 0.
double sim_fluid_drag_coefficient(const SimFluidDef *def, double reynolds);

#ifdef __cplusplus
}
#endif

#endif /* SIM_H */
