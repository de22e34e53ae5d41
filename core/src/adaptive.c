/* The accuracy-driven controller (issue 6.4a): substeps per frame and CG
 * tolerance from a local error estimate, with rollback. See the block
 * "accuracy-driven stepping" at the end of cloth.h for the contract.
 *
 * Why this estimate: backward Euler's local errors are h^2/2 x'' in position
 * and h^2/2 x''' in velocity. The step's own velocity change dv_k = h a_k
 * gives the first; the second, summed over the frame's n substeps, is
 * n h^2/2 |a'| = h/2 |a_n - a_0|, differenced over the whole frame rather
 * than substep by substep, since the CG's error makes each a_k noisy and
 * summed differences of noise do not shrink with h (a floor no substep count
 * gets under). So the estimate costs one pass over the velocities per
 * substep and no extra solve (step doubling would cost 1.5 to 3 times the
 * frame). Both parts scale as 1/n for a frame, so the next n is
 * n E / (0.7 budget).
 *
 * The CG tolerance: the stopping test is relative to the right-hand side,
 * h f, so an inexact solve is a relative error of about cg in the force,
 * repeated every substep (the warm start carries it on): the velocity drifts
 * by cg |a| per second, and with a loose tolerance the run converges to the
 * wrong motion (measured: cg 0.1 left 5 mm on an 11x11 swing at any n). A
 * bias held for the run's time t moves the positions by cg |a| t^2 / 2; a
 * tenth of the budget tolerance * t gives cg = 0.2 tolerance / (|a| t), with
 * t the simulated time so far (at least velocity_weight): later frames solve
 * tighter, as the bias has had longer to act. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

struct cloth_adaptive {
    const cloth *owner;
    int n;                 /* vertices */
    cloth_adaptive_desc d;
    cloth_state *snap;     /* the frame's start, for rollback */
    double *v0, *acc;      /* 3n: velocities before a substep, its acceleration */
    double *acc_prev;      /* 3n: the last accepted substep's acceleration */
    double *acc_prev_start;/* 3n: the same at the frame's start (a_0) */
    int have_prev, have_prev_start;
    int n_next;            /* substeps of the next frame */
    double cg_next;        /* CG tolerance of the next frame */
    double elapsed;        /* s, simulated time of the accepted frames */
};

cloth_adaptive_desc cloth_adaptive_default_desc(void)
{
    cloth_adaptive_desc d;
    memset(&d, 0, sizeof d);
    d.tolerance = 1e-2;
    d.min_substeps = 1;
    d.max_substeps = 256;
    d.cg_tolerance_min = 1e-8;
    d.cg_tolerance_max = 1e-1;
    d.velocity_weight = 0.1;
    return d;
}

static int finite_pos(double x) { return isfinite(x) && x > 0.0; }

cloth_status cloth_adaptive_create(const cloth *c, const cloth_adaptive_desc *d, cloth_adaptive **out,
                                   cloth_error *err)
{
    if (out) *out = NULL;
    if (!out) return error_set(err, CLOTH_EINVAL, "cloth_adaptive_create: out is NULL");
    if (!c) return error_set(err, CLOTH_EINVAL, "cloth_adaptive_create: cloth is NULL");
    if (!d) return error_set(err, CLOTH_EINVAL, "cloth_adaptive_create: descriptor is NULL");
    if (!finite_pos(d->tolerance))
        return error_set(err, CLOTH_EINVAL, "adaptive tolerance = %g m/s must be finite and > 0", d->tolerance);
    if (d->min_substeps < 1 || d->max_substeps < d->min_substeps)
        return error_set(err, CLOTH_EINVAL, "adaptive substeps %d..%d: need 1 <= min_substeps <= max_substeps",
                         d->min_substeps, d->max_substeps);
    if (!finite_pos(d->cg_tolerance_min) || !(d->cg_tolerance_max < 1.0) ||
        !(d->cg_tolerance_min <= d->cg_tolerance_max))
        return error_set(err, CLOTH_EINVAL, "adaptive CG tolerance range %g..%g: need 0 < min <= max < 1",
                         d->cg_tolerance_min, d->cg_tolerance_max);
    if (!finite_pos(d->velocity_weight))
        return error_set(err, CLOTH_EINVAL, "adaptive velocity_weight = %g s must be finite and > 0",
                         d->velocity_weight);
    cloth_adaptive *a = calloc(1, sizeof *a);
    if (!a) return error_set(err, CLOTH_ENOMEM, "cloth_adaptive_create: out of memory");
    a->owner = c;
    a->n = cloth_vertex_count(c);
    a->d = *d;
    size_t n3 = 3 * (size_t)a->n;
    a->snap = cloth_state_create(c);
    a->v0 = calloc(4 * n3, sizeof *a->v0);
    if (!a->snap || !a->v0) {
        cloth_adaptive_destroy(a);
        return error_set(err, CLOTH_ENOMEM, "cloth_adaptive_create: out of memory (%d vertices)", a->n);
    }
    a->acc = a->v0 + n3;
    a->acc_prev = a->acc + n3;
    a->acc_prev_start = a->acc_prev + n3;
    a->n_next = d->min_substeps;
    a->cg_next = d->cg_tolerance_min;
    *out = a;
    return CLOTH_OK;
}

void cloth_adaptive_destroy(cloth_adaptive *a)
{
    if (!a) return;
    cloth_state_destroy(a->snap);
    free(a->v0);
    free(a);
}

static double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }

static int clamp_substeps(const cloth_adaptive *a, double n)
{
    if (!(n >= a->d.min_substeps)) return a->d.min_substeps; /* also NaN */
    if (n >= a->d.max_substeps) return a->d.max_substeps;
    return (int)ceil(n);
}

/* RMS over vertices of |u| (3n) */
static double rms3(const double *u, int n)
{
    double s = 0.0;
    for (size_t k = 0; k < 3 * (size_t)n; k++) s += u[k] * u[k];
    return sqrt(s / n);
}

typedef struct attempt {
    cloth_failure failure; /* NONE: all substeps taken */
    int callback_failed;
    double ex, ev;         /* position (m) and velocity (m/s) estimates */
    int steps, iterations;
} attempt;

/* n substeps of h from the current state, with the frame's estimates:
 * ex = sum over substeps of h^2/2 |a_k| (positions), ev = n h^2/2 |a'| with
 * a' = (a_n - a_0) / frame over the whole frame (velocities; a_0 is the last
 * substep's acceleration before the frame). Differencing over the frame
 * rather than substep by substep keeps the CG's noise in a_k from adding up
 * into a floor that no step size could get under. */
static attempt run_substeps(cloth_adaptive *a, cloth *c, int n, double h)
{
    attempt t = {CLOTH_FAIL_NONE, 0, 0.0, 0.0, 0, 0};
    size_t n3 = 3 * (size_t)a->n;
    for (int k = 0; k < n; k++) {
        if (a->d.before_substep && a->d.before_substep(c, h, a->d.user) != 0) {
            t.callback_failed = 1;
            return t;
        }
        memcpy(a->v0, cloth_velocities(c), n3 * sizeof *a->v0);
        cloth_step_stats st;
        cloth_status s = cloth_step(c, h, &st);
        t.steps++;
        t.iterations += st.iterations;
        if (s != CLOTH_OK) {
            t.failure = st.failure != CLOTH_FAIL_NONE ? st.failure : CLOTH_FAIL_NAN;
            return t;
        }
        const double *v = cloth_velocities(c);
        for (size_t i = 0; i < n3; i++) a->acc[i] = (v[i] - a->v0[i]) / h;
        t.ex += 0.5 * h * h * rms3(a->acc, a->n);
        if (!a->have_prev) { /* no acceleration before the frame: this one */
            memcpy(a->acc_prev_start, a->acc, n3 * sizeof *a->acc);
            a->have_prev = 1;
        }
    }
    for (size_t i = 0; i < n3; i++) a->acc_prev[i] = a->acc[i] - a->acc_prev_start[i];
    t.ev = 0.5 * h * rms3(a->acc_prev, a->n); /* n h^2/2 |a_n - a_0| / (n h) */
    memcpy(a->acc_prev, a->acc, n3 * sizeof *a->acc);
    return t;
}

cloth_status cloth_adaptive_frame(cloth_adaptive *a, cloth *c, double frame_dt, cloth_adaptive_stats *stats)
{
    cloth_adaptive_stats st;
    memset(&st, 0, sizeof st);
    if (stats) *stats = st;
    if (!a || !c) return CLOTH_EINVAL;
    if (c != a->owner || cloth_vertex_count(c) != a->n)
        return cloth_fail(c, CLOTH_EINVAL, "cloth_adaptive_frame: the controller was made for another cloth");
    if (!finite_pos(frame_dt)) {
        st.failure = CLOTH_FAIL_BAD_STEP;
        if (stats) *stats = st;
        return cloth_fail(c, CLOTH_EINVAL, "cloth_adaptive_frame: frame_dt = %g must be finite and > 0", frame_dt);
    }
    const cloth_solver user = cloth_get_desc(c).solver;
    size_t n3 = 3 * (size_t)a->n;
    cloth_save(c, a->snap);
    memcpy(a->acc_prev_start, a->acc_prev, n3 * sizeof *a->acc_prev);
    a->have_prev_start = a->have_prev;

    const double budget = a->d.tolerance * frame_dt;
    int n = clamp_substeps(a, a->n_next);
    double cg = clampd(a->cg_next, a->d.cg_tolerance_min, a->d.cg_tolerance_max);
    if (!a->have_prev) {
        /* the first frame: no acceleration from before it, so at least two
         * substeps for a velocity estimate, and a tight solve (nothing yet
         * to choose the tolerance from) */
        n = clamp_substeps(a, 2.0 * n);
        cg = clampd(1e-6, a->d.cg_tolerance_min, a->d.cg_tolerance_max);
    }
    st.error_budget = budget;
    attempt t;
    for (;;) {
        cloth_solver sv = user;
        sv.method = CLOTH_BACKWARD_EULER;
        sv.cg_tolerance = cg;
        cloth_set_solver(c, &sv);
        t = run_substeps(a, c, n, frame_dt / n);
        st.attempts++;
        st.steps += t.steps;
        st.cg_iterations += t.iterations;
        st.substeps = n;
        st.h = frame_dt / n;
        st.cg_tolerance = cg;
        st.error_estimate = t.ex + a->d.velocity_weight * t.ev;
        int ok = t.failure == CLOTH_FAIL_NONE && !t.callback_failed;
        if (ok && (st.error_estimate <= 2.0 * budget || n >= a->d.max_substeps)) break;
        /* roll back to the frame's start */
        cloth_restore(c, a->snap);
        memcpy(a->acc_prev, a->acc_prev_start, n3 * sizeof *a->acc_prev);
        a->have_prev = a->have_prev_start;
        if (!ok && (t.callback_failed || n >= a->d.max_substeps)) {
            cloth_set_solver(c, &user);
            st.failure = t.failure;
            if (stats) *stats = st;
            if (t.callback_failed)
                return cloth_fail(c, CLOTH_ESTEP, "cloth_adaptive_frame: before_substep failed (state unchanged)");
            return cloth_fail(c, CLOTH_ESTEP, "cloth_adaptive_frame: %s at %d substeps (state unchanged)",
                              cloth_failure_string(t.failure), n);
        }
        /* a failed step: twice the substeps and a tighter solve; too large an
         * estimate: the substeps it asks for (the estimate scales as 1/n) */
        if (!ok) {
            n = clamp_substeps(a, 2.0 * n);
            cg = clampd(0.1 * cg, a->d.cg_tolerance_min, a->d.cg_tolerance_max);
        } else {
            n = clamp_substeps(a, fmax(2.0 * n, n * st.error_estimate / (0.7 * budget)));
        }
    }
    cloth_set_solver(c, &user);
    st.over_budget = !(st.error_estimate <= 2.0 * budget);
    /* the next frame: aim at 0.7 of the budget, at most halving n at once */
    a->n_next = clamp_substeps(a, fmax(n * st.error_estimate / (0.7 * budget), 0.5 * n));
    /* The CG tolerance: the stopping test is relative to the right-hand side,
     * which is h f, so an inexact solve is a relative error of about cg in
     * the force, the same in every substep (the warm start keeps it): it adds
     * a velocity error of cg |a| per second, weighed like the truncation's
     * velocity error. A tenth of the budget: cg = 0.1 tol / (weight |a|). */
    double a_mean = 2.0 * t.ex / (n * st.h * st.h);
    a->elapsed += frame_dt;
    double horizon = fmax(a->d.velocity_weight, a->elapsed);
    a->cg_next = a_mean > 0.0 ? 0.2 * a->d.tolerance / (horizon * a_mean) : a->d.cg_tolerance_max;
    a->cg_next = clampd(a->cg_next, a->d.cg_tolerance_min, a->d.cg_tolerance_max);
    if (stats) *stats = st;
    return CLOTH_OK;
}
