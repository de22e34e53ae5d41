/* Per-vertex velocity constraints (Baraff-Witkin 1998, section 5) as plain
 * data: pins (3 DOF), planes (1 DOF), lines (2 DOF). The step turns each into
 * a filter S_i and a target velocity change z_i (step.c). */
#include <math.h>
#include <string.h>
#include "internal.h"

cloth_status cloth_set_constraint(cloth *c, const cloth_constraint *k)
{
    if (!c) return CLOTH_EINVAL;
    if (!k) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_constraint: constraint is NULL");
    if (k->vertex < 0 || k->vertex >= c->n)
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_constraint: vertex %d out of range [0, %d)", k->vertex, c->n);
    if (k->ndof < 0 || k->ndof > 3)
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_constraint: ndof %d must be 0, 1, 2 or 3", k->ndof);
    if (!finite3(k->target)) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_constraint: target must be finite");
    cloth_constraint kk = *k;
    if (k->ndof == 1 || k->ndof == 2) {
        if (!finite3(k->axis)) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_constraint: axis must be finite");
        /* scaled by its largest component first, so that neither huge
         * (1e200) nor tiny (1e-200) components overflow or vanish when
         * squared (found by unit_fuzz_api: 1e154 became a zero normal) */
        double big = fmax(fabs(k->axis[0]), fmax(fabs(k->axis[1]), fabs(k->axis[2])));
        if (!(big > 0.0)) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_constraint: axis must be non-zero");
        double n2 = k->axis[0] * k->axis[0] + k->axis[1] * k->axis[1] + k->axis[2] * k->axis[2];
        if (n2 > 1e-280 && n2 < 1e280) { /* the common case, kept bit for bit */
            double n = sqrt(n2);
            for (int a = 0; a < 3; a++) kk.axis[a] = k->axis[a] / n;
        } else {
            double u[3] = {k->axis[0] / big, k->axis[1] / big, k->axis[2] / big};
            double n = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
            for (int a = 0; a < 3; a++) kk.axis[a] = u[a] / n;
        }
    } else {
        kk.axis[0] = kk.axis[1] = kk.axis[2] = 0.0;
    }
    if (c->cand2_on[k->vertex] >= 2) c->cand2_on[k->vertex] = 0; /* a second plane held ends with it */
    int was = c->con[k->vertex].ndof != 0, now = kk.ndof != 0;
    c->con[k->vertex] = kk;
    c->n_con += now - was;
    if (c->vbody) c->vbody[k->vertex] = -1;
    if (!now) memset(c->con_force + 3 * k->vertex, 0, 3 * sizeof(double));
    return CLOTH_OK;
}

cloth_status cloth_pin(cloth *c, int vertex, const double target[3])
{
    if (!c) return CLOTH_EINVAL;
    if (!target) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_pin: target is NULL");
    cloth_constraint k = {.vertex = vertex, .ndof = 3};
    memcpy(k.target, target, sizeof k.target);
    return cloth_set_constraint(c, &k);
}

cloth_status cloth_release(cloth *c, int vertex)
{
    if (!c) return CLOTH_EINVAL;
    cloth_constraint k = {.vertex = vertex, .ndof = 0};
    cloth_status s = cloth_set_constraint(c, &k);
    if (s == CLOTH_OK) c->cand_on[vertex] = c->cand2_on[vertex] = 0;
    return s;
}

void cloth_release_all(cloth *c)
{
    if (!c) return;
    memset(c->con, 0, (size_t)c->n * sizeof *c->con);
    memset(c->con_force, 0, 3 * (size_t)c->n * sizeof *c->con_force);
    memset(c->cand_on, 0, (size_t)c->n);
    memset(c->cand2_on, 0, (size_t)c->n);
    c->n_con = 0;
    if (c->vbody)
        for (int i = 0; i < c->n; i++) c->vbody[i] = -1;
}

cloth_status cloth_get_constraint(const cloth *c, int vertex, cloth_constraint *out)
{
    if (!c) return CLOTH_EINVAL;
    if (!out) return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_get_constraint: out is NULL");
    if (vertex < 0 || vertex >= c->n)
        return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_get_constraint: vertex %d out of range [0, %d)", vertex,
                             c->n);
    *out = c->con[vertex];
    out->vertex = vertex;
    return CLOTH_OK;
}

int cloth_constraint_count(const cloth *c) { return c ? c->n_con : 0; }

cloth_status cloth_constraint_force(const cloth *c, int vertex, double f[3])
{
    if (!c) return CLOTH_EINVAL;
    if (!f) return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_constraint_force: f is NULL");
    if (vertex < 0 || vertex >= c->n)
        return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_constraint_force: vertex %d out of range [0, %d)", vertex,
                             c->n);
    memcpy(f, c->con_force + 3 * vertex, 3 * sizeof(double));
    return CLOTH_OK;
}

static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

/* The filter S_i of each vertex and z_i = (I - S_i)(v_target - v0), the velocity change that lands
 * its constrained components on the target given x_new = a + cfac v_new; a substep aims at frac of
 * the way from xs (the whole step's start) to the target (frac 1 or xs NULL: the target). */
void oc_constraints_build(cloth *c, const double *a, const double *v0, double cfac, const double *xs, double frac)
{
    int m = 0;
    for (int i = 0; i < c->n; i++)
        if (c->con[i].ndof) c->clist[m++] = i;
    for (int i = 0; i < c->n; i++) {
        double *S = c->S + 9 * (size_t)i, *z = c->z + 3 * (size_t)i;
        const cloth_constraint *k = &c->con[i];
        c->cflag[i] = k->ndof != 0;
        memcpy(S, I3, sizeof I3);
        z[0] = z[1] = z[2] = 0.0;
        if (k->ndof == 0) continue;
        const double *n = k->axis;
        for (int r = 0; r < 3; r++)
            for (int s = 0; s < 3; s++) {
                double nn = n[r] * n[s];
                if (k->ndof == 3) S[3 * r + s] = 0.0;
                else if (k->ndof == 1) S[3 * r + s] -= nn; /* plane: normal constrained */
                else S[3 * r + s] = nn;                    /* line: only the axis free  */
            }
        double dvt[3], tg[3];
        for (int r = 0; r < 3; r++)
            tg[r] = xs && frac != 1.0 ? xs[3 * i + r] + frac * (k->target[r] - xs[3 * i + r]) : k->target[r];
        if (c->body_retry) oc_bodies_retry_target(c, i, c->body_hs, tg);
        for (int r = 0; r < 3; r++) dvt[r] = (tg[r] - a[3 * i + r]) / cfac - v0[3 * i + r];
        for (int r = 0; r < 3; r++) z[r] = dvt[r] - (S[3 * r] * dvt[0] + S[3 * r + 1] * dvt[1] + S[3 * r + 2] * dvt[2]);
        /* on the target where constrained, moving on at v0 where free */
        for (int r = 0; r < 3; r++) c->x_lever[3 * i + r] = a[3 * i + r] + cfac * (v0[3 * i + r] + z[r]);
    }
}
