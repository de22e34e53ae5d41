/* A shadow map for one directional light in fixed-function OpenGL 1.4
 * (depth textures, ARB_shadow compare, eye-linear texgen): what OSMesa's
 * GL 2.1 and any desktop libGL give. Internal to the renderer (render.c). */
#ifndef ODECLOTH_EXAMPLES_SHADOW_H
#define ODECLOTH_EXAMPLES_SHADOW_H

#include "draw.h"

#ifdef DEMO_HAVE_GL
typedef struct shadow_map {
    GLuint tex;
    int size;           /* texels a side                                    */
    double plane[4][4]; /* world (x, y, z, 1) -> texture (s, t, r, q)       */
} shadow_map;

/* Start the depth pass seen from the light (to_light: the direction toward
 * it) over the box lo..hi, in a size x size corner of the framebuffer.
 * The caller then draws the casters. -1 if the box is empty. */
int shadow_begin(shadow_map *sm, const double to_light[3], const double lo[3], const double hi[3], int size);
/* End it: the depth buffer into the map's texture, colour writes back on. */
void shadow_end(shadow_map *sm);
/* Texture unit 0 looks the map up: 1 where the light reaches a fragment,
 * 0 in shadow, filtered at edges. Call with the camera's view matrix
 * loaded (eye-linear planes are fixed in the world then). */
void shadow_bind(const shadow_map *sm);
void shadow_unbind(void);
void shadow_free(shadow_map *sm);
#endif

#endif
