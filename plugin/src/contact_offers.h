/* A vertex's contact in this step, offered surface by surface (contact_offers.c). */
#ifndef ODECLOTH_CONTACT_OFFERS_H
#define ODECLOTH_CONTACT_OFFERS_H

#include "dcloth_internal.h"

/* vc becomes a contact with geom sf->g (of body, 0 if static): the surface's outward normal and nearest
 * point, and the gap from the shell */
void dcloth_set_contact(vcontact *vc, const struct dcloth_surf *sf, dBodyID body, const double nrm[3],
                        const double point[3], double gap);
/* before contact (g, body, n, gap at point) is offered to vertex contact vc (kept if deeper), note it, or
 * vc's present contact if it is to be replaced, as vc's opposite when the two geoms differ and their
 * normals oppose (DCLOTH_PINCH_COS) */
void dcloth_offer_opposite(vcontact *vc, dGeomID g, dBodyID body, const double n[3], double gap, const double point[3]);
/* a contact vc does not keep, offered as its second surface: kept if g is static or kinematic (vc's own
 * geom too: an edge's plane), the normals neither oppose (the pinch's) nor lie within DCLOTH_SECOND_COS
 * (their line ill-posed), deepest so far */
void dcloth_offer_second(vcontact *vc, dGeomID g, double t, dBodyID body, const double n[3], const double point[3],
                         double gap);
/* whether a surface of body with normal n may be vc's second (as dcloth_offer_second decides) */
int dcloth_second_fits(const vcontact *vc, dBodyID body, const double n[3]);
/* after all the tests: drop each second that no longer fits the contact they left */
void dcloth_drop_unfit_seconds(dClothID c);
/* then: a vertex with no second keeps its opposite there (a static or kinematic geom's), so the Newton
 * step holds it against the surface squeezing it from the other side too, not only against its own */
void dcloth_opposites_as_seconds(dClothID c, double h);
/* how far (m, along vc's normal) vc's target for a step of h seconds lies from entering its opposite's
 * surface: below 0 it is pinched (contact_rule aims midway); infinite where no opposite faces it */
double dcloth_pinch_room(const vcontact *vc, double h);

#endif
