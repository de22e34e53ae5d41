/* The broadphase (dcloth.h, step 1): a box geom around the cloth, swept by the step's motion and grown
 * by the thickness, against the user's space via dSpaceCollide2 (category / collide bits, nested spaces
 * entered). The box is in no space, so dSpaceCollide never meets it; a geom it misses costs nothing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "dcloth_internal.h"
#include "body_motion.h"
#include "broadphase.h"

static int bits_meet(dClothID c, dGeomID g)
{
    return (c->collide & dGeomGetCategoryBits(g)) || (dGeomGetCollideBits(g) & c->category);
}

static void near_cb(void *data, dGeomID o1, dGeomID o2)
{
    dClothID c = data;
    dGeomID g = o1 == c->broad.box ? o2 : o1;
    if (g == c->broad.box || g == c->vertex.sphere) return;
    if (dGeomIsSpace(g)) {
        dSpaceCollide2(c->broad.box, g, c, near_cb);
        return;
    }
    if (!dGeomIsEnabled(g) || !bits_meet(c, g)) return;
    if (c->broad.ncand == c->broad.cand_cap) {
        int cap = c->broad.cand_cap ? 2 * c->broad.cand_cap : 16;
        dGeomID *p = realloc(c->broad.cand, (size_t)cap * sizeof *p);
        if (!p) {
            c->broad.cand_cap = -1; /* out of memory: reported by the caller */
            return;
        }
        c->broad.cand = p;
        c->broad.cand_cap = cap;
    }
    if (c->broad.cand_cap > 0) c->broad.cand[c->broad.ncand++] = g;
}

/* the fastest geom of a space (nested spaces entered), by dcloth_geom_speed. A quadtree space
 * counts nothing, since it cannot hand out its geoms (dSpaceGetGeom aborts there): its bodies are
 * found as they arrive */
static double space_speed(dSpaceID s)
{
    if (dSpaceGetClass(s) == dQuadTreeSpaceClass) return 0.0;
    double m = 0.0;
    for (int k = 0, n = dSpaceGetNumGeoms(s); k < n; k++) {
        dGeomID g = dSpaceGetGeom(s, k);
        if (!g) continue;
        double v = dGeomIsSpace(g) ? space_speed((dSpaceID)g) : dcloth_geom_speed(g);
        if (v > m) m = v;
    }
    return m;
}

int dcloth_find_candidates(dClothID c, double h, double reach)
{
    const double *x = cloth_positions(c->core), *v = cloth_velocities(c->core);
    int n = c->n;
    memset(c->vc_new, 0, (size_t)n * sizeof *c->vc_new);
    c->broad.ncand = 0;
    if (!c->space) return 0;

    /* the cloth's swept bounds */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            double a = x[3 * i + k], b = a + h * v[3 * i + k];
            lo[k] = fmin(lo[k], fmin(a, b));
            hi[k] = fmax(hi[k], fmax(a, b));
        }
    /* grown by the thickness (the largest a geom has had, dcloth_surface)
     * and what the fastest body covers in the step: a body approaching the
     * cloth is a candidate before it arrives */
    double t = fmax(c->thickness, c->surf_tmax);
    double grow = t * (1.0 + DCLOTH_CONTACT_MARGIN) + reach + h * space_speed(c->space);
    for (int k = 0; k < 3; k++) {
        lo[k] -= grow;
        hi[k] += grow;
    }
    dGeomBoxSetLengths(c->broad.box, hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    dGeomSetPosition(c->broad.box, 0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]));
    dGeomSetCategoryBits(c->broad.box, c->category);
    dGeomSetCollideBits(c->broad.box, c->collide);
    dSpaceCollide2(c->broad.box, (dGeomID)c->space, c, near_cb);
    if (c->broad.cand_cap < 0) {
        c->broad.cand_cap = 0;
        free(c->broad.cand);
        c->broad.cand = NULL;
        c->broad.ncand = 0;
        return -1;
    }
    return c->broad.ncand;
}

/* What any vertex may cover in a Newton step beyond its own start
 * velocity: h times the cloth's fastest vertex (the implicit step pulls a
 * vertex toward its neighbours' velocities); 0 for the linearised step. */
double dcloth_newton_reach(dClothID c, double h)
{
    if (cloth_get_desc(c->core).solver.nonlinear != CLOTH_NEWTON) return 0.0;
    const double *v = cloth_velocities(c->core);
    double vmax = 0.0;
    for (int i = 0; i < c->n; i++) vmax = fmax(vmax, dcloth_dot3(v + 3 * i, v + 3 * i));
    return h * sqrt(vmax);
}

/* Each candidate's surface (dcloth_surface) into c->broad.surf, asking for each
 * geom once a step. When a geom is thicker than the broadphase reached, it
 * is run again that much wider, the geoms already asked keeping their answers. */
int dcloth_find_surfaces(dClothID c, double h, double extra)
{
    int nold = 0;
    for (;;) {
        double reached = fmax(c->thickness, c->surf_tmax);
        if (dcloth_find_candidates(c, h, extra) < 0) return -1;
        if (c->broad.ncand > c->broad.surf_cap) {
            int cap = c->broad.cand_cap;
            struct dcloth_surf *p = realloc(c->broad.surf, (size_t)cap * sizeof *p);
            if (p) c->broad.surf = p;
            struct dcloth_surf *q = p ? realloc(c->broad.surf_old, (size_t)cap * sizeof *q) : NULL;
            if (q) c->broad.surf_old = q;
            if (!q) return -1;
            c->broad.surf_cap = cap;
        }
        for (int a = 0; a < c->broad.ncand; a++) {
            struct dcloth_surf *sf = &c->broad.surf[a];
            int k = 0;
            while (k < nold && c->broad.surf_old[k].g != c->broad.cand[a]) k++;
            if (k < nold) {
                *sf = c->broad.surf_old[k];
                continue;
            }
            sf->g = c->broad.cand[a];
            dcloth_surface(c, sf->g, &sf->mu, &sf->thickness);
        }
        if (!(c->surf_tmax > reached)) return c->broad.ncand;
        nold = c->broad.ncand;
        memcpy(c->broad.surf_old, c->broad.surf, (size_t)nold * sizeof *c->broad.surf_old);
    }
}
