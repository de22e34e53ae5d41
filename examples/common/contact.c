/* Contact darkening (contact.h): each cloth is projected onto each plane
 * as a black mesh whose opacity is contact_shade_weight of the height of
 * the point above, with a skirt around its boundary fading to nothing over
 * CONTACT_RIM; blended multiplicatively onto the finished picture. */
#include <stdlib.h>
#include "contact.h"

#ifdef DEMO_HAVE_GL

#define CONTACT_DARK 0.45  /* darkening where the cloth touches the plane  */
#define CONTACT_FADE 0.03  /* m: height over which it falls by e          */
#define CONTACT_RIM 0.04   /* m: the rim's width around the footprint     */
#define CONTACT_LIFT 0.001 /* m: drawn this far above the plane (over it in depth) */

double contact_shade_weight(double h) { return CONTACT_DARK * exp(-fmax(h, 0.0) / CONTACT_FADE); }

typedef struct plane {
    double n[3], d; /* n . x = d, n unit */
} plane;

/* A point's foot on the plane (lifted a little) and its weight. */
static double foot(const plane *p, const double *x, double *f)
{
    double h = draw_dot3(p->n, x) - p->d;
    for (int k = 0; k < 3; k++) f[k] = x[k] - (h - CONTACT_LIFT) * p->n[k];
    return contact_shade_weight(h);
}

static void footprint(const plane *p, const draw_mesh *m)
{
    for (int r = 0; r + 1 < m->R; r++) {
        glBegin(GL_TRIANGLE_STRIP);
        for (int c = 0; c < m->C; c++)
            for (int k = 1; k >= 0; k--) {
                double f[3], w = foot(p, m->x + 3 * ((size_t)(r + k) * m->C + c), f);
                glColor4d(0, 0, 0, w);
                glVertex3dv(f);
            }
        glEnd();
    }
}

/* Grid index of the i-th boundary point, going round (0, 0), (0, C-1),
 * (R-1, C-1), (R-1, 0); and the interior neighbour it points away from. */
static void boundary_point(const draw_mesh *m, int i, int *at, int *inner)
{
    int R = m->R, C = m->C, r, c;
    if (i < C - 1) r = 0, c = i;
    else if (i < C - 1 + R - 1) r = i - (C - 1), c = C - 1;
    else if (i < 2 * (C - 1) + R - 1) r = R - 1, c = C - 1 - (i - (C - 1) - (R - 1));
    else r = R - 1 - (i - 2 * (C - 1) - (R - 1)), c = 0;
    int ri = r == 0 ? 1 : r == R - 1 ? R - 2 : r, ci = c == 0 ? 1 : c == C - 1 ? C - 2 : c;
    *at = r * C + c;
    *inner = ri * C + ci;
}

static void rim(const plane *p, const draw_mesh *m)
{
    int nb = 2 * (m->R - 1) + 2 * (m->C - 1);
    glBegin(GL_QUAD_STRIP);
    for (int i = 0; i <= nb; i++) {
        int at, in;
        boundary_point(m, i % nb, &at, &in);
        double f[3], g[3], out[3];
        double w = foot(p, m->x + 3 * (size_t)at, f);
        foot(p, m->x + 3 * (size_t)in, g);
        for (int k = 0; k < 3; k++) out[k] = f[k] - g[k];
        draw_normalize3(out);
        glColor4d(0, 0, 0, w);
        glVertex3dv(f);
        for (int k = 0; k < 3; k++) f[k] += CONTACT_RIM * out[k];
        glColor4d(0, 0, 0, 0);
        glVertex3dv(f);
    }
    glEnd();
}

static void shade_plane(dGeomID g, const draw_mesh *m, int n)
{
    dVector4 q;
    dGeomPlaneGetParams(g, q);
    double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    if (!(len > 0.0)) return;
    plane p = {{q[0] / len, q[1] / len, q[2] / len}, q[3] / len};
    for (int i = 0; i < n; i++)
        if (m[i].R >= 3 && m[i].C >= 3) {
            footprint(&p, &m[i]);
            rim(&p, &m[i]);
        }
}

static void shade_space(dSpaceID space, const draw_mesh *m, int n)
{
    for (int i = 0; i < dSpaceGetNumGeoms(space); i++) {
        dGeomID g = dSpaceGetGeom(space, i);
        if (dGeomIsSpace(g)) shade_space((dSpaceID)g, m, n);
        else if (dGeomGetClass(g) == dPlaneClass && dGeomGetData(g) != demo_geom_hidden) shade_plane(g, m, n);
    }
}

void contact_shade(dSpaceID space, const draw_mesh *m, int n)
{
    if (!space || n <= 0) return;
    glDisable(GL_LIGHTING);
    glShadeModel(GL_SMOOTH);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    shade_space(space, m, n);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glEnable(GL_LIGHTING);
}

#endif /* DEMO_HAVE_GL */
