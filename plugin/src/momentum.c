/* The cloth's angular momentum that no force explains (non-central frozen-direction forces, backward
 * Euler's start-of-step change, solver tolerances), and the least-energy rigid turn that takes it out
 * of the cloth and the moving bodies holding it, together (reactions.c). */
#include <math.h>
#include <string.h>
#include "dcloth_internal.h"
#include "eigen6.h"
#include "journal.h"
#include "momentum.h"
#include "vertex_force.h"

static void cross_add(const double *r, const double *f, double s, double *t)
{
    t[0] += s * (r[1] * f[2] - r[2] * f[1]);
    t[1] += s * (r[2] * f[0] - r[0] * f[2]);
    t[2] += s * (r[0] * f[1] - r[1] * f[0]);
}

void dcloth_leftover_torque(dClothID c, double h, const double F[3], double wsum, double T[3])
{
    cloth *core = c->core;
    const double *x1 = cloth_positions(core), *v1 = cloth_velocities(core), *m = cloth_masses(core);
    const double *g = cloth_get_desc(core).gravity;
    double ref[3] = {0.0, 0.0, 0.0}, air[3], tair[3];
    /* about the start's centroid, a fixed point near the cloth, for rounding */
    for (int i = 0; i < c->n; i++)
        for (int r = 0; r < 3; r++) ref[r] += c->step.x0[3 * i + r] / c->n;
    T[0] = T[1] = T[2] = 0.0;
    for (int i = 0; i < c->n; i++) {
        double r0[3], r1[3], f[3], cf[3];
        for (int r = 0; r < 3; r++) {
            r0[r] = c->step.x0[3 * i + r] - ref[r];
            r1[r] = x1[3 * i + r] - ref[r];
            f[r] = m[i] * g[r] + c->step.fext[3 * i + r];
        }
        cross_add(r1, v1 + 3 * i, m[i] / h, T);
        cross_add(r0, c->step.v0 + 3 * i, -m[i] / h, T);
        cross_add(r1, f, -1.0, T);
        if (!c->pin[i].active && !c->vc_new[i].active) continue;
        cloth_constraint_force(core, i, cf);
        double w = wsum > 0.0 ? sqrt(dcloth_dot3(cf, cf)) / wsum : 0.0;
        for (int r = 0; r < 3; r++) cf[r] += w * F[r];
        cross_add(r1, cf, -1.0, T);
    }
    /* the air's, given about the origin */
    cloth_air_force(core, air);
    cloth_air_torque(core, tair);
    cross_add(ref, air, -1.0, tair);
    for (int r = 0; r < 3; r++) T[r] -= tair[r];
}

/* The moving body (dynamic, not kinematic) that takes vertex i's force
 * (c->reactions.holder) by a pin or a contact the step kept, or 0 */
static dBodyID mover(dClothID c, int i)
{
    cloth_constraint k;
    dBodyID b = c->reactions.holder[i];
    if (!c->pin[i].active && !(cloth_get_constraint(c->core, i, &k) == CLOTH_OK && k.ndof)) b = 0;
    return b && !dBodyIsKinematic(b) ? b : 0;
}

/* the rigid velocity y = (u, w / L) at offset r */
static void rigid(const double y[6], const double r[3], double L, double v[3])
{
    double w[3] = {y[3] / L, y[4] / L, y[5] / L};
    v[0] = y[0] + w[1] * r[2] - w[2] * r[1];
    v[1] = y[1] + w[2] * r[0] - w[0] * r[2];
    v[2] = y[2] + w[0] * r[1] - w[1] * r[0];
}

/* adds the momenta (P, L / len) of mass m moving at v at offset r to out */
static void momenta(const double r[3], double m, const double v[3], double L, double out[6])
{
    double t[3] = {0.0, 0.0, 0.0};
    cross_add(r, v, m / L, t);
    for (int q = 0; q < 3; q++) {
        out[q] += m * v[q];
        out[3 + q] += t[q];
    }
}

/* The momenta (P, L / len) of the rigid change y of the cloth and bodies bs[nb] about ref */
static void turn_momenta(dClothID c, dBodyID *bs, int nb, const double ref[3], const double y[6], double L,
                         double out[6])
{
    const double *x = cloth_positions(c->core), *m = cloth_masses(c->core);
    for (int q = 0; q < 6; q++) out[q] = 0.0;
    for (int i = 0; i < c->n; i++) {
        double r[3] = {x[3 * i] - ref[0], x[3 * i + 1] - ref[1], x[3 * i + 2] - ref[2]}, v[3];
        rigid(y, r, L, v);
        momenta(r, m[i], v, L, out);
    }
    for (int k = 0; k < nb; k++) {
        dMass ms;
        dBodyGetMass(bs[k], &ms);
        const dReal *cb = dBodyGetPosition(bs[k]), *R = dBodyGetRotation(bs[k]);
        double r[3] = {cb[0] - ref[0], cb[1] - ref[1], cb[2] - ref[2]}, v[3], wl[3], Iw[3];
        rigid(y, r, L, v);
        momenta(r, ms.mass, v, L, out);
        for (int q = 0; q < 3; q++) wl[q] = (R[q] * y[3] + R[4 + q] * y[4] + R[8 + q] * y[5]) / L; /* R^T w */
        for (int q = 0; q < 3; q++) Iw[q] = ms.I[4 * q] * wl[0] + ms.I[4 * q + 1] * wl[1] + ms.I[4 * q + 2] * wl[2];
        for (int q = 0; q < 3; q++) out[3 + q] += (R[4 * q] * Iw[0] + R[4 * q + 1] * Iw[1] + R[4 * q + 2] * Iw[2]) / L;
    }
}

/* The turn's constraints (y = (u, w len), velocity u + w x (x - ref)) as
 * rows, each accumulated into A += row row^T: a velocity along n at point a
 * that stays none; a rotation about t, or a translation along it, none */
static void add_row(double A[6][6], const double row[6])
{
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) A[i][j] += row[i] * row[j];
}

static void keep_along(double A[6][6], const dReal *a, const double n[3], const double ref[3], double len)
{
    double r[3] = {a[0] - ref[0], a[1] - ref[1], a[2] - ref[2]}, row[6] = {n[0], n[1], n[2], 0.0, 0.0, 0.0};
    double t[3] = {0.0, 0.0, 0.0};
    cross_add(r, n, 1.0 / len, t); /* n . (w x r) = w . (r x n) */
    for (int q = 0; q < 3; q++) row[3 + q] = t[q];
    add_row(A, row);
}

static void keep_point(double A[6][6], const dReal *a, const double ref[3], double len)
{
    double e[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int q = 0; q < 3; q++) keep_along(A, a, e[q], ref, len);
}

static void keep_dir(double A[6][6], const double t[3], int angular, double len)
{
    double row[6] = {0};
    for (int q = 0; q < 3; q++) row[3 * angular + q] = angular ? t[q] / len : t[q];
    add_row(A, row);
}

/* two unit vectors perpendicular to unit a */
static void perpendicular(const dReal *a, double t1[3], double t2[3])
{
    double e[3] = {fabs(a[0]) < 0.6 ? 1.0 : 0.0, fabs(a[0]) < 0.6 ? 0.0 : 1.0, 0.0}, n = 0.0;
    double ad[3] = {a[0], a[1], a[2]};
    t1[0] = t1[1] = t1[2] = 0.0;
    cross_add(ad, e, 1.0, t1);
    n = sqrt(dcloth_dot3(t1, t1));
    for (int q = 0; q < 3; q++) t1[q] /= n;
    t2[0] = t2[1] = t2[2] = 0.0;
    cross_add(ad, t1, 1.0, t2);
}

/* The constraints body b's joints to anything not turned with it put on
 * the turn (a ball keeps its anchor, a hinge its anchor and axis, a slider
 * its axis's translation; any other joint holds the body: docs/contacts.md) */
static void joint_rows(dBodyID b, dBodyID *bs, int nb, const double ref[3], double len, double A[6][6])
{
    for (int k = 0; k < dBodyGetNumJoints(b); k++) {
        dJointID j = dBodyGetJoint(b, k);
        if (!dJointIsEnabled(j)) continue;
        dBodyID o = dJointGetBody(j, 0) == b ? dJointGetBody(j, 1) : dJointGetBody(j, 0);
        int turned = 0;
        for (int q = 0; q < nb; q++) turned |= o && bs[q] == o;
        if (turned) continue; /* moves with it */
        dVector3 a, ax;
        double t1[3], t2[3], e[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        switch (dJointGetType(j)) {
        case dJointTypeBall:
            dJointGetBallAnchor(j, a);
            keep_point(A, a, ref, len);
            break;
        case dJointTypeHinge:
            dJointGetHingeAnchor(j, a);
            dJointGetHingeAxis(j, ax);
            keep_point(A, a, ref, len);
            perpendicular(ax, t1, t2);
            keep_dir(A, t1, 1, len);
            keep_dir(A, t2, 1, len);
            break;
        case dJointTypeSlider:
            dJointGetSliderAxis(j, ax);
            perpendicular(ax, t1, t2);
            for (int q = 0; q < 3; q++) keep_dir(A, e[q], 1, len);
            keep_dir(A, t1, 0, len);
            keep_dir(A, t2, 0, len);
            break;
        default:
            for (int q = 0; q < 3; q++) {
                keep_dir(A, e[q], 0, len);
                keep_dir(A, e[q], 1, len);
            }
        }
    }
}

/* The cloth's constraints held by no moving body (the world, static or
 * kinematic geoms) on the turn: a pin keeps its point, a plane its normal
 * velocity there, a line its velocity across its direction */
static void world_rows(dClothID c, const double ref[3], double len, double A[6][6])
{
    const double *x = cloth_positions(c->core);
    for (int i = 0; i < c->n; i++) {
        cloth_constraint k;
        if (mover(c, i) || cloth_get_constraint(c->core, i, &k) != CLOTH_OK || k.ndof == 0) continue;
        double t1[3], t2[3];
        dReal a[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]}, ax[3] = {k.axis[0], k.axis[1], k.axis[2]};
        if (k.ndof == 3) {
            keep_point(A, a, ref, len);
        } else if (k.ndof == 1) {
            keep_along(A, a, k.axis, ref, len);
        } else {
            perpendicular(ax, t1, t2);
            keep_along(A, a, t1, ref, len);
            keep_along(A, a, t2, ref, len);
        }
    }
}

/* The turns allowed: an orthonormal basis N (columns) of the null space of
 * the constraints accumulated in A (destroyed); their number */
static int allowed(double A[6][6], double N[6][6])
{
    double d[6], V[6][6], amax = 0.0;
    dcloth_eigen6(A, d, V);
    for (int k = 0; k < 6; k++) amax = fmax(amax, d[k]);
    int r = 0;
    for (int k = 0; k < 6; k++)
        if (!(d[k] > 1e-9 * amax) || amax == 0.0) {
            for (int i = 0; i < 6; i++) N[i][r] = V[i][k];
            r++;
        }
    return r;
}

int dcloth_turn(dClothID c, const double dL[3], double done[3])
{
    const double *x = cloth_positions(c->core), *m = cloth_masses(c->core);
    dBodyID *bs = c->turn.bodies;
    double *dv = c->turn.dv;
    done[0] = done[1] = done[2] = 0.0;
    int nb = 0;
    double ref[3] = {0.0, 0.0, 0.0}, mt = 0.0, L = 0.0;
    for (int i = 0; i < c->n; i++) {
        dBodyID b = mover(c, i);
        int k = 0;
        while (k < nb && bs[k] != b) k++;
        if (b && k == nb) bs[nb++] = b;
        mt += m[i];
        for (int q = 0; q < 3; q++) ref[q] += m[i] * x[3 * i + q];
    }
    for (int q = 0; q < 3; q++) ref[q] /= mt;
    for (int i = 0; i < c->n; i++)
        for (int q = 0; q < 3; q++) L += m[i] * (x[3 * i + q] - ref[q]) * (x[3 * i + q] - ref[q]);
    L = L > 0.0 ? sqrt(L / mt) : 1.0; /* the radius of gyration scales turns to velocities */
    /* within the turns N z the joints allow, H z = N^T e: H = N^T G N, G y
     * the momenta of the rigid change y (symmetric positive semidefinite);
     * N^T (P, L) is what the joints conserve (L about a ball's anchor...) */
    double A[6][6] = {{0}}, N[6][6], H[6][6] = {{0}}, d[6], V[6][6], z[6] = {0}, y[6] = {0}, dmax = 0.0;
    double e[6] = {0.0, 0.0, 0.0, dL[0] / L, dL[1] / L, dL[2] / L}, Ne[6] = {0};
    for (int k = 0; k < nb; k++) joint_rows(bs[k], bs, nb, ref, L, A);
    world_rows(c, ref, L, A);
    int na = allowed(A, N);
    if (na == 0) { /* the world holds every rigid motion: it takes the leftover */
        for (int q = 0; q < 3; q++) done[q] = dL[q];
        return 0;
    }
    for (int j = 0; j < na; j++) {
        double yj[6], col[6];
        for (int i = 0; i < 6; i++) yj[i] = N[i][j];
        turn_momenta(c, bs, nb, ref, yj, L, col);
        for (int a = 0; a < na; a++)
            for (int i = 0; i < 6; i++) H[a][j] += N[i][a] * col[i];
    }
    for (int a = 0; a < na; a++)
        for (int i = 0; i < 6; i++) Ne[a] += N[i][a] * e[i];
    for (int i = 0; i < 6; i++)
        for (int j = i + 1; j < 6; j++) H[i][j] = H[j][i] = 0.5 * (H[i][j] + H[j][i]);
    double H0[6][6];
    memcpy(H0, H, sizeof H);
    dcloth_eigen6(H, d, V);
    for (int k = 0; k < 6; k++) dmax = fmax(dmax, d[k]);
    for (int k = 0; k < 6; k++) { /* within the directions the free parts can take */
        if (!(d[k] > 1e-9 * dmax)) continue;
        double s = 0.0;
        for (int i = 0; i < 6; i++) s += V[i][k] * Ne[i];
        for (int i = 0; i < 6; i++) z[i] += s / d[k] * V[i][k];
    }
    for (int i = 0; i < 6; i++)
        for (int a = 0; a < na; a++) y[i] += N[i][a] * z[a];
    /* what the joints conserve and the turn did not reach, as a couple */
    double miss[6] = {0};
    for (int a = 0; a < na; a++) {
        double ra = Ne[a];
        for (int b2 = 0; b2 < na; b2++) ra -= H0[a][b2] * z[b2];
        for (int i = 0; i < 6; i++) miss[i] += N[i][a] * ra;
    }
    for (int i = 0; i < c->n; i++) {
        double r[3] = {x[3 * i] - ref[0], x[3 * i + 1] - ref[1], x[3 * i + 2] - ref[2]};
        rigid(y, r, L, dv + 3 * i);
    }
    int ok = 1;
    for (int k = 0; k < nb; k++) ok = ok && dcloth_touch(c, bs[k]) == 0; /* undoable, or not done */
    ok = ok && cloth_add_velocities(c->core, dv) == CLOTH_OK;
    for (int k = 0; ok && k < nb; k++) {
        const dReal *cb = dBodyGetPosition(bs[k]), *lv = dBodyGetLinearVel(bs[k]), *av = dBodyGetAngularVel(bs[k]);
        double r[3] = {cb[0] - ref[0], cb[1] - ref[1], cb[2] - ref[2]}, v[3];
        rigid(y, r, L, v);
        dBodySetLinearVel(bs[k], lv[0] + v[0], lv[1] + v[1], lv[2] + v[2]);
        dBodySetAngularVel(bs[k], av[0] + y[3] / L, av[1] + y[4] / L, av[2] + y[5] / L);
    }
    if (ok)
        for (int q = 0; q < 3; q++) done[q] = dL[q] - L * miss[3 + q];
    return ok ? 0 : -1;
}
