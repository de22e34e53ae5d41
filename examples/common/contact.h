/* Contact darkening: the floor under and just around a cloth darkened by
 * how close the cloth is to it, so a cloth lying on the floor reads as
 * lying on it. Internal to the renderer (render.c); OpenGL builds only. */
#ifndef ODECLOTH_EXAMPLES_CONTACT_H
#define ODECLOTH_EXAMPLES_CONTACT_H

#include "draw.h"

#ifdef DEMO_HAVE_GL
/* Weight of the darkening at a cloth point h m above a plane: 1 - what the
 * colour beneath is scaled by, largest in contact, fading with h. */
double contact_shade_weight(double h);
/* Darken every plane of space (hidden ones left out) under the meshes:
 * their footprint and a soft rim around it. Drawn after the scene, into
 * its depth buffer: what stands in front stays as it is. */
void contact_shade(dSpaceID space, const draw_mesh *m, int n);
#endif

#endif
