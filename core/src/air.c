/* Air drag on the grid's triangles (cloth_set_air): a linear drag against
 * each triangle's velocity relative to a uniform wind, a third on each of
 * its vertices, with its velocity Jacobian for the implicit steps. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"
#include "mat3.h"

static int tri_count(const cloth *c) { return 2 * (c->rows - 1) * (c->cols - 1); }

/* Triangle t's vertices: cell t / 2 split along its (r, k)-(r + 1, k + 1)
 * diagonal, counter-clockwise seen from axis_u x axis_v, as the plugin's
 * dClothGetTriangles lists them. */
static void tri_vertices(const cloth *c, int t, int p[3])
{
    int C = c->cols, cell = t / 2, a = (cell / (C - 1)) * C + cell % (C - 1), d = a + C + 1;
    p[0] = a;
    p[1] = t % 2 ? d : a + 1;
    p[2] = t % 2 ? a + C : d;
}

/* a triangle's vertex pairs; air_blk holds blocks (i, j), (j, i) of each */
static const int pair[3][2] = {{0, 1}, {0, 2}, {1, 2}};

int oc_air_on(const cloth *c) { return c->air.drag_normal > 0.0 || c->air.drag_tangent > 0.0; }

int oc_air_blocks(cloth *c)
{
    int nt = tri_count(c);
    c->air_blk = malloc(6 * (size_t)nt * sizeof *c->air_blk);
    if (!c->air_blk) return -1;
    for (int t = 0; t < nt; t++) {
        int p[3], *b = c->air_blk + 6 * (size_t)t;
        tri_vertices(c, t, p);
        for (int k = 0; k < 3; k++) {
            int i = p[pair[k][0]], j = p[pair[k][1]];
            b[2 * k] = oc_bsr_find(&c->A, i, j);
            b[2 * k + 1] = oc_bsr_find(&c->A, j, i);
            if (b[2 * k] < 0 || b[2 * k + 1] < 0) return -1; /* every triangle edge is a link */
        }
    }
    return 0;
}

/* Triangle p's area and unit normal at xf + hf vf (vf NULL: at xf); 0 if
 * degenerate. */
static double tri_frame(const double *xf, const double *vf, double hf, const int p[3], double n[3])
{
    double y[3][3], e1[3], e2[3];
    for (int a = 0; a < 3; a++)
        for (int q = 0; q < 3; q++) y[a][q] = xf[3 * p[a] + q] + (vf ? hf * vf[3 * p[a] + q] : 0.0);
    for (int q = 0; q < 3; q++) {
        e1[q] = y[1][q] - y[0][q];
        e2[q] = y[2][q] - y[0][q];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0.0) || !isfinite(len)) return 0.0;
    for (int q = 0; q < 3; q++) n[q] /= len;
    return 0.5 * len;
}

/* A += w D on the triangle's nine blocks; D = c_t I + (c_n - c_t) n n^T
 * with each n_q n_s formed first, so every block is bitwise symmetric. */
static void add_blocks(const cloth *c, bsr *A, const int p[3], const int *blk, const double n[3], double w)
{
    double cn = c->air.drag_normal, ct = c->air.drag_tangent, B[9];
    for (int q = 0; q < 3; q++)
        for (int s = 0; s < 3; s++) {
            double nn = n[q] * n[s];
            B[3 * q + s] = w * ((cn - ct) * nn + (q == s ? ct : 0.0));
        }
    for (int a = 0; a < 3; a++) mat3_axpy(A->val + 9 * (size_t)A->diag[p[a]], B, 1.0);
    for (int k = 0; k < 6; k++) mat3_axpy(A->val + 9 * (size_t)blk[k], B, 1.0);
}

/* Triangle k's vertices p, area and unit normal n (frame at xf + hf vf), its
 * velocity r relative to the wind and drag density Dr = D r, whose force is
 * -area Dr; area 0 if degenerate. */
static double tri_drag(const cloth *c, const double *xf, const double *vf, double hf, const double *v, int k, int p[3],
                       double n[3], double r[3], double Dr[3])
{
    const double *w = c->air.wind;
    double cn = c->air.drag_normal, ct = c->air.drag_tangent;
    tri_vertices(c, k, p);
    double area = tri_frame(xf, vf, hf, p, n);
    if (area == 0.0) return 0.0;
    for (int q = 0; q < 3; q++) r[q] = (v[3 * p[0] + q] + v[3 * p[1] + q] + v[3 * p[2] + q]) / 3.0 - w[q];
    double rn = r[0] * n[0] + r[1] * n[1] + r[2] * n[2];
    for (int q = 0; q < 3; q++) Dr[q] = ct * r[q] + (cn - ct) * rn * n[q];
    return area;
}

double oc_air_eval(const cloth *c, const double *xf, const double *vf, double hf, const double *v, double s, double *f,
                   bsr *A, double t)
{
    double P = 0.0;
    int nt = tri_count(c);
    for (int k = 0; k < nt; k++) {
        int p[3];
        double n[3], r[3], Dr[3];
        double area = tri_drag(c, xf, vf, hf, v, k, p, n, r, Dr);
        if (area == 0.0) continue;
        P += 0.5 * area * (r[0] * Dr[0] + r[1] * Dr[1] + r[2] * Dr[2]);
        if (f)
            for (int a = 0; a < 3; a++)
                for (int q = 0; q < 3; q++) f[3 * p[a] + q] -= s * area / 3.0 * Dr[q];
        if (A) add_blocks(c, A, p, c->air_blk + 6 * (size_t)k, n, t * area / 9.0);
    }
    return P;
}

void oc_air_step_force(const cloth *c, double h, double out[3], double tq[3])
{
    const cloth_solver *sv = &c->desc.solver;
    const double *x0 = c->st.x, *v0 = c->st.v;
    int implicit = sv->method == CLOTH_BACKWARD_EULER || sv->method == CLOTH_BDF2;
    /* Newton's frame at x0 + h v0 (potential.c), the linearized step's at x0,
     * both at v_new; the explicit steppers' at x0 with v0 */
    int newton = implicit && sv->nonlinear == CLOTH_NEWTON;
    const double *v = implicit ? c->v_new : v0;
    out[0] = out[1] = out[2] = 0.0;
    tq[0] = tq[1] = tq[2] = 0.0;
    if (!oc_air_on(c)) return;
    for (int k = 0, nt = tri_count(c); k < nt; k++) {
        int p[3];
        double n[3], r[3], Dr[3];
        double area = tri_drag(c, x0, newton ? v0 : NULL, newton ? h : 0.0, v, k, p, n, r, Dr);
        if (area == 0.0) continue;
        for (int q = 0; q < 3; q++) out[q] -= area * Dr[q];
        /* its torque about the origin with each third at its vertex's end-of-step position */
        for (int a = 0; a < 3; a++) {
            const double *y = c->x_new + 3 * (size_t)p[a];
            tq[0] -= area / 3.0 * (y[1] * Dr[2] - y[2] * Dr[1]);
            tq[1] -= area / 3.0 * (y[2] * Dr[0] - y[0] * Dr[2]);
            tq[2] -= area / 3.0 * (y[0] * Dr[1] - y[1] * Dr[0]);
        }
    }
}

cloth_status cloth_air_force(const cloth *c, double f[3])
{
    if (!c) return CLOTH_EINVAL;
    if (!f) return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_air_force: f is NULL");
    memcpy(f, c->air_force, sizeof c->air_force);
    return CLOTH_OK;
}

cloth_status cloth_air_torque(const cloth *c, double t[3])
{
    if (!c) return CLOTH_EINVAL;
    if (!t) return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_air_torque: t is NULL");
    memcpy(t, c->air_torque, sizeof c->air_torque);
    return CLOTH_OK;
}

cloth_status cloth_set_air(cloth *c, const cloth_air *air)
{
    if (!c) return CLOTH_EINVAL;
    if (!air) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_air: air is NULL");
    if (!finite3(air->wind))
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_air: wind (%g, %g, %g) m/s must be finite", air->wind[0],
                             air->wind[1], air->wind[2]);
    const struct {
        const char *name;
        double v;
    } drag[] = {{"drag_normal", air->drag_normal}, {"drag_tangent", air->drag_tangent}};
    for (int k = 0; k < 2; k++)
        if (!(drag[k].v >= 0.0) || !isfinite(drag[k].v))
            return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_air: %s %g N s/m^3 must be finite and >= 0", drag[k].name,
                                 drag[k].v);
    c->air = *air;
    return CLOTH_OK;
}

cloth_air cloth_get_air(const cloth *c)
{
    cloth_air none = {{0.0, 0.0, 0.0}, 0.0, 0.0};
    return c ? c->air : none;
}
