/* Contacts with bodies' surfaces (cloth_set_contact, and a second plane a vertex, cloth_set_contact_second),
 * decided inside the Newton step: held behind a surface, let go where it pulls, a sticking one on a link past
 * the limit let slide; on two planes a vertex is held on their line (internal.h: con, con1). */
#include <math.h>
#include <string.h>
#include "internal.h"
#include "vec3.h"
#include "tuning.h"

/* The plane (normal, point) of a vertex checked for `who` and stored in its
 * row of `planes` (6 each: the unit normal, the point); nothing on an error */
static cloth_status set_plane(cloth *c, const char *who, int vertex, const double normal[3], const double point[3],
                              double *planes)
{
    if (!c) return CLOTH_EINVAL;
    if (!normal || !point) return oc_cloth_fail(c, CLOTH_EINVAL, "%s: %s is NULL", who, normal ? "point" : "normal");
    if (vertex < 0 || vertex >= c->n)
        return oc_cloth_fail(c, CLOTH_EINVAL, "%s: vertex %d out of range [0, %d)", who, vertex, c->n);
    if (!finite3(normal) || !finite3(point))
        return oc_cloth_fail(c, CLOTH_EINVAL, "%s: %s must be finite", who, finite3(normal) ? "point" : "normal");
    /* scaled by the largest component first: neither huge nor tiny
     * components overflow or vanish when squared */
    double big = fmax(fabs(normal[0]), fmax(fabs(normal[1]), fabs(normal[2])));
    if (!(big > 0.0)) return oc_cloth_fail(c, CLOTH_EINVAL, "%s: normal must be non-zero", who);
    double u[3] = {normal[0] / big, normal[1] / big, normal[2] / big};
    double len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    double *k = planes + 6 * (size_t)vertex;
    for (int r = 0; r < 3; r++) {
        k[r] = u[r] / len;
        k[3 + r] = point[r];
    }
    return CLOTH_OK;
}

cloth_status cloth_set_contact(cloth *c, int vertex, const double normal[3], const double point[3])
{
    cloth_status s = set_plane(c, "cloth_set_contact", vertex, normal, point, c ? c->cand : NULL);
    if (s != CLOTH_OK) return s;
    c->cand_on[vertex] = 1;
    c->cand_pull[vertex] = INFINITY;
    return CLOTH_OK;
}

cloth_status cloth_set_contact_pull(cloth *c, int vertex, double pull)
{
    if (!c) return CLOTH_EINVAL;
    if (vertex < 0 || vertex >= c->n)
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_contact_pull: vertex %d out of range [0, %d)", vertex, c->n);
    if (!(pull >= 0.0)) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_contact_pull: pull = %g must be >= 0", pull);
    if (!c->cand_on[vertex])
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_contact_pull: vertex %d has no contact (cloth_set_contact)",
                             vertex);
    c->cand_pull[vertex] = pull;
    return CLOTH_OK;
}

cloth_status cloth_set_contact_second(cloth *c, int vertex, const double normal[3], const double point[3])
{
    cloth_status s = set_plane(c, "cloth_set_contact_second", vertex, normal, point, c ? c->cand2 : NULL);
    if (s == CLOTH_OK) c->cand2_on[vertex] = 1;
    return s;
}

/* whether vertex i's second plane holds it */
static int second_held(const cloth *c, int i) { return c->cand2_on[i] == 2 || c->cand2_on[i] == 9; }

/* vertex i's constraint without its second plane */
static cloth_constraint *first(cloth *c, int i) { return second_held(c, i) ? &c->con1[i] : &c->con[i]; }

/* whether unit normals n1 and n2 are too near parallel to meet in a line */
static int near_parallel(const double *n1, const double *n2)
{
    double d = vec3_dot(n1, n2);
    return !(1.0 - d * d > PLANES_PARALLEL * PLANES_PARALLEL);
}

/* (I - S) b, for a vertex on two planes of unit normals n1 and n2, as mu1
 * n1 + mu2 n2 (the Gram system of the two normals) */
static void split_planes(const double *n1, const double *n2, const double *b, double *mu1, double *mu2)
{
    double g = vec3_dot(n1, n2), d = 1.0 - g * g, b1 = vec3_dot(n1, b), b2 = vec3_dot(n2, b);
    *mu1 = (b1 - g * b2) / d;
    *mu2 = (b2 - g * b1) / d;
}

/* con[i] again from con1[i] and the second plane, which holds vertex i:
 * that plane alone, or the line where it meets con1's plane (the target
 * moved from con1's along both normals onto both planes) */
static void meet(cloth *c, int i)
{
    const cloth_constraint *o = &c->con1[i];
    const double *k = c->cand2 + 6 * (size_t)i;
    cloth_constraint *q = &c->con[i];
    q->vertex = i;
    if (o->ndof == 0) {
        q->ndof = 1;
        memcpy(q->axis, k, 3 * sizeof *k);
        memcpy(q->target, k + 3, 3 * sizeof *k);
        return;
    }
    const double *n1 = o->axis, *n2 = k;
    double t[3];
    vec3_cross(n1, n2, t);
    double tl = vec3_norm(t), g = vec3_dot(n1, n2), d = 1.0 - g * g;
    double r2 = n2[0] * (k[3] - o->target[0]) + n2[1] * (k[4] - o->target[1]) + n2[2] * (k[5] - o->target[2]);
    double a1 = -g * r2 / d, a2 = r2 / d;
    q->ndof = 2;
    for (int r = 0; r < 3; r++) {
        q->axis[r] = t[r] / tl;
        q->target[r] = o->target[r] + a1 * n1[r] + a2 * n2[r];
    }
}

/* vertex i's second plane lets go: con[i] is its own constraint again; a candidate
 * again if held once so far */
static void second_let_go(cloth *c, int i)
{
    c->con[i] = c->con1[i];
    c->cand2_on[i] = c->cand2_on[i] == 2 ? 8 : 4;
}

/* vertex i's constraint changed (first(c, i)): con[i] follows */
static void sync(cloth *c, int i)
{
    if (second_held(c, i)) meet(c, i);
}

/* n_con again after contacts changed */
static void recount(cloth *c)
{
    int m = 0;
    for (int i = 0; i < c->n; i++) m += c->con[i].ndof != 0;
    c->n_con = m;
}

/* how far x_i is behind plane k (normal, point) */
static double behind(const double *k, const double *x, int i)
{
    const double *xi = x + 3 * (size_t)i;
    return k[0] * (k[3] - xi[0]) + k[1] * (k[4] - xi[1]) + k[2] * (k[5] - xi[2]);
}

/* free vertex i behind its surface by more than tol: held on its plane (with
 * the second, on their line; the second let go where the two are parallel) */
static int make_plane(cloth *c, int i, const double *k, const double *x, double tol)
{
    if (!(behind(k, x, i) > tol)) return 0;
    cloth_constraint *q = first(c, i);
    q->vertex = i;
    q->ndof = 1;
    memcpy(q->axis, k, 3 * sizeof *k);
    memcpy(q->target, k + 3, 3 * sizeof *k);
    /* held by the body cloth_hold_by_body named, if any */
    c->cand_on[i] = c->cand_on[i] == 8 ? 9 : c->cand_on[i] == 10 ? 11 : 2;
    if (second_held(c, i) && near_parallel(k, c->cand2 + 6 * (size_t)i)) second_let_go(c, i);
    sync(c, i);
    return 1;
}

/* vertex i (free or on one plane, held by no body) behind its second plane
 * by more than tol: held on it too */
static int make_second(cloth *c, int i, const double *x, double tol)
{
    const double *k = c->cand2 + 6 * (size_t)i;
    cloth_constraint *q = &c->con[i];
    if ((q->ndof != 0 && q->ndof != 1) || (c->vbody && c->vbody[i] >= 0)) return 0;
    if (q->ndof == 1 && near_parallel(q->axis, k)) return 0;
    if (!(behind(k, x, i) > tol)) return 0;
    c->con1[i] = *q;
    c->cand2_on[i] = c->cand2_on[i] == 8 ? 9 : 2;
    meet(c, i);
    return 1;
}

int oc_contacts_decide(cloth *c, const double *x, double tol)
{
    int changed = 0;
    for (int i = 0; i < c->n; i++) {
        int on = c->cand_on[i];
        if ((on == 1 || on == 8 || on == 10) && first(c, i)->ndof == 0)
            changed += make_plane(c, i, c->cand + 6 * (size_t)i, x, tol);
        if (c->cand2_on[i] == 1 || c->cand2_on[i] == 8) changed += make_second(c, i, x, tol);
    }
    if (changed) recount(c);
    return changed;
}

int oc_contacts_slide(cloth *c, const double *x)
{
    const cloth_material *m = &c->desc.material;
    double lim = (1.0 + m->delta) * (1.0 + c->desc.solver.limit_tolerance);
    int changed = 0;
    for (int e = 0; e < c->n_seq; e++) {
        const link_topo *L = &c->seq[e];
        int ends[2] = {L->i, L->j}, any = 0;
        for (int a = 0; a < 2; a++) any = any || (first(c, ends[a])->ndof == 3 && c->cand_on[ends[a]] == 1);
        if (!any) continue;
        double d2 = 0.0;
        for (int r = 0; r < 3; r++) {
            double w = x[3 * L->j + r] - x[3 * L->i + r];
            d2 += w * w;
        }
        if (d2 <= lim * lim * L->rest * L->rest) continue;
        for (int a = 0; a < 2; a++) {
            int i = ends[a];
            cloth_constraint *q = first(c, i);
            if (q->ndof != 3 || c->cand_on[i] != 1) continue;
            q->ndof = 1;
            memcpy(q->axis, c->cand + 6 * (size_t)i, 3 * sizeof(double));
            c->cand_on[i] = 3;
            sync(c, i);
            changed++;
        }
    }
    return changed;
}

/* cand_on of vertex i's released contact by its code (internal.h: cand_on); a plane the step made,
 * or a set sliding one, is a candidate again, held at most once */
static unsigned char released_as(const cloth *c, int i)
{
    unsigned char on = c->cand_on[i];
    return on == 1 ? 10 : on == 11 ? 6 : on == 2 ? 8 : on == 9 ? 4 : 5;
}

/* whether vertex i's contact is a plane the step made */
static int made(const cloth *c, int i) { return c->cand_on[i] == 2 || c->cand_on[i] == 9 || c->cand_on[i] == 11; }

/* Releases contact i (a plane set, made or let slide; or a set sticking one) if its force b pulls it
 * onto its surface by more than the impulse pull_min (N s), and its second plane if that pulls by
 * more than pull2 (each plane's force apart where both hold). */
static int release_if_pulling(cloth *c, int i, const double *b, double pull_min, double pull2)
{
    cloth_constraint *q = first(c, i);
    int stuck = q->ndof == 3 && c->cand_on[i] == 1; /* sticking: pulls along its candidate's normal */
    int on = c->cand_on[i], two = second_held(c, i);
    int plane = ((on >= 1 && on <= 3) || on == 9 || on == 11) && (q->ndof == 1 || stuck);
    if (!plane && !two) return 0;
    const double *bi = b + 3 * (size_t)i, *ax = stuck ? c->cand + 6 * (size_t)i : q->axis;
    const double *n2 = c->cand2 + 6 * (size_t)i;
    double mu1 = plane ? vec3_dot(bi, ax) : 0.0, mu2 = two ? vec3_dot(bi, n2) : 0.0;
    if (two && q->ndof == 1) split_planes(q->axis, n2, bi, &mu1, &mu2);
    int go1 = plane && mu1 > pull_min, go2 = two && mu2 > pull2; /* else they push */
    if (go1) {
        q->ndof = 0;
        c->cand_on[i] = stuck ? 7 : released_as(c, i);
    }
    if (go2) second_let_go(c, i);
    sync(c, i);
    return go1 + go2;
}

int oc_contacts_release(cloth *c, const double *x, const double *b, double cfac)
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
        changed += release_if_pulling(c, L->i, b, 0.0, 0.0) + release_if_pulling(c, L->j, b, 0.0, 0.0);
    }
    /* elsewhere a plane the step made, which is unilateral, at any pull (held
     * ahead of its surface, a pulling plane would do work on the cloth: the
     * second plane too); a contact set so, past its own pull */
    for (int i = 0; i < c->n; i++) {
        double pull = made(c, i) ? 0.0 : c->cand_pull[i];
        if (pull < INFINITY || second_held(c, i)) changed += release_if_pulling(c, i, b, cfac * pull, 0.0);
    }
    if (changed) recount(c);
    return changed;
}

void oc_contacts_land(cloth *c, const double *dv)
{
    for (int i = 0; i < c->n; i++) {
        double *z = c->z + 3 * (size_t)i;
        if ((!made(c, i) || !first(c, i)->ndof) && !second_held(c, i)) {
            z[0] = z[1] = z[2] = 0.0;
            continue;
        }
        /* what the next iteration must add to land the normal component,
         * on the holding body as it has moved so far */
        const double *S = c->S + 9 * (size_t)i, *dd = dv + 3 * (size_t)i;
        double d[3];
        oc_bodies_held_motion(c, i, d);
        for (int r = 0; r < 3; r++) d[r] = dd[r] - d[r];
        for (int r = 0; r < 3; r++) z[r] -= d[r] - (S[3 * r] * d[0] + S[3 * r + 1] * d[1] + S[3 * r + 2] * d[2]);
    }
}

void oc_contacts_begin(cloth *c)
{
    for (int i = 0; i < c->n; i++) {
        if (c->cand_on[i] >= 2) c->cand_on[i] = 0; /* a plane kept from the last step: a constraint now */
        if (c->cand2_on[i] >= 2) c->cand2_on[i] = 0;
    }
}

void oc_contacts_undo(cloth *c)
{
    for (int i = 0; i < c->n; i++) {
        if (c->cand2_on[i] >= 2) { /* the second first: con[i] is then the vertex's own again */
            if (second_held(c, i)) c->con[i] = c->con1[i];
            c->cand2_on[i] = 1;
        }
        if (c->cand_on[i] == 2 || c->cand_on[i] == 9 || c->cand_on[i] == 4 || c->cand_on[i] == 8) {
            memset(&c->con[i], 0, sizeof c->con[i]);
        } else if (c->cand_on[i] == 6 || c->cand_on[i] == 10 || c->cand_on[i] == 11) {
            c->con[i].ndof = 1;
        } else if (c->cand_on[i] == 3 || c->cand_on[i] == 5 || c->cand_on[i] == 7) {
            c->con[i].ndof = 3;
            memset(c->con[i].axis, 0, sizeof c->con[i].axis);
        } else {
            continue;
        }
        c->cand_on[i] = 1;
    }
    recount(c);
}

cloth_status cloth_get_contact_planes(const cloth *c, int vertex, cloth_constraint *first_out, int *second,
                                      double f_first[3], double f_second[3])
{
    if (!c) return CLOTH_EINVAL;
    if (vertex < 0 || vertex >= c->n)
        return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_get_contact_planes: vertex %d out of range [0, %d)",
                             vertex, c->n);
    int two = second_held(c, vertex);
    const cloth_constraint *q = two ? &c->con1[vertex] : &c->con[vertex];
    const double *f = c->con_force + 3 * (size_t)vertex, *n2 = c->cand2 + 6 * (size_t)vertex;
    double mu1 = 0.0, mu2 = 0.0, f1[3], f2[3];
    if (two && q->ndof == 1) split_planes(q->axis, n2, f, &mu1, &mu2);
    for (int r = 0; r < 3; r++) {
        f2[r] = !two ? 0.0 : q->ndof == 1 ? mu2 * n2[r] : q->ndof == 0 ? f[r] : 0.0;
        f1[r] = f[r] - f2[r];
    }
    if (first_out) {
        *first_out = *q;
        first_out->vertex = vertex;
    }
    if (second) *second = two;
    if (f_first) memcpy(f_first, f1, sizeof f1);
    if (f_second) memcpy(f_second, f2, sizeof f2);
    return CLOTH_OK;
}
