/* The accuracy-driven controller (odecloth/adaptive.h): substeps per frame, CG tolerance and
 * method from a shadow run's error estimate, with rollback. Why a shadow at 2 h, symplectic
 * Euler and the a-priori CG bound: docs/solver.md, "The accuracy-driven controller". */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"
#include "tuning.h"

struct cloth_adaptive {
    const cloth *owner;
    int n; /* vertices */
    cloth_adaptive_desc d;
    cloth_state *snap;      /* the frame's start, for rollback */
    double *v0, *acc;       /* 3n: velocities before a substep, its acceleration */
    double *acc_prev;       /* 3n: the last accepted substep's acceleration */
    double *acc_prev_start; /* 3n: the same at the frame's start (a_0) */
    int have_prev, have_prev_start;
    int n_next;     /* substeps of the next frame */
    double cg_next; /* CG tolerance of the next frame */
    double elapsed; /* s, simulated time of the accepted frames */
    /* the global estimate: a shadow cloth run alongside at twice the step */
    cloth *shadow; /* NULL: no global estimate (bodies, or no memory) */
    cloth_state *shadow_snap;
    cloth_state *alt, *alt_shadow;    /* the first frame's backward Euler solution while symplectic Euler is tried */
    int shadow_synced;                /* 1 once the shadow has been started from the cloth */
    double global;                    /* m, RMS |x - x_shadow| after the last accepted frame */
    double h_int;                     /* s^2, integral of the substep size over the shadow's run */
    double k_err;                     /* m / s^2, the estimate per unit step and time (decaying maximum) */
    double carried;                   /* m, the estimate at the shadow's last restart */
    cloth_method method;              /* of the last frame: backward or symplectic Euler */
    double k_be;                      /* m / s^2, k_err of backward Euler when it last ran */
    double it_be;                     /* CG iterations per backward Euler substep (running mean) */
    double h_stab;                    /* s, symplectic Euler's stable step (0: not yet computed) */
    double h_scale;                   /* 1, halved whenever a symplectic frame fails */
    double *uk, *uc, *px, *pf0, *pf1; /* 3n each: power iterations */
    double *cf0;                      /* 3n: the constraint forces before the frame (a failed frame keeps them) */
};

cloth_adaptive_desc cloth_adaptive_default_desc(void)
{
    cloth_adaptive_desc d;
    memset(&d, 0, sizeof d);
    d.tolerance = 1e-2;
    d.min_substeps = 1;
    d.max_substeps = 1024;
    d.cg_tolerance_min = 1e-8;
    d.cg_tolerance_max = 1e-1;
    d.velocity_weight = 0.1;
    d.global_estimate = 1;
    d.allow_explicit = 1;
    return d;
}

static int finite_pos(double x) { return isfinite(x) && x > 0.0; }

cloth_status cloth_adaptive_create(const cloth *c, const cloth_adaptive_desc *d, cloth_adaptive **out, cloth_error *err)
{
    if (out) *out = NULL;
    if (!out) return oc_error_set(err, CLOTH_EINVAL, "cloth_adaptive_create: out is NULL");
    if (!c) return oc_error_set(err, CLOTH_EINVAL, "cloth_adaptive_create: cloth is NULL");
    if (!d) return oc_error_set(err, CLOTH_EINVAL, "cloth_adaptive_create: descriptor is NULL");
    if (!finite_pos(d->tolerance))
        return oc_error_set(err, CLOTH_EINVAL, "adaptive tolerance = %g m/s must be finite and > 0", d->tolerance);
    if (d->min_substeps < 1 || d->max_substeps < d->min_substeps)
        return oc_error_set(err, CLOTH_EINVAL, "adaptive substeps %d..%d: need 1 <= min_substeps <= max_substeps",
                            d->min_substeps, d->max_substeps);
    if (!finite_pos(d->cg_tolerance_min) || !(d->cg_tolerance_max < 1.0) ||
        !(d->cg_tolerance_min <= d->cg_tolerance_max))
        return oc_error_set(err, CLOTH_EINVAL, "adaptive CG tolerance range %g..%g: need 0 < min <= max < 1",
                            d->cg_tolerance_min, d->cg_tolerance_max);
    if (!finite_pos(d->velocity_weight))
        return oc_error_set(err, CLOTH_EINVAL, "adaptive velocity_weight = %g s must be finite and > 0",
                            d->velocity_weight);
    if (d->global_estimate != 0 && d->global_estimate != 1)
        return oc_error_set(err, CLOTH_EINVAL, "adaptive global_estimate = %d must be 0 or 1", d->global_estimate);
    if (d->allow_explicit != 0 && d->allow_explicit != 1)
        return oc_error_set(err, CLOTH_EINVAL, "adaptive allow_explicit = %d must be 0 or 1", d->allow_explicit);
    cloth_adaptive *a = calloc(1, sizeof *a);
    if (!a) return oc_error_set(err, CLOTH_ENOMEM, "cloth_adaptive_create: out of memory");
    a->owner = c;
    a->n = cloth_vertex_count(c);
    a->d = *d;
    size_t n3 = 3 * (size_t)a->n;
    a->snap = cloth_state_create(c);
    a->v0 = calloc(10 * n3, sizeof *a->v0);
    int ok = a->snap && a->v0;
    /* the shadow needs an even substep count in the user's range (with
     * min = max = 3 frames ran 2 and 4 substeps: found in review) */
    if (ok && d->global_estimate &&
        d->min_substeps + (d->min_substeps & 1) <= d->max_substeps - (d->max_substeps & 1)) {
        /* the shadow: the same cloth (the masses copied, as cloth_set_material
         * keeps the ones made at creation) */
        cloth_desc sd = cloth_get_desc(c);
        ok = cloth_create(&sd, &a->shadow, NULL) == CLOTH_OK && (a->shadow_snap = cloth_state_create(a->shadow)) &&
             (a->alt = cloth_state_create(c)) && (a->alt_shadow = cloth_state_create(a->shadow));
        if (ok) memcpy(a->shadow->mass, c->mass, (size_t)a->n * sizeof *c->mass);
    }
    if (!ok) {
        int nv = a->n;
        cloth_adaptive_destroy(a);
        return oc_error_set(err, CLOTH_ENOMEM, "cloth_adaptive_create: out of memory (%d vertices)", nv);
    }
    a->acc = a->v0 + n3;
    a->acc_prev = a->acc + n3;
    a->acc_prev_start = a->acc_prev + n3;
    a->uk = a->acc_prev_start + n3;
    a->uc = a->uk + n3;
    a->px = a->uc + n3;
    a->pf0 = a->px + n3;
    a->pf1 = a->pf0 + n3;
    a->cf0 = a->pf1 + n3;
    for (size_t k = 0; k < n3; k++) /* a fixed start with every direction in it */
        a->uk[k] = a->uc[k] = (double)((k * 2654435761u) % 1000u) / 500.0 - 1.0;
    a->method = CLOTH_BACKWARD_EULER;
    a->h_scale = 1.0;
    a->n_next = d->min_substeps;
    a->cg_next = d->cg_tolerance_min;
    *out = a;
    return CLOTH_OK;
}

void cloth_adaptive_destroy(cloth_adaptive *a)
{
    if (!a) return;
    cloth_state_destroy(a->snap);
    cloth_state_destroy(a->shadow_snap);
    cloth_state_destroy(a->alt);
    cloth_state_destroy(a->alt_shadow);
    cloth_destroy(a->shadow);
    free(a->v0);
    free(a);
}

static double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }

/* the most substeps a frame may take: the user's bound, made even with a
 * shadow (it takes n / 2) */
static int n_top(const cloth_adaptive *a, int even) { return a->d.max_substeps - (even ? a->d.max_substeps & 1 : 0); }

/* n substeps, rounded up (even with a shadow: it takes n / 2), within the
 * user's range (made even, never empty: cloth_adaptive_create keeps the
 * shadow only when an even count fits) */
static int clamp_substeps(const cloth_adaptive *a, double n, int even)
{
    int lo = a->d.min_substeps + (even ? a->d.min_substeps & 1 : 0), hi = n_top(a, even);
    if (!(n >= lo)) return lo; /* also NaN */
    if (n >= hi) return hi;
    int k = (int)ceil(n);
    if (even) k += k & 1;
    return k > hi ? hi : k;
}

/* RMS over vertices of |u| (3n) */
static double rms3(const double *u, int n)
{
    double s = 0.0;
    for (size_t k = 0; k < 3 * (size_t)n; k++) s += u[k] * u[k];
    return sqrt(s / n);
}

/* RMS over vertices of |x - y| (3n) */
static double rms_diff(const double *x, const double *y, int n)
{
    double s = 0.0;
    for (size_t k = 0; k < 3 * (size_t)n; k++) s += (x[k] - y[k]) * (x[k] - y[k]);
    return sqrt(s / n);
}

typedef struct attempt {
    cloth_failure failure; /* NONE: all substeps taken */
    int callback_failed;
    double ex, ev; /* position (m) and velocity (m/s) estimates */
    int steps, iterations;
} attempt;

/* n substeps of h from the current state, with the frame's error estimates (ex for positions,
 * ev for velocities, the acceleration differenced over the whole frame so that the CG's noise
 * in each substep's acceleration does not add up into a floor no step size gets under). */
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

/* Copies the cloth's inputs to the shadow (material, gravity, external forces, air and
 * constraints as the frame starts) so both integrate the same problem. */
static void shadow_inputs(cloth_adaptive *a, const cloth *c)
{
    cloth *s = a->shadow;
    s->desc.material = c->desc.material;
    memcpy(s->desc.gravity, c->desc.gravity, sizeof s->desc.gravity);
    memcpy(s->f_ext, c->f_ext, 3 * (size_t)a->n * sizeof *c->f_ext);
    s->air = c->air;
    for (int i = 0; i < a->n; i++) {
        const cloth_constraint *k = &c->con[i], *q = &s->con[i];
        if (k->ndof == q->ndof && (k->ndof == 0 || !memcmp(k, q, sizeof *k))) continue;
        if (k->ndof == 0) cloth_release(s, i);
        else cloth_set_constraint(s, k);
    }
}

/* the shadow's n / 2 substeps of 2 h; 0 if all of them were taken */
static int run_shadow(cloth_adaptive *a, int n, double h, int *steps, int *iterations)
{
    cloth *s = a->shadow;
    for (int k = 0; k < n / 2; k++) {
        if (a->d.before_substep && a->d.before_substep(s, 2.0 * h, a->d.user) != 0) return 1;
        cloth_step_stats st;
        cloth_status r = cloth_step(s, 2.0 * h, &st);
        ++*steps;
        *iterations += st.iterations;
        if (r != CLOTH_OK) return 1;
    }
    return 0;
}

/* Filter u (3n) as the solver's constraints do: constrained directions and
 * massless vertices get nothing. */
static void filter(const cloth *c, double *u)
{
    for (int i = 0; i < c->n; i++) {
        double *w = u + 3 * i;
        const cloth_constraint *k = &c->con[i];
        if (k->ndof == 3 || !(c->mass[i] > 0.0)) {
            w[0] = w[1] = w[2] = 0.0;
        } else if (k->ndof == 1) { /* plane: remove the normal component */
            double d = w[0] * k->axis[0] + w[1] * k->axis[1] + w[2] * k->axis[2];
            for (int j = 0; j < 3; j++) w[j] -= d * k->axis[j];
        } else if (k->ndof == 2) { /* line: keep the component along it */
            double d = w[0] * k->axis[0] + w[1] * k->axis[1] + w[2] * k->axis[2];
            for (int j = 0; j < 3; j++) w[j] = d * k->axis[j];
        }
    }
}

/* Largest eigenvalue of M^-1 K (which 0) or M^-1 C (which 1) at the cloth's state, by `iters`
 * power iterations of finite-difference force products continuing from u (kept for the next call). */
static double power_max(cloth_adaptive *a, const cloth *c, int which, double *u, int iters)
{
    size_t n3 = 3 * (size_t)a->n;
    const double *x = cloth_positions(c), *v = cloth_velocities(c);
    int air = which && oc_air_on(c);
    oc_forces_eval(c, x, v, 0, a->pf0);
    if (air) oc_air_eval(c, x, NULL, 0.0, v, 1.0, a->pf0, NULL, 0.0);
    double lam = 0.0;
    for (int it = 0; it < iters; it++) {
        filter(c, u);
        double s = 0.0;
        for (size_t k = 0; k < n3; k++) s += u[k] * u[k];
        if (!(s > 0.0)) return 0.0;
        double sc = 1.0 / sqrt(s / a->n), eps = 1e-6; /* u: RMS 1 per vertex; eps in m or m/s */
        for (size_t k = 0; k < n3; k++) {
            u[k] *= sc;
            a->px[k] = (which ? v[k] : x[k]) + eps * u[k];
        }
        oc_forces_eval(c, which ? x : a->px, which ? a->px : v, 0, a->pf1);
        if (air) oc_air_eval(c, x, NULL, 0.0, a->px, 1.0, a->pf1, NULL, 0.0);
        double num = 0.0, den = 0.0;
        for (size_t k = 0; k < n3; k++) {
            double m = c->mass[k / 3];
            double y = m > 0.0 ? -(a->pf1[k] - a->pf0[k]) / (eps * m) : 0.0;
            num += m * u[k] * y; /* M^-1 K is self-adjoint in the M inner product */
            den += m * u[k] * u[k];
            a->pf1[k] = y;
        }
        lam = den > 0.0 ? num / den : 0.0;
        memcpy(u, a->pf1, n3 * sizeof *u);
    }
    return isfinite(lam) && lam > 0.0 ? lam : 0.0;
}

/* Symplectic Euler's stable step: a mode is stable while h^2 k' + 2 h c' < 4 (damping explicit too),
 * taken with the largest k' and c', an upper bound since they need not share a mode. */
static double stable_step(cloth_adaptive *a, const cloth *c, int iters)
{
    double lk = power_max(a, c, 0, a->uk, iters), lc = power_max(a, c, 1, a->uc, iters);
    if (!(lk > 0.0)) return 0.0;
    return 4.0 / (lc + sqrt(lc * lc + 4.0 * lk));
}

/* Newton's residual, an impulse of velocity size r a step, is a bias r / h in
 * the acceleration: held over the horizon it moves the positions by at most
 * ADAPTIVE_CGF / 2 of the request, as the CG tolerance's bias does (top of the file). */
static double newton_bound(const cloth_adaptive *a, double h)
{
    return ADAPTIVE_CGF * a->d.tolerance * h / fmax(a->d.velocity_weight, a->elapsed);
}

/* The shadow restarted from the cloth's state at the frame's start (a->snap):
 * the estimate so far is carried (added to what the new run estimates). */
static void resync(cloth_adaptive *a)
{
    a->carried += a->global;
    cloth_restore(a->shadow, a->snap);
    cloth_save(a->shadow, a->shadow_snap);
    a->global = a->h_int = a->k_err = 0.0;
}

/* A change of method restarts the shadow from the cloth: k is estimated afresh for the new method and
 * the estimate so far is carried, not propagated, so the error amplified before the switch is not
 * charged to the new method (docs/solver.md, "Design notes from the code"). */
static void new_method(cloth_adaptive *a, cloth_method m)
{
    a->method = m;
    resync(a);
}

/* CPU cost of a backward Euler substep in symplectic Euler substeps (one force evaluation and update
 * each); the constants come from a benchmark (docs/solver.md, "Design notes from the code"). */
static double be_cost(double iterations) { return ADAPTIVE_BE_COST_FIXED + ADAPTIVE_BE_COST_PER_CG * iterations; }

/* The frame's method with the shadow running: symplectic Euler where it is cheaper (its step is
 * bounded by stability, at 2 h for the shadow), else backward Euler; *n its substeps, *synced set
 * when a change of method restarted the shadow. */
static cloth_method choose_method(cloth_adaptive *a, const cloth *c, double frame_dt, int *n, int *synced)
{
    cloth_method method = a->method;
    if (a->d.allow_explicit && a->have_prev && a->h_scale > 0.0) {
        double nb = a->method == CLOTH_BACKWARD_EULER ? *n : frame_dt * a->k_be / (ADAPTIVE_AIM * a->d.tolerance);
        double cost_be = fmax(nb, 2.0) * be_cost(a->it_be);
        /* the stable step, estimated (40 power iterations, then 6 from the last vector)
         * while symplectic Euler runs or might be within 2x */
        if (a->method == CLOTH_SYMPLECTIC_EULER || a->h_stab == 0.0 ||
            frame_dt / (ADAPTIVE_SYM_FRAC * a->h_scale * a->h_stab) < 2.0 * cost_be) {
            a->h_stab = stable_step(a, c, a->h_stab > 0.0 ? 6 : 40);
            double hs = ADAPTIVE_SYM_FRAC * a->h_scale * a->h_stab;
            int ns = hs > 0.0 ? clamp_substeps(a, frame_dt / hs, 1) : n_top(a, 1);
            if (a->method == CLOTH_SYMPLECTIC_EULER && *n < ns) *n = ns;
            if (a->method == CLOTH_BACKWARD_EULER && ns < n_top(a, 1) && ns < cost_be) {
                method = CLOTH_SYMPLECTIC_EULER;
                a->k_be = a->k_err;
                *n = ns;
            } else if (a->method == CLOTH_SYMPLECTIC_EULER &&
                       (cost_be < ADAPTIVE_BACK_TO_IMPLICIT * *n || ns >= n_top(a, 1))) {
                method = CLOTH_BACKWARD_EULER;
                *n = clamp_substeps(a, nb, 1);
            }
            if (method != a->method) {
                new_method(a, method);
                *synced = 1;
            }
        }
    }
    return method;
}

/* The first frame, solved by backward Euler (attempt *t, *n substeps, its shadow's difference
 * *g_est), solved again by symplectic Euler when its stable step fits max_substeps; the cheaper at
 * the tolerance kept (backward Euler's error the larger of its shadow's and its distance to it). */
static void first_frame_explicit(cloth_adaptive *a, cloth *c, double frame_dt, cloth_solver *sv, attempt *t, int *n,
                                 cloth_method *method, double *g_est, cloth_adaptive_stats *st)
{
    size_t n3 = 3 * (size_t)a->n;
    a->h_stab = stable_step(a, c, 40);
    double hs = ADAPTIVE_SYM_FRAC * a->h_scale * a->h_stab;
    int ns = hs > 0.0 ? clamp_substeps(a, frame_dt / hs, 1) : n_top(a, 1);
    if (ns < n_top(a, 1)) {
        const attempt tb = *t;
        const double gb = *g_est, hb = st->h, its = t->steps ? (double)t->iterations / t->steps : 0.0;
        const int nbe = *n;
        cloth_save(c, a->alt);
        cloth_save(a->shadow, a->alt_shadow);
        cloth_restore(c, a->snap);
        cloth_restore(a->shadow, a->shadow_snap);
        memcpy(a->acc_prev, a->acc_prev_start, n3 * sizeof *a->acc_prev);
        a->have_prev = a->have_prev_start;
        sv->method = CLOTH_SYMPLECTIC_EULER;
        cloth_set_solver(c, sv);
        cloth_set_solver(a->shadow, sv); /* builds its multigrid levels when first chosen */
        attempt ts = run_substeps(a, c, ns, frame_dt / ns);
        st->attempts++;
        st->steps += ts.steps;
        int sok = ts.failure == CLOTH_FAIL_NONE && !ts.callback_failed &&
                  !run_shadow(a, ns, frame_dt / ns, &st->steps, &st->cg_iterations);
        double d = sok ? rms_diff(cloth_positions(c), a->alt->x, a->n) : 0.0;
        double k0 = fmax(gb, d) / (hb * frame_dt);
        double cost_be = fmax(frame_dt * k0 / (ADAPTIVE_AIM * a->d.tolerance), 2.0) * be_cost(its);
        a->k_be = k0;
        a->it_be = its;
        if (sok && ns < ADAPTIVE_SYM_PREFER * cost_be) {
            *method = a->method = CLOTH_SYMPLECTIC_EULER;
            *t = ts;
            *n = ns;
            st->substeps = *n;
            st->h = frame_dt / *n;
            st->method = *method;
            st->error_estimate = t->ex + a->d.velocity_weight * t->ev;
            *g_est = rms_diff(cloth_positions(c), cloth_positions(a->shadow), a->n);
        } else { /* backward Euler's frame back, with what its shadow missed carried */
            cloth_restore(c, a->alt);
            cloth_restore(a->shadow, a->alt_shadow);
            sv->method = CLOTH_BACKWARD_EULER;
            cloth_set_solver(c, sv);
            cloth_set_solver(a->shadow, sv); /* builds its multigrid levels when first chosen */
            *t = tb;
            *n = nbe;
            a->carried += fmax(0.0, d - gb);
        }
    }
}

/* After an accepted frame of n substeps (attempt t, the shadow's difference g_est, or the local
 * estimate where the shadow failed or did not run): the next frame's substeps and CG tolerance. */
static void next_frame(cloth_adaptive *a, double frame_dt, int n, const attempt *t, int global, int shadow_failed,
                       double g_est, cloth_method method, cloth_adaptive_stats *st)
{
    const double budget = a->d.tolerance * frame_dt;
    if (global && !shadow_failed) {
        st->over_budget = !(g_est - a->global <= 2.0 * budget);
        a->global = g_est;
        st->global_estimate = a->carried + g_est;
        /* the next frame's step: E = k int h dt (k the error per unit step and time), so h =
         * ADAPTIVE_AIM tolerance / k keeps the estimate a fraction of the request; n at most halves at once */
        a->h_int += st->h * frame_dt;
        a->k_err = fmax(g_est / a->h_int, a->k_err * exp(-frame_dt / ADAPTIVE_KMEM));
        if (method == CLOTH_BACKWARD_EULER) a->k_be = a->k_err;
        double want = frame_dt * a->k_err / (ADAPTIVE_AIM * a->d.tolerance);
        a->n_next = clamp_substeps(a, fmax(want, 0.5 * n), 1);
    } else {
        if (global) { /* the shadow failed where the cloth did not: start it again */
            a->shadow_synced = 0;
        }
        st->global_estimate = NAN;
        st->over_budget = !(st->error_estimate <= 2.0 * budget);
        /* the next frame: aim at ADAPTIVE_LOCAL_AIM of the budget, at most halving n at once */
        a->n_next = clamp_substeps(a, fmax(n * st->error_estimate / (ADAPTIVE_LOCAL_AIM * budget), 0.5 * n), global);
    }
    st->requested = a->d.tolerance * a->elapsed; /* a->elapsed: the frame's end */
    /* The next frame's CG tolerance: a bias of cg |a| in the acceleration held for the time so far,
     * bounded by ADAPTIVE_CGF / 2 of the request tolerance * t (docs/solver.md). */
    double a_mean = 2.0 * t->ex / (n * st->h * st->h);
    double horizon = fmax(a->d.velocity_weight, a->elapsed);
    a->cg_next = a_mean > 0.0 ? ADAPTIVE_CGF * a->d.tolerance / (horizon * a_mean) : a->d.cg_tolerance_max;
    a->cg_next = clampd(a->cg_next, a->d.cg_tolerance_min, a->d.cg_tolerance_max);
}

/* A symplectic frame unstable after all (a link reaching the limit's stiffness, or the power
 * iteration short of the largest mode): the explicit step halved, or backward Euler once that costs
 * less; the method to solve the frame again with, *n its substeps. */
static cloth_method explicit_failed(cloth_adaptive *a, double frame_dt, int *n)
{
    a->h_scale *= 0.5;
    int ns = clamp_substeps(a, 2.0 * *n, 1);
    double cost_be = fmax(frame_dt * a->k_be / (ADAPTIVE_AIM * a->d.tolerance), 2.0) * be_cost(a->it_be);
    if (ns > *n && ns < cost_be) {
        *n = ns;
        return CLOTH_SYMPLECTIC_EULER;
    }
    new_method(a, CLOTH_BACKWARD_EULER);
    *n = clamp_substeps(a, frame_dt * a->k_be / (ADAPTIVE_AIM * a->d.tolerance), 1);
    return CLOTH_BACKWARD_EULER;
}

cloth_status cloth_adaptive_frame(cloth_adaptive *a, cloth *c, double frame_dt, cloth_adaptive_stats *stats)
{
    cloth_adaptive_stats st;
    memset(&st, 0, sizeof st);
    if (stats) *stats = st;
    if (!a || !c) return CLOTH_EINVAL;
    if (c != a->owner || cloth_vertex_count(c) != a->n)
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_adaptive_frame: the controller was made for another cloth");
    if (!finite_pos(frame_dt)) {
        st.failure = CLOTH_FAIL_BAD_STEP;
        if (stats) *stats = st;
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_adaptive_frame: frame_dt = %g must be finite and > 0", frame_dt);
    }
    const cloth_solver user = cloth_get_desc(c).solver;
    size_t n3 = 3 * (size_t)a->n;
    cloth_save(c, a->snap);
    memcpy(a->cf0, c->con_force, n3 * sizeof *a->cf0);
    memcpy(a->acc_prev_start, a->acc_prev, n3 * sizeof *a->acc_prev);
    a->have_prev_start = a->have_prev;

    /* the global estimate needs the shadow to step what the cloth steps:
     * not with rigid bodies solved with the cloth (the shadow has none) */
    const int global = a->shadow && cloth_body_count(c) == 0;
    const double budget = a->d.tolerance * frame_dt, t_end = a->elapsed + frame_dt;
    int n = clamp_substeps(a, a->n_next, global);
    cloth_method method = CLOTH_BACKWARD_EULER;
    int synced_now = 0;
    if (global) {
        shadow_inputs(a, c);
        if (!a->shadow_synced) { /* (re)started from the cloth: no difference yet */
            a->global = 0.0;
            resync(a);
            a->shadow_synced = 1;
            synced_now = 1;
        }
        cloth_save(a->shadow, a->shadow_snap);
        method = choose_method(a, c, frame_dt, &n, &synced_now);
    } else {
        a->shadow_synced = 0;
    }
    double cg = clampd(a->cg_next, a->d.cg_tolerance_min, a->d.cg_tolerance_max);
    if (!a->have_prev) {
        /* the first frame: no acceleration from before it, so at least two
         * substeps for a velocity estimate, and a tight solve (nothing yet
         * to choose the tolerance from) */
        n = clamp_substeps(a, 2.0 * n, global);
        cg = clampd(1e-6, a->d.cg_tolerance_min, a->d.cg_tolerance_max);
    }
    st.error_budget = budget;
    attempt t;
    double g_est = 0.0;
    int shadow_failed = 0;
    const int fresh = global && synced_now; /* the shadow starts with the cloth this frame */
    int tried_explicit = 0;
    for (;;) {
        cloth_solver sv = user;
        sv.method = method;
        sv.cg_tolerance = cg;
        sv.newton_tolerance = fmin(user.newton_tolerance, newton_bound(a, frame_dt / n));
        /* the share's estimate bounds nothing, and its error is a bias the
         * shadow shares: the solves are held to the bounds above alone */
        sv.newton_cg_share = 0.0;
        cloth_set_solver(c, &sv);
        t = run_substeps(a, c, n, frame_dt / n);
        st.attempts++;
        st.steps += t.steps;
        st.cg_iterations += t.iterations;
        st.substeps = n;
        st.h = frame_dt / n;
        st.cg_tolerance = cg;
        st.method = method;
        st.error_estimate = t.ex + a->d.velocity_weight * t.ev;
        int ok = t.failure == CLOTH_FAIL_NONE && !t.callback_failed;
        shadow_failed = 0;
        if (ok && global) {
            cloth_set_solver(a->shadow, &sv); /* builds its multigrid levels when first chosen */
            shadow_failed = run_shadow(a, n, st.h, &st.steps, &st.cg_iterations);
            if (!shadow_failed) g_est = rms_diff(cloth_positions(c), cloth_positions(a->shadow), a->n);
        }
        /* the first frame, solved by backward Euler, is solved again by symplectic Euler (when its stable
         * step fits max_substeps) and the cheaper at the tolerance kept: backward Euler's coarse steps damp
         * stiff modes that its shadow, damping them too, does not see (docs/solver.md) */
        if (ok && global && !shadow_failed && fresh && !a->have_prev_start && method == CLOTH_BACKWARD_EULER &&
            a->d.allow_explicit && !tried_explicit) {
            tried_explicit = 1;
            first_frame_explicit(a, c, frame_dt, &sv, &t, &n, &method, &g_est, &st);
        }
        /* with the global estimate a frame is solved again only when the shadow started with it (first
         * frame, change of method): later, its share cannot be told from the motion's growth of the error */
        if (ok && global && !shadow_failed) {
            if (!fresh || st.attempts > 1 || g_est <= 2.0 * budget || a->carried + g_est <= a->d.tolerance * t_end ||
                n >= n_top(a, 1))
                break;
        } else if (ok && global && method == CLOTH_BACKWARD_EULER) {
            break; /* the shadow failed at 2 h where the cloth did not: kept, the shadow restarted next frame */
        } else if (ok && !global && (st.error_estimate <= 2.0 * budget || n >= a->d.max_substeps)) {
            break;
        }
        /* roll back to the frame's start */
        cloth_restore(c, a->snap);
        if (global) cloth_restore(a->shadow, a->shadow_snap);
        memcpy(a->acc_prev, a->acc_prev_start, n3 * sizeof *a->acc_prev);
        a->have_prev = a->have_prev_start;
        if (!ok && (t.callback_failed || (n >= n_top(a, global) && method == CLOTH_BACKWARD_EULER))) {
            cloth_set_solver(c, &user);
            memcpy(c->con_force, a->cf0, n3 * sizeof *a->cf0);
            st.failure = t.failure;
            if (stats) *stats = st;
            if (t.callback_failed)
                return oc_cloth_fail(c, CLOTH_ESTEP, "cloth_adaptive_frame: before_substep failed (state unchanged)");
            return oc_cloth_fail(c, CLOTH_ESTEP, "cloth_adaptive_frame: %s at %d substeps (state unchanged)",
                                 cloth_failure_string(t.failure), n);
        }
        if (method == CLOTH_SYMPLECTIC_EULER && (!ok || shadow_failed)) {
            method = explicit_failed(a, frame_dt, &n);
            continue;
        }
        /* a failed step: twice the substeps and a tighter solve; too large an
         * estimate: the substeps it asks for (the estimate scales as 1/n) */
        if (!ok) {
            n = clamp_substeps(a, 2.0 * n, global);
            cg = clampd(0.1 * cg, a->d.cg_tolerance_min, a->d.cg_tolerance_max);
        } else if (global) {
            n = clamp_substeps(a, n * g_est / (ADAPTIVE_AIM * budget), 1);
        } else {
            n = clamp_substeps(a, fmax(2.0 * n, n * st.error_estimate / (ADAPTIVE_LOCAL_AIM * budget)), global);
        }
    }
    cloth_set_solver(c, &user);
    a->elapsed = t_end;
    if (method == CLOTH_BACKWARD_EULER && t.steps > 0)
        a->it_be = a->it_be > 0.0 ? 0.8 * a->it_be + 0.2 * (double)t.iterations / t.steps
                                  : (double)t.iterations / t.steps;
    next_frame(a, frame_dt, n, &t, global, shadow_failed, g_est, method, &st);
    if (stats) *stats = st;
    return CLOTH_OK;
}
