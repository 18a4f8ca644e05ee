/* SPDX-License-Identifier: MIT */
/* advice.c: dt advice (docs/accuracy.md "dt advice"). The worst-case restitution error of a
 * head-on impact follows |e - e_n| ~ C / n^p in the number n of steps per contact time; C and p
 * were fitted per integrator, onset option and e_n by bench/bench_accuracy.c (worst of 16 contact
 * phases, n = 30 ... 3000; `bench/run_accuracy.sh`, table "convergence law"), the cost per
 * particle-step on its crater case (same run). Inverting the law gives n for a target error. */
#include "scene/advice.h"

#include <math.h>
#include <string.h>

/* |e - e_n| <= c / n^p: bench/bench_accuracy.c, table "convergence law" of
 * bench/results/accuracy-summary.md (`build/bench/bench_accuracy --crater-every 2`). */
typedef struct Law {
    SimIntegrator integrator;
    SimOnset onset;
    double restitution, c, p;
} Law;

static const Law laws[] = {
    {SIM_INTEGRATOR_VELOCITY_VERLET, SIM_ONSET_STEP, 0.2, 0.559, 0.988},
    {SIM_INTEGRATOR_VELOCITY_VERLET, SIM_ONSET_STEP, 0.5, 0.716, 1.010},
    {SIM_INTEGRATOR_VELOCITY_VERLET, SIM_ONSET_STEP, 0.9, 0.191, 1.004},
    {SIM_INTEGRATOR_VELOCITY_VERLET, SIM_ONSET_EVENT, 0.2, 2.16, 2.011},
    {SIM_INTEGRATOR_VELOCITY_VERLET, SIM_ONSET_EVENT, 0.5, 1.87, 2.003},
    {SIM_INTEGRATOR_VELOCITY_VERLET, SIM_ONSET_EVENT, 0.9, 0.432, 1.997},
    {SIM_INTEGRATOR_SYMPLECTIC_EULER, SIM_ONSET_STEP, 0.2, 0.782, 0.979},
    {SIM_INTEGRATOR_SYMPLECTIC_EULER, SIM_ONSET_STEP, 0.5, 0.817, 1.012},
    {SIM_INTEGRATOR_SYMPLECTIC_EULER, SIM_ONSET_STEP, 0.9, 0.16, 0.982},
    {SIM_INTEGRATOR_SYMPLECTIC_EULER, SIM_ONSET_EVENT, 0.2, 0.329, 1.001},
    {SIM_INTEGRATOR_SYMPLECTIC_EULER, SIM_ONSET_EVENT, 0.5, 0.122, 0.994},
    {SIM_INTEGRATOR_SYMPLECTIC_EULER, SIM_ONSET_EVENT, 0.9, 0.00356, 0.943},
    {SIM_INTEGRATOR_GEAR, SIM_ONSET_STEP, 0.2, 0.577, 0.992},
    {SIM_INTEGRATOR_GEAR, SIM_ONSET_STEP, 0.5, 0.71, 1.011},
    {SIM_INTEGRATOR_GEAR, SIM_ONSET_STEP, 0.9, 0.179, 0.994},
    {SIM_INTEGRATOR_RK4, SIM_ONSET_STEP, 0.2, 0.349, 0.982},
    {SIM_INTEGRATOR_RK4, SIM_ONSET_STEP, 0.5, 0.487, 1.018},
    {SIM_INTEGRATOR_RK4, SIM_ONSET_STEP, 0.9, 0.118, 0.995},
};

/* CPU per particle-step, ns: bench/bench_accuracy.c's crater case (347 grains, best run; same
 * run as the laws, shared 2-core VM at load 8-10: an estimate, ±30 %). Stormer-Verlet uses
 * symplectic Euler's row (table_integrator). */
typedef struct Cost {
    SimIntegrator integrator;
    SimOnset onset;
    double ns;
} Cost;

static const Cost costs[] = {
    {SIM_INTEGRATOR_VELOCITY_VERLET, SIM_ONSET_STEP, 27.1},
    {SIM_INTEGRATOR_VELOCITY_VERLET, SIM_ONSET_EVENT, 31.6},
    {SIM_INTEGRATOR_SYMPLECTIC_EULER, SIM_ONSET_STEP, 28.8},
    {SIM_INTEGRATOR_SYMPLECTIC_EULER, SIM_ONSET_EVENT, 34.9},
    {SIM_INTEGRATOR_GEAR, SIM_ONSET_STEP, 50.8},
    {SIM_INTEGRATOR_RK4, SIM_ONSET_STEP, 150.6},
};

enum {
    LAW_COUNT = (int)(sizeof laws / sizeof laws[0]),
    COST_COUNT = (int)(sizeof costs / sizeof costs[0])
};

/* Stormer-Verlet moves the grains as symplectic Euler does in this engine (docs/accuracy.md):
 * it uses that integrator's rows. */
static SimIntegrator table_integrator(SimIntegrator integrator)
{
    return integrator == SIM_INTEGRATOR_STORMER_VERLET ? SIM_INTEGRATOR_SYMPLECTIC_EULER
                                                       : integrator;
}

/* c and p at e_n: linear in e_n between the measured rows (log c), the nearest row outside. */
static int law_at(SimIntegrator integrator, SimOnset onset, double e, double *c, double *p,
                  double *e_row)
{
    const Law *lo = NULL, *hi = NULL;
    integrator = table_integrator(integrator);
    for (int k = 0; k < LAW_COUNT; ++k) {
        const Law *l = &laws[k];
        if (l->integrator != integrator || l->onset != onset)
            continue;
        if (l->restitution <= e && (!lo || l->restitution > lo->restitution))
            lo = l;
        if (l->restitution >= e && (!hi || l->restitution < hi->restitution))
            hi = l;
    }
    if (!lo && !hi)
        return -1;
    if (!lo || !hi || lo == hi) {
        const Law *l = lo ? lo : hi;
        *c = l->c;
        *p = l->p;
        *e_row = l->restitution;
        return 0;
    }
    double w = (e - lo->restitution) / (hi->restitution - lo->restitution);
    *c = exp((1.0 - w) * log(lo->c) + w * log(hi->c));
    *p = (1.0 - w) * lo->p + w * hi->p;
    *e_row = e;
    return 0;
}

static double cost_ns(SimIntegrator integrator, SimOnset onset)
{
    integrator = table_integrator(integrator);
    for (int k = 0; k < COST_COUNT; ++k)
        if (costs[k].integrator == integrator && costs[k].onset == onset)
            return costs[k].ns;
    return NAN;
}

/* e_n without grains: the smallest e_n given by the species, or NAN. */
static double species_restitution(const SimWorldDef *def)
{
    double e = INFINITY;
    for (int s = 0; s < def->species_count; ++s) {
        if (def->materials[s].damping_mode != SIM_DAMPING_RESTITUTION)
            return NAN;
        e = fmin(e, def->materials[s].restitution);
    }
    return isfinite(e) ? e : (double)NAN;
}

int app_dt_advice(const SimWorldDef *def, int mobile, double target, AppAdvice *out, char *err,
                  size_t err_size)
{
    memset(out, 0, sizeof *out);
    if (!(target > 0.0 && target < 0.5)) {
        snprintf(err, err_size, "the target error must be in (0, 0.5) (got %g)", target);
        return -1;
    }
    if (def->contact.normal != SIM_NORMAL_LINEAR) {
        snprintf(err, err_size, "dt advice is measured for the linear normal law only");
        return -1;
    }
    SimTiming t = sim_world_def_timing(def);
    out->target = target;
    out->contact_time = isfinite(t.contact_time_min) ? t.contact_time_min : (double)NAN;
    out->stability_limit = t.stability_limit;
    out->restitution = isfinite(out->contact_time) ? t.restitution : species_restitution(def);
    if (!(out->restitution > 0.0)) {
        snprintf(err, err_size,
                 "no restitution to advise on: the scene has no grains of its own and its "
                 "species do not give `restitution`");
        return -1;
    }
    if (law_at(def->integrator, def->contact.onset, out->restitution, &out->c, &out->p,
               &out->law_restitution) != 0) {
        snprintf(err, err_size, "no measured convergence law for integrator %s with onset %s",
                 sim_integrator_name(def->integrator),
                 def->contact.onset == SIM_ONSET_EVENT ? "event" : "step");
        return -1;
    }
    /* invert |e - e_n| = c / n^p; the measured range starts at n = 10 */
    out->steps_per_contact = fmax(pow(out->c / target, 1.0 / out->p), 10.0);
    out->time_step = out->contact_time / out->steps_per_contact;
    if (isfinite(out->stability_limit) && out->time_step > 0.5 * out->stability_limit) {
        out->stability_capped = 1; /* as sim_world_def_timing caps it */
        out->time_step = 0.5 * out->stability_limit;
        out->steps_per_contact = out->contact_time / out->time_step;
    }
    out->ns_per_particle_step = cost_ns(def->integrator, def->contact.onset);
    out->mobile = mobile;
    out->cpu_per_sim_s = out->ns_per_particle_step * 1e-9 * mobile / out->time_step;
    return 0;
}

void app_dt_advice_print(const AppAdvice *a, const SimWorldDef *def, FILE *out)
{
    fprintf(out, "dt advice for |e - e_n| <= %g (%s, onset %s):\n", a->target,
            sim_integrator_name(def->integrator),
            def->contact.onset == SIM_ONSET_EVENT ? "event" : "step");
    if (isfinite(a->contact_time))
        fprintf(out, "  stiffest pair     t_c %.6g s, e_n %.6g\n", a->contact_time, a->restitution);
    else /* the grains come with the stage: dt = t_c,min / n is chosen then */
        fprintf(out, "  stiffest pair     t_c from the stage's grains, e_n %.6g (species)\n",
                a->restitution);
    fprintf(out, "  law               error = %.6g / n^%.6g (bench/bench_accuracy.c, e_n %.3g)\n",
            a->c, a->p, a->law_restitution);
    fprintf(out, "  steps per contact %.6g%s\n", a->steps_per_contact,
            a->stability_capped ? " (raised to half the stability limit)" : "");
    if (isfinite(a->time_step))
        fprintf(out, "  time step         %.6g s\n", a->time_step);
    if (isfinite(a->cpu_per_sim_s))
        fprintf(out,
                "  cost              %.6g CPU s per simulated s (estimate: %.6g ns per "
                "particle-step x %d mobile grains / dt)\n",
                a->cpu_per_sim_s, a->ns_per_particle_step, a->mobile);
    else
        fprintf(out, "  cost              not known (no grains yet, or not measured)\n");
}
