/* What the renderer's passes draw (draw.c): the geoms of an ODE space and
 * the cloths' display meshes, in the current OpenGL context. Internal to
 * examples/common (render.c, shadow.c); only in builds with OpenGL. */
#ifndef ODECLOTH_EXAMPLES_DRAW_H
#define ODECLOTH_EXAMPLES_DRAW_H

#include "demo.h"

/* OpenGL comes from OSMesa (offscreen pictures) or from the system's libGL
 * next to GLFW (the --view window, view.c). */
#if defined(ODECLOTH_HAVE_OSMESA) || defined(ODECLOTH_HAVE_GLFW)
#define DEMO_HAVE_GL 1
#endif

#ifdef DEMO_HAVE_GL
#include <math.h>
#include <GL/gl.h>

static inline double draw_dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static inline void draw_cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static inline void draw_normalize3(double *a)
{
    double n = sqrt(draw_dot3(a, a));
    if (n > 0.0)
        for (int k = 0; k < 3; k++) a[k] /= n;
}

/* A cloth's display mesh: its grid refined `smooth` times (draw.c says
 * how), R x C points and a normal at each. */
typedef struct draw_mesh {
    double *x, *n;
    int R, C;
} draw_mesh;

/* Build m from the cloth as it is now; 0, or -1 on no memory (m empty). */
int draw_mesh_build(draw_mesh *m, dClothID c, int smooth);
void draw_mesh_free(draw_mesh *m);
/* Both faces lit, each in its own colour. */
void draw_mesh_triangles(const draw_mesh *m);
/* Every geom of space (spaces recursed into, hidden ones left out); planes
 * too unless casters_only. The floor's tiles centre on cam's target. */
void draw_geoms(dSpaceID space, const demo_camera *cam, int casters_only);
/* Grow lo..hi by the meshes' points and the geoms' boxes (planes and
 * hidden geoms left out). */
void draw_bounds(dSpaceID space, const draw_mesh *m, int n, double lo[3], double hi[3]);
/* Load the view matrix of a camera at eye looking at target, z up. */
void draw_look_at(const double eye[3], const double target[3]);

#endif
#endif
