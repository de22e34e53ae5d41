/* A vertex's contact in this step (vcontact), offered surface by surface:
 * the deepest is kept, the one it replaces or one facing it noted as its
 * second surface or its opposite. Every contact test offers through these. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "dcloth_internal.h"
#include "body_motion.h"
#include "contact_offers.h"

static int plane_finite(const double *n, const double *p, double gap)
{
    return isfinite(n[0] + n[1] + n[2] + p[0] + p[1] + p[2] + gap);
}

void dcloth_offer_opposite(vcontact *vc, dGeomID g, dBodyID body, const double n[3], double gap, const double point[3])
{
    if (!vc->geom || vc->geom == g || dcloth_dot3(vc->normal, n) > -DCLOTH_PINCH_COS) return;
    if (gap < vc->gap) { /* the candidate replaces vc's contact, which becomes the opposite */
        if (vc->opp_geom && vc->opp_gap <= vc->gap && vc->opp_geom != g) return;
        vc->opp_geom = vc->geom;
        vc->opp_body = vc->body;
        vc->opp_gap = vc->gap;
        memcpy(vc->opp_normal, vc->normal, sizeof vc->opp_normal);
        memcpy(vc->opp_vbody, vc->vbody, sizeof vc->opp_vbody);
        return;
    }
    if (vc->opp_geom && vc->opp_gap <= gap) return;
    vc->opp_geom = g;
    vc->opp_body = body;
    vc->opp_gap = gap;
    memcpy(vc->opp_normal, n, sizeof vc->opp_normal);
    dcloth_point_velocity(body, point, vc->opp_vbody);
}

/* whether a surface of a static or kinematic body with normal n may be vc's second */
int dcloth_second_fits(const vcontact *vc, dBodyID body, const double n[3])
{
    double nn = dcloth_dot3(vc->normal, n);
    return vc->geom && (!body || dBodyIsKinematic(body)) && nn > -DCLOTH_PINCH_COS && nn < DCLOTH_SECOND_COS;
}

void dcloth_offer_second(vcontact *vc, dGeomID g, double t, dBodyID body, const double n[3], const double point[3],
                         double gap)
{
    if (!dcloth_second_fits(vc, body, n) || (vc->sec_geom && vc->sec_gap <= gap) || !plane_finite(n, point, gap))
        return;
    vc->sec_geom = g;
    vc->sec_body = body;
    vc->sec_thickness = t;
    vc->sec_gap = gap;
    memcpy(vc->sec_normal, n, sizeof vc->sec_normal);
    memcpy(vc->sec_point, point, sizeof vc->sec_point);
    dcloth_point_velocity(body, point, vc->sec_vbody);
}

/* vc becomes a contact with geom g (surface sf, of body, 0 if static): the
 * surface's outward normal and nearest point, and the gap from the shell */
void dcloth_set_contact(vcontact *vc, const struct dcloth_surf *sf, dBodyID body, const double nrm[3],
                        const double point[3], double gap)
{
    vc->geom = sf->g;
    vc->thickness = sf->thickness;
    vc->mu = sf->mu;
    vc->body = body;
    memcpy(vc->normal, nrm, sizeof vc->normal);
    memcpy(vc->point, point, sizeof vc->point);
    vc->gap = gap;
    vc->weight = 1.0;
    dcloth_point_velocity(body, point, vc->vbody); /* zero for a static geom (it replaced a moving one's: stale) */
}

void dcloth_drop_unfit_seconds(dClothID c)
{
    /* a second that no longer fits the contact the tests left */
    for (int i = 0; i < c->n; i++) {
        vcontact *vc = &c->vc_new[i];
        if (vc->sec_geom && !dcloth_second_fits(vc, vc->sec_body, vc->sec_normal)) vc->sec_geom = 0;
    }
}

/* the thickness of candidate geom g this step (the cloth's if g is no candidate) */
static double surf_thickness(dClothID c, dGeomID g)
{
    for (int a = 0; a < c->broad.ncand; a++)
        if (c->broad.surf[a].g == g) return c->broad.surf[a].thickness;
    return c->thickness;
}

double dcloth_pinch_room(const vcontact *vc, double h)
{
    const double *n = vc->normal;
    double nn = dcloth_dot3(n, vc->opp_normal);
    if (!vc->opp_geom || vc->opp_geom == vc->geom || !(nn < -DCLOTH_PINCH_COS)) return INFINITY;
    double d1 = h * dcloth_dot3(vc->vbody, n) - vc->gap;
    return (h * dcloth_dot3(vc->opp_vbody, vc->opp_normal) - vc->opp_gap) / nn - d1;
}

void dcloth_opposites_as_seconds(dClothID c, double h)
{
    const double *x = cloth_positions(c->core);
    for (int i = 0; i < c->n; i++) {
        vcontact *vc = &c->vc_new[i];
        dBodyID b = vc->opp_body;
        /* none where the pinch rule aims midway (room < 0) or no opposite faces the contact (infinite) */
        double room = dcloth_pinch_room(vc, h);
        if (!vc->geom || !(room >= 0.0 && isfinite(room)) || (b && !dBodyIsKinematic(b))) continue;
        if (vc->sec_geom && vc->sec_gap <= vc->opp_gap) continue; /* a deeper second is kept */
        double t = surf_thickness(c, vc->opp_geom), point[3];
        for (int r = 0; r < 3; r++) point[r] = x[3 * i + r] - (vc->opp_gap + t) * vc->opp_normal[r];
        if (!plane_finite(vc->opp_normal, point, vc->opp_gap)) continue;
        vc->sec_geom = vc->opp_geom;
        vc->sec_body = b;
        vc->sec_thickness = t;
        vc->sec_gap = vc->opp_gap;
        memcpy(vc->sec_normal, vc->opp_normal, sizeof vc->sec_normal);
        memcpy(vc->sec_point, point, sizeof vc->sec_point);
        memcpy(vc->sec_vbody, vc->opp_vbody, sizeof vc->sec_vbody);
    }
}
