/* The elongation limit delta (paper Table 1): after a step no sequential link is longer than (1 +
 * delta) l0. Fast projection (Goldenthal et al. 2007) with an active set and Levenberg-Marquardt
 * damping, not Provot's passes, which converge too slowly (docs/solver.md, "Design notes"). */
#include <math.h>
#include <string.h>
#include "internal.h"
#include "tuning.h"

/* Vertices held by a body solved with the cloth move with it: W_i gains P J Minv J^T P, with levers
 * and Minv taken at the projection's start, and links held in full by one body (rigid_pair) are left
 * out, both needed for a consistent linear model (docs/solver.md, "Design notes"). */
static int bodies_on(const cloth *c)
{
    cloth_method m = c->desc.solver.method;
    return c->body_held && (m == CLOTH_BACKWARD_EULER || m == CLOTH_BDF2);
}

/* u^T W u for a vertex: W = S / m (0 if pinned), plus its body's part */
static double wnorm(const cloth *c, const double *S, int i, const double u[3])
{
    double b = bodies_on(c) && oc_body_holds(c, i) ? oc_body_wnorm(c, S, i, u) : 0.0;
    if (c->con[i].ndof == 3) return b;
    if (c->con[i].ndof == 0) return b + 1.0 / c->mass[i];
    const double *Si = S + 9 * (size_t)i;
    double q = 0.0;
    for (int r = 0; r < 3; r++) q += u[r] * (Si[3 * r] * u[0] + Si[3 * r + 1] * u[1] + Si[3 * r + 2] * u[2]);
    return b + q / c->mass[i];
}

/* q_i += s W_i u: the vertex's own part now; its body's is gathered (see
 * bodies_spread) */
static void add_wu(const cloth *c, const double *S, int i, const double u[3], double s, double *q)
{
    if (bodies_on(c) && oc_body_holds(c, i)) oc_body_push((cloth *)c, S, i, u, s);
    if (c->con[i].ndof == 3) return;
    double *qi = q + 3 * (size_t)i, k = s / c->mass[i];
    if (c->con[i].ndof == 0) {
        for (int r = 0; r < 3; r++) qi[r] += k * u[r];
        return;
    }
    const double *Si = S + 9 * (size_t)i;
    for (int r = 0; r < 3; r++) qi[r] += k * (Si[3 * r] * u[0] + Si[3 * r + 1] * u[1] + Si[3 * r + 2] * u[2]);
}

/* The bodies' part of q = W G^T (...): each body moves by D = Minv F from
 * the impulses add_wu gathered, and the held ends of the active links with
 * it (each once: touched marks them, cleared again). */
static void bodies_spread(const cloth *c, int m, const int *act, const double *S, double *q, unsigned char *touched)
{
    if (!bodies_on(c)) return;
    oc_body_solve((cloth *)c);
    for (int t = 0; t < 2; t++)
        for (int a = 0; a < m; a++) {
            int i = t ? c->seq[act[a]].j : c->seq[act[a]].i;
            if (touched[i] || !oc_body_holds(c, i)) continue;
            touched[i] = 1;
            oc_body_move(c, S, i, 1.0, q);
        }
    for (int a = 0; a < m; a++) touched[c->seq[act[a]].i] = touched[c->seq[act[a]].j] = 0;
}

/* y = G W G^T p over the m active links (q: 3n scratch, zeroed on return) */
static void link_matvec(const cloth *c, const double *S, int m, const int *act, const double *u, const double *p,
                        double *q, double *y)
{
    for (int a = 0; a < m; a++) {
        const link_topo *L = &c->seq[act[a]];
        add_wu(c, S, L->i, u + 3 * a, -p[a], q);
        add_wu(c, S, L->j, u + 3 * a, p[a], q);
    }
    bodies_spread(c, m, act, S, q, c->sl_held + c->n_seq);
    for (int a = 0; a < m; a++) {
        const link_topo *L = &c->seq[act[a]];
        const double *qi = q + 3 * L->i, *qj = q + 3 * L->j, *ua = u + 3 * a;
        y[a] = ua[0] * (qj[0] - qi[0]) + ua[1] * (qj[1] - qi[1]) + ua[2] * (qj[2] - qi[2]);
    }
    for (int a = 0; a < m; a++) {
        const link_topo *L = &c->seq[act[a]];
        memset(q + 3 * L->i, 0, 3 * sizeof *q);
        memset(q + 3 * L->j, 0, 3 * sizeof *q);
    }
}

/* Sum of squared excess lengths over all sequential links, and their count. */
static double violation(const cloth *c, const double *x, double limit, int *over)
{
    double sum = 0.0;
    int n = 0;
    for (int e = 0; e < c->n_seq; e++) {
        const double *xi = x + 3 * c->seq[e].i, *xj = x + 3 * c->seq[e].j;
        double w0 = xj[0] - xi[0], w1 = xj[1] - xi[1], w2 = xj[2] - xi[2];
        double d = sqrt(w0 * w0 + w1 * w1 + w2 * w2), lmax = limit * c->seq[e].rest;
        if (d > lmax * (1.0 + SL_TOL)) {
            n++;
            sum += (d - lmax) * (d - lmax);
        }
    }
    *over = n;
    return sum;
}

/* x += s q over the vertices touched by the active links; each vertex once
 * (touched[] marks them). The other vertices held by a body move with it. */
static void apply_step(const cloth *c, const double *S, int m, const int *act, double *x, const double *q, double s,
                       unsigned char *touched)
{
    for (int a = 0; a < m; a++) {
        int ends[2] = {c->seq[act[a]].i, c->seq[act[a]].j};
        for (int t = 0; t < 2; t++) {
            size_t i = (size_t)ends[t];
            if (touched[i]) continue;
            touched[i] = 1;
            for (int k = 0; k < 3; k++) x[3 * i + k] += s * q[3 * i + k];
        }
    }
    if (bodies_on(c))
        for (int i = 0; i < c->n; i++)
            if (!touched[i] && oc_body_holds(c, i)) oc_body_move(c, S, i, s, x);
    for (int a = 0; a < m; a++) touched[c->seq[act[a]].i] = touched[c->seq[act[a]].j] = 0;
}

/* Do i and j move as one rigid piece in the projection (both held in full
 * by the same body)? Then no step changes the link's length. */
static int rigid_pair(const cloth *c, int i, int j)
{
    if (c->con[i].ndof != 3 || c->con[j].ndof != 3) return 0;
    int bi = bodies_on(c) && oc_body_holds(c, i), bj = bodies_on(c) && oc_body_holds(c, j);
    return bi && bj && c->vbody[i] == c->vbody[j];
}

/* Fill row a of the link system for link e at positions x: u, C = d - lmax,
 * and the inverse of its (damped) diagonal. 0 if neither end can move. */
static int link_row(const cloth *c, const double *S, const double *x, int e, double limit, double mu, double *ua,
                    double *Ca, double *dinva)
{
    int i = c->seq[e].i, j = c->seq[e].j;
    if (rigid_pair(c, i, j)) return 0;
    const double *xi = x + 3 * i, *xj = x + 3 * j;
    double w[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
    double d = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (!(d > 0.0)) return 0;
    for (int k = 0; k < 3; k++) ua[k] = w[k] / d;
    double diag = wnorm(c, S, i, ua) + wnorm(c, S, j, ua);
    if (!(diag > 0.0)) return 0;
    *Ca = d - limit * c->seq[e].rest;
    *dinva = 1.0 / (diag * (1.0 + mu));
    return 1;
}

/* CG on (G W G^T + mu diag) lambda = C over the m rows, Jacobi
 * preconditioned, from lambda = D^-1 C. */
static void solve_links(const cloth *c, const double *S, int m, const int *act, const double *u, const double *C,
                        const double *dinv, double mu, double *lam, double *r, double *p, double *y, double *q)
{
    double rz = 0.0, rz0;
    for (int a = 0; a < m; a++) lam[a] = dinv[a] * C[a];
    link_matvec(c, S, m, act, u, lam, q, y);
    for (int a = 0; a < m; a++) {
        y[a] += mu * lam[a] / (dinv[a] * (1.0 + mu));
        r[a] = C[a] - y[a];
        p[a] = dinv[a] * r[a];
        rz += r[a] * p[a];
    }
    rz0 = rz;
    for (int k = 0; k < SL_CG_MAX && rz > SL_CG_TOL * SL_CG_TOL * rz0 && rz > 0.0; k++) {
        link_matvec(c, S, m, act, u, p, q, y);
        double pAp = 0.0;
        for (int a = 0; a < m; a++) {
            y[a] += mu * p[a] / (dinv[a] * (1.0 + mu));
            pAp += p[a] * y[a];
        }
        if (!(pAp > 0.0)) break;
        double alpha = rz / pAp, rz1 = 0.0;
        for (int a = 0; a < m; a++) {
            lam[a] += alpha * p[a];
            r[a] -= alpha * y[a];
            rz1 += r[a] * r[a] * dinv[a];
        }
        double beta = rz1 / rz;
        rz = rz1;
        for (int a = 0; a < m; a++) p[a] = dinv[a] * r[a] + beta * p[a];
    }
}

/* q = -W G^T lambda (q zero on entry over the rows' vertices) */
static void step_of(const cloth *c, const double *S, int m, const int *act, const double *u, const double *lam,
                    double *q)
{
    for (int a = 0; a < m; a++) {
        const link_topo *L = &c->seq[act[a]];
        add_wu(c, S, L->i, u + 3 * a, lam[a], q);
        add_wu(c, S, L->j, u + 3 * a, -lam[a], q);
    }
    bodies_spread(c, m, act, S, q, c->sl_held + c->n_seq);
}

static void clear_step(const cloth *c, int m, const int *act, double *q)
{
    for (int a = 0; a < m; a++) {
        memset(q + 3 * (size_t)c->seq[act[a]].i, 0, 3 * sizeof *q);
        memset(q + 3 * (size_t)c->seq[act[a]].j, 0, 3 * sizeof *q);
    }
}

int oc_strain_limit(cloth *c, double *x, double *v, const double *S, double h, int iterations)
{
    double limit = 1.0 + c->desc.material.delta;
    int *act = c->sl_act;
    unsigned char *in = c->sl_held, *touched = c->sl_held + c->n_seq;
    memset(in, 0, (size_t)c->n_seq);
    double *u = c->sl, *C = u + 3 * (size_t)c->n_seq, *lam = C + c->n_seq, *r = lam + c->n_seq;
    double *p = r + c->n_seq, *y = p + c->n_seq, *dinv = y + c->n_seq, *q = c->sl_vtx;
    int first;
    if (bodies_on(c)) { /* the held vertices' levers from where they are now */
        memcpy(c->sl_x0, x, 3 * (size_t)c->n * sizeof *x);
        c->sl_x = c->sl_x0;
        oc_body_limit_begin(c);
    }
    double merit = violation(c, x, limit, &first), mu = SL_MU_MIN;
    int over = first;
    for (int it = 0; it < iterations && over > 0 && mu <= SL_MU_MAX; it++) {
        /* the set: links over the limit, or held at it by the last step */
        int m = 0;
        for (int e = 0; e < c->n_seq; e++) {
            const double *xi = x + 3 * c->seq[e].i, *xj = x + 3 * c->seq[e].j;
            double w0 = xj[0] - xi[0], w1 = xj[1] - xi[1], w2 = xj[2] - xi[2];
            double d = sqrt(w0 * w0 + w1 * w1 + w2 * w2);
            int want = in[e] || d > limit * c->seq[e].rest * (1.0 + SL_TOL);
            in[e] = 0;
            if (want && link_row(c, S, x, e, limit, mu, u + 3 * (size_t)m, C + m, dinv + m)) {
                act[m++] = e;
                in[e] = 1;
            }
        }
        if (m == 0) break;
        for (int round = 0;; round++) {
            solve_links(c, S, m, act, u, C, dinv, mu, lam, r, p, y, q);
            step_of(c, S, m, act, u, lam, q);
            if (round == SL_INNER - 1) break;
            int changed = 0;
            /* links the step would stretch over join; the rows are rebuilt
             * after the step is cleared (the step stays valid meanwhile) */
            int m1 = m;
            for (int e = 0; e < c->n_seq; e++) {
                if (in[e]) continue;
                const link_topo *L = &c->seq[e];
                const double *xi = x + 3 * L->i, *xj = x + 3 * L->j, *qi = q + 3 * L->i, *qj = q + 3 * L->j;
                double w0 = xj[0] - xi[0] + qj[0] - qi[0], w1 = xj[1] - xi[1] + qj[1] - qi[1];
                double w2 = xj[2] - xi[2] + qj[2] - qi[2];
                if (!(w0 * w0 + w1 * w1 + w2 * w2 > (limit * L->rest) * (limit * L->rest) * (1.0 + 2.0 * SL_TOL)))
                    continue;
                if (m1 < c->n_seq && link_row(c, S, x, e, limit, mu, u + 3 * (size_t)m1, C + m1, dinv + m1)) {
                    act[m1++] = e;
                    in[e] = 1;
                    changed = 1;
                }
            }
            clear_step(c, m, act, q);
            /* links that would push leave (only those that are not over now) */
            int k = 0;
            for (int a = 0; a < m1; a++) {
                if (a < m && lam[a] < 0.0 && C[a] <= 0.0) {
                    in[act[a]] = 0;
                    changed = 1;
                    continue;
                }
                act[k] = act[a];
                C[k] = C[a];
                dinv[k] = dinv[a];
                memcpy(u + 3 * (size_t)k, u + 3 * (size_t)a, 3 * sizeof *u);
                k++;
            }
            m = k;
            if (!changed) {
                /* the same set: recompute its step */
                solve_links(c, S, m, act, u, C, dinv, mu, lam, r, p, y, q);
                step_of(c, S, m, act, u, lam, q);
                break;
            }
        }
        /* backtracking on the summed squared violation: the full step, then
         * halves of it; if none lowers it, undo and damp harder */
        double s = 1.0, merit1 = merit;
        int over1 = over, kept = 0;
        apply_step(c, S, m, act, x, q, 1.0, touched);
        for (int half = 0; half < SL_HALVINGS; half++) {
            merit1 = violation(c, x, limit, &over1);
            if (merit1 < merit) {
                kept = 1;
                break;
            }
            apply_step(c, S, m, act, x, q, -0.5 * s, touched);
            s *= 0.5;
        }
        if (kept) { /* velocities follow; pushing links leave */
            apply_step(c, S, m, act, v, q, s / h, touched);
            if (bodies_on(c)) oc_body_kept(c, s / h);
            for (int a = 0; a < m; a++) in[act[a]] = lam[a] > 0.0;
            merit = merit1;
            over = over1;
            mu = mu / 10.0 > SL_MU_MIN ? mu / 10.0 : SL_MU_MIN;
        } else {
            apply_step(c, S, m, act, x, q, -s, touched);
            mu *= 10.0;
        }
        clear_step(c, m, act, q);
    }
    c->sl_x = NULL;
    return first;
}
