/* Contacts with bodies' surfaces (cloth_set_contact): decided inside the
 * Newton step, so a vertex that would end inside a body is held on its
 * surface, and a sticking one that holds a link past the elongation limit
 * slides, in the same solve instead of by solving the step again. */
#include <math.h>
#include <string.h>
#include "internal.h"

cloth_status cloth_set_contact(cloth *c, int vertex, const double normal[3], const double point[3])
{
    if (!c) return CLOTH_EINVAL;
    if (!normal || !point)
        return cloth_fail(c, CLOTH_EINVAL, "cloth_set_contact: %s is NULL", normal ? "point" : "normal");
    if (vertex < 0 || vertex >= c->n)
        return cloth_fail(c, CLOTH_EINVAL, "cloth_set_contact: vertex %d out of range [0, %d)", vertex, c->n);
    if (!finite3(normal) || !finite3(point))
        return cloth_fail(c, CLOTH_EINVAL, "cloth_set_contact: %s must be finite", finite3(normal) ? "point" : "normal");
    /* scaled by the largest component first: neither huge nor tiny
     * components overflow or vanish when squared */
    double big = fmax(fabs(normal[0]), fmax(fabs(normal[1]), fabs(normal[2])));
    if (!(big > 0.0)) return cloth_fail(c, CLOTH_EINVAL, "cloth_set_contact: normal must be non-zero");
    double u[3] = {normal[0] / big, normal[1] / big, normal[2] / big};
    double len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    double *k = c->cand + 6 * (size_t)vertex;
    for (int r = 0; r < 3; r++) {
        k[r] = u[r] / len;
        k[3 + r] = point[r];
    }
    c->cand_on[vertex] = 1;
    c->cand_pull[vertex] = INFINITY;
    return CLOTH_OK;
}

cloth_status cloth_set_contact_pull(cloth *c, int vertex, double pull)
{
    if (!c) return CLOTH_EINVAL;
    if (vertex < 0 || vertex >= c->n)
        return cloth_fail(c, CLOTH_EINVAL, "cloth_set_contact_pull: vertex %d out of range [0, %d)", vertex, c->n);
    if (!(pull >= 0.0)) return cloth_fail(c, CLOTH_EINVAL, "cloth_set_contact_pull: pull = %g must be >= 0", pull);
    if (!c->cand_on[vertex])
        return cloth_fail(c, CLOTH_EINVAL, "cloth_set_contact_pull: vertex %d has no contact (cloth_set_contact)",
                          vertex);
    c->cand_pull[vertex] = pull;
    return CLOTH_OK;
}

/* free vertex i behind its surface by more than tol: held on its plane */
static int make_plane(cloth *c, int i, const double *k, const double *x, double tol)
{
    const double *xi = x + 3 * (size_t)i;
    double depth = k[0] * (k[3] - xi[0]) + k[1] * (k[4] - xi[1]) + k[2] * (k[5] - xi[2]);
    if (!(depth > tol)) return 0;
    cloth_constraint *q = &c->con[i];
    q->vertex = i;
    q->ndof = 1;
    memcpy(q->axis, k, 3 * sizeof *k);
    memcpy(q->target, k + 3, 3 * sizeof *k);
    c->cand_on[i] = c->cand_on[i] == 8 ? 9 : 2; /* held by the body cloth_hold_by_body named, if any */
    c->n_con++;
    return 1;
}

int contacts_decide(cloth *c, const double *x, double tol)
{
    int changed = 0;
    for (int i = 0; i < c->n; i++)
        if ((c->cand_on[i] == 1 || c->cand_on[i] == 8) && c->con[i].ndof == 0)
            changed += make_plane(c, i, c->cand + 6 * (size_t)i, x, tol);
    return changed;
}

int contacts_slide(cloth *c, const double *x)
{
    const cloth_material *m = &c->desc.material;
    double lim = (1.0 + m->delta) * (1.0 + c->desc.solver.limit_tolerance);
    int changed = 0;
    for (int e = 0; e < c->n_seq; e++) {
        const link_topo *L = &c->seq[e];
        int ends[2] = {L->i, L->j}, any = 0;
        for (int a = 0; a < 2; a++) any = any || (c->con[ends[a]].ndof == 3 && c->cand_on[ends[a]] == 1);
        if (!any) continue;
        double d2 = 0.0;
        for (int r = 0; r < 3; r++) {
            double w = x[3 * L->j + r] - x[3 * L->i + r];
            d2 += w * w;
        }
        if (d2 <= lim * lim * L->rest * L->rest) continue;
        for (int a = 0; a < 2; a++) {
            int i = ends[a];
            if (c->con[i].ndof != 3 || c->cand_on[i] != 1) continue;
            c->con[i].ndof = 1;
            memcpy(c->con[i].axis, c->cand + 6 * (size_t)i, 3 * sizeof(double));
            c->cand_on[i] = 3;
            changed++;
        }
    }
    return changed;
}

/* cand_on of a contact released by the step, by what it was: 6 a sliding
 * contact set so, 8 a plane the step made (a candidate again: a later
 * iterate behind the surface holds it once more), 4 such a plane made
 * again, 5 a contact it let slide (7: a sticking contact set so) */
static unsigned char released_as(unsigned char on) { return on == 1 ? 6 : on == 2 ? 8 : on == 9 ? 4 : 5; }

/* Releases contact i (a plane: set so, made so or let slide; or sticking,
 * set so) if its force b pulls it onto its surface by more than pull_min
 * (an impulse, N s). */
static int release_if_pulling(cloth *c, int i, const double *b, double pull_min)
{
    cloth_constraint *q = &c->con[i];
    int stuck = q->ndof == 3 && c->cand_on[i] == 1; /* sticking: pulls along its candidate's normal */
    int on = c->cand_on[i];
    if (((on < 1 || on > 3) && on != 9) || (q->ndof != 1 && !stuck)) return 0;
    const double *bi = b + 3 * (size_t)i, *ax = stuck ? c->cand + 6 * (size_t)i : q->axis;
    if (!(bi[0] * ax[0] + bi[1] * ax[1] + bi[2] * ax[2] > pull_min)) return 0; /* pushes */
    q->ndof = 0;
    c->cand_on[i] = stuck ? 7 : released_as(c->cand_on[i]);
    c->n_con--;
    return 1;
}

int contacts_release(cloth *c, const double *x, const double *b, double cfac)
{
    double lim = (1.0 + c->desc.material.delta) * (1.0 + c->desc.solver.limit_tolerance);
    int changed = 0;
    for (int e = 0; e < c->n_seq; e++) {
        const link_topo *L = &c->seq[e];
        double d2 = 0.0;
        for (int r = 0; r < 3; r++) {
            double w = x[3 * L->j + r] - x[3 * L->i + r];
            d2 += w * w;
        }
        if (d2 <= lim * lim * L->rest * L->rest) continue;
        changed += release_if_pulling(c, L->i, b, 0.0) + release_if_pulling(c, L->j, b, 0.0);
    }
    /* elsewhere a plane the step made, which is unilateral, at any pull (held
     * ahead of its surface, a pulling plane would do work on the cloth); a
     * contact set so, past its own pull */
    for (int i = 0; i < c->n; i++) {
        double pull = c->cand_on[i] == 2 || c->cand_on[i] == 9 ? 0.0 : c->cand_pull[i];
        if (pull < INFINITY) changed += release_if_pulling(c, i, b, cfac * pull);
    }
    return changed;
}

void contacts_land(cloth *c, const double *dv)
{
    for (int i = 0; i < c->n; i++) {
        double *z = c->z + 3 * (size_t)i;
        if ((c->cand_on[i] != 2 && c->cand_on[i] != 9) || !c->con[i].ndof) {
            z[0] = z[1] = z[2] = 0.0;
            continue;
        }
        /* what the next iteration must add to land the normal component,
         * on the holding body as it has moved so far */
        const double *S = c->S + 9 * (size_t)i, *dd = dv + 3 * (size_t)i;
        double d[3];
        bodies_held_motion(c, i, d);
        for (int r = 0; r < 3; r++) d[r] = dd[r] - d[r];
        for (int r = 0; r < 3; r++) z[r] -= d[r] - (S[3 * r] * d[0] + S[3 * r + 1] * d[1] + S[3 * r + 2] * d[2]);
    }
}

void contacts_begin(cloth *c)
{
    for (int i = 0; i < c->n; i++)
        if (c->cand_on[i] >= 2) c->cand_on[i] = 0; /* a plane kept from the last step: a constraint now */
}

void contacts_undo(cloth *c)
{
    for (int i = 0; i < c->n; i++) {
        if (c->cand_on[i] == 2 || c->cand_on[i] == 9 || c->cand_on[i] == 4 || c->cand_on[i] == 8) {
            if (c->cand_on[i] == 2 || c->cand_on[i] == 9) c->n_con--;
            memset(&c->con[i], 0, sizeof c->con[i]);
        } else if (c->cand_on[i] == 6) {
            c->con[i].ndof = 1;
            c->n_con++;
        } else if (c->cand_on[i] == 3 || c->cand_on[i] == 5 || c->cand_on[i] == 7) {
            if (c->cand_on[i] != 3) c->n_con++;
            c->con[i].ndof = 3;
            memset(c->con[i].axis, 0, sizeof c->con[i].axis);
        } else {
            continue;
        }
        c->cand_on[i] = 1;
    }
}
