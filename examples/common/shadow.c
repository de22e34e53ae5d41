/* The shadow map (shadow.h). The light is directional, so its view is an
 * orthographic box around the casters: x and y across the light, depth
 * along it. The texture coordinates a fragment gets are its world position
 * in that box scaled to [0, 1]; r is compared with the stored depth. */
#include <string.h>
#include "shadow.h"

#ifdef DEMO_HAVE_GL

#ifndef GL_CLAMP_TO_BORDER
#define GL_CLAMP_TO_BORDER 0x812D
#endif
#ifndef GL_DEPTH_TEXTURE_MODE
#define GL_DEPTH_TEXTURE_MODE 0x884B
#endif
#ifndef GL_TEXTURE_COMPARE_MODE
#define GL_TEXTURE_COMPARE_MODE 0x884C
#endif
#ifndef GL_TEXTURE_COMPARE_FUNC
#define GL_TEXTURE_COMPARE_FUNC 0x884D
#endif
#ifndef GL_COMPARE_R_TO_TEXTURE
#define GL_COMPARE_R_TO_TEXTURE 0x884E
#endif

/* Receivers may lie this far beyond the casters' box along the light (the
 * floor under a raised body): m. */
#define SHADOW_REACH 20.0

int shadow_begin(shadow_map *sm, const double to_light[3], const double lo[3], const double hi[3], int size)
{
    memset(sm, 0, sizeof *sm);
    if (!(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]) || size < 16) return -1;
    double f[3] = {-to_light[0], -to_light[1], -to_light[2]}, s[3], u[3], up[3] = {0, 0, 1};
    draw_normalize3(f);
    draw_cross3(f, up, s);
    if (draw_dot3(s, s) < 1e-12) s[0] = 1, s[1] = s[2] = 0; /* light straight above */
    draw_normalize3(s);
    draw_cross3(s, f, u);
    /* the box's extent across the light (square, so texels are too) and along it */
    double a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY, d0 = INFINITY, d1 = -INFINITY;
    for (int c = 0; c < 8; c++) {
        double p[3] = {c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]};
        double a = draw_dot3(s, p), b = draw_dot3(u, p), d = draw_dot3(f, p);
        a0 = fmin(a0, a), a1 = fmax(a1, a), b0 = fmin(b0, b), b1 = fmax(b1, b), d0 = fmin(d0, d), d1 = fmax(d1, d);
    }
    double half = 0.52 * fmax(fmax(a1 - a0, b1 - b0), 1e-3), am = 0.5 * (a0 + a1), bm = 0.5 * (b0 + b1);
    a0 = am - half, a1 = am + half, b0 = bm - half, b1 = bm + half;
    d0 -= 0.1, d1 += SHADOW_REACH;
    double *P = sm->plane[0];
    for (int k = 0; k < 3; k++) P[k] = s[k] / (a1 - a0), P[4 + k] = u[k] / (b1 - b0), P[8 + k] = f[k] / (d1 - d0);
    P[3] = -a0 / (a1 - a0), P[7] = -b0 / (b1 - b0), P[11] = -d0 / (d1 - d0);
    P[12] = P[13] = P[14] = 0, P[15] = 1;
    sm->size = size;

    glViewport(0, 0, size, size);
    glClear(GL_DEPTH_BUFFER_BIT);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDisable(GL_LIGHTING);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glShadeModel(GL_FLAT);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(a0, a1, b0, b1, d0, d1);
    glMatrixMode(GL_MODELVIEW);
    double V[16] = {s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0, 0, 0, 0, 1};
    glLoadMatrixd(V);
    /* pushed back a little, so a lit surface does not shadow itself */
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.5f, 4.0f);
    return 0;
}

void shadow_end(shadow_map *sm)
{
    glDisable(GL_POLYGON_OFFSET_FILL);
    glGenTextures(1, &sm->tex);
    glBindTexture(GL_TEXTURE_2D, sm->tex);
    glCopyTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT, 0, 0, sm->size, sm->size, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
    GLfloat far[4] = {1, 1, 1, 1}; /* outside the map: lit */
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, far);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_R_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glTexParameteri(GL_TEXTURE_2D, GL_DEPTH_TEXTURE_MODE, GL_LUMINANCE);
    glBindTexture(GL_TEXTURE_2D, 0);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void shadow_bind(const shadow_map *sm)
{
    static const GLenum coord[4] = {GL_S, GL_T, GL_R, GL_Q};
    static const GLenum gen[4] = {GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R, GL_TEXTURE_GEN_Q};
    glBindTexture(GL_TEXTURE_2D, sm->tex);
    glEnable(GL_TEXTURE_2D);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    for (int k = 0; k < 4; k++) {
        glTexGeni(coord[k], GL_TEXTURE_GEN_MODE, GL_EYE_LINEAR);
        glTexGendv(coord[k], GL_EYE_PLANE, sm->plane[k]);
        glEnable(gen[k]);
    }
}

void shadow_unbind(void)
{
    glDisable(GL_TEXTURE_GEN_S);
    glDisable(GL_TEXTURE_GEN_T);
    glDisable(GL_TEXTURE_GEN_R);
    glDisable(GL_TEXTURE_GEN_Q);
    glDisable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, 0);
}

void shadow_free(shadow_map *sm)
{
    if (sm->tex) glDeleteTextures(1, &sm->tex);
    sm->tex = 0;
}

#endif /* DEMO_HAVE_GL */
