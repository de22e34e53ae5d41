/* The scene's geometry in OpenGL's fixed-function pipeline (draw.h): the
 * geoms flat-coloured (a geom's data, when set, is read as a `const
 * float[3]` colour: a demo convention) and the cloths smooth-shaded.
 *
 * A cloth is drawn from its grid, optionally subdivided for display by the
 * four-point interpolating scheme (Dyn, Levin, Gregory) applied along rows
 * and then columns, so the simulated vertices stay where they are and only
 * in-between points are added. Both faces are lit (GL_LIGHT_MODEL_TWO_SIDE),
 * each in its own colour: the face seen from axis_u x axis_v ("top" of the
 * cloth as created) warm, the other cool. */
#include <stdlib.h>
#include <string.h>
#include "draw.h"

#ifdef DEMO_HAVE_GL

/* ---------------------------------------------------------------- helpers */

static void sub3(const double *a, const double *b, double *o)
{
    for (int k = 0; k < 3; k++) o[k] = a[k] - b[k];
}

void draw_look_at(const double eye[3], const double target[3])
{
    double f[3], s[3], u[3], up[3] = {0, 0, 1};
    sub3(target, eye, f);
    draw_normalize3(f);
    draw_cross3(f, up, s);
    if (draw_dot3(s, s) < 1e-12) { /* looking straight down or up */
        double y[3] = {0, 1, 0};
        draw_cross3(f, y, s);
    }
    draw_normalize3(s);
    draw_cross3(s, f, u);
    double m[16] = {s[0],
                    u[0],
                    -f[0],
                    0,
                    s[1],
                    u[1],
                    -f[1],
                    0,
                    s[2],
                    u[2],
                    -f[2],
                    0,
                    -draw_dot3(s, eye),
                    -draw_dot3(u, eye),
                    draw_dot3(f, eye),
                    1};
    glLoadMatrixd(m);
}

static void geom_transform(dGeomID g)
{
    const dReal *p = dGeomGetPosition(g), *R = dGeomGetRotation(g);
    double m[16] = {R[0], R[4], R[8], 0, R[1], R[5], R[9], 0, R[2], R[6], R[10], 0, p[0], p[1], p[2], 1};
    glMultMatrixd(m);
}

static void colour(float r, float g, float b)
{
    GLfloat c[4] = {r, g, b, 1.0f};
    glMaterialfv(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE, c);
}

/* ------------------------------------------------------------------ geoms */

static void draw_box(const dReal *L)
{
    double h[3] = {L[0] / 2, L[1] / 2, L[2] / 2};
    static const int faces[6][4] = {{1, 3, 7, 5}, {0, 4, 6, 2}, {2, 6, 7, 3}, {0, 1, 5, 4}, {4, 5, 7, 6}, {0, 2, 3, 1}};
    static const double normals[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    glBegin(GL_QUADS);
    for (int f = 0; f < 6; f++) {
        glNormal3dv(normals[f]);
        for (int k = 0; k < 4; k++) {
            int v = faces[f][k];
            glVertex3d(v & 1 ? h[0] : -h[0], v & 2 ? h[1] : -h[1], v & 4 ? h[2] : -h[2]);
        }
    }
    glEnd();
}

/* A band of a surface of revolution about z: radius r(t) and height z(t)
 * for t in [0, 1], n segments along t, 48 around. */
typedef void (*profile_fn)(double t, const double *par, double *r, double *z, double *nr, double *nz);

static void draw_revolution(profile_fn f, const double *par, int n)
{
    const int around = 48;
    for (int i = 0; i < n; i++) {
        double r0, z0, nr0, nz0, r1, z1, nr1, nz1;
        f((double)i / n, par, &r0, &z0, &nr0, &nz0);
        f((double)(i + 1) / n, par, &r1, &z1, &nr1, &nz1);
        glBegin(GL_QUAD_STRIP);
        for (int k = 0; k <= around; k++) {
            double a = 2 * M_PI * k / around, c = cos(a), s = sin(a);
            glNormal3d(nr1 * c, nr1 * s, nz1);
            glVertex3d(r1 * c, r1 * s, z1);
            glNormal3d(nr0 * c, nr0 * s, nz0);
            glVertex3d(r0 * c, r0 * s, z0);
        }
        glEnd();
    }
}

/* par: radius, z of the centre, from angle, to angle (from the -z pole) */
static void arc_profile(double t, const double *par, double *r, double *z, double *nr, double *nz)
{
    double th = par[2] + t * (par[3] - par[2]);
    *nr = sin(th);
    *nz = -cos(th);
    *r = par[0] * *nr;
    *z = par[1] + par[0] * *nz;
}

/* par: radius, half length */
static void side_profile(double t, const double *par, double *r, double *z, double *nr, double *nz)
{
    *r = par[0];
    *z = -par[1] + 2 * par[1] * t;
    *nr = 1;
    *nz = 0;
}

static void draw_disc(double r, double z, double nz)
{
    glBegin(GL_TRIANGLE_FAN);
    glNormal3d(0, 0, nz);
    glVertex3d(0, 0, z);
    for (int k = 0; k <= 48; k++) {
        double a = 2 * M_PI * k / 48 * nz;
        glVertex3d(r * cos(a), r * sin(a), z);
    }
    glEnd();
}

static void draw_rounded(double r, double len, int caps_round)
{
    double side[2] = {r, len / 2};
    draw_revolution(side_profile, side, 1);
    if (caps_round) {
        double lo[4] = {r, -len / 2, 0, M_PI / 2}, hi[4] = {r, len / 2, M_PI / 2, M_PI};
        draw_revolution(arc_profile, lo, 12);
        draw_revolution(arc_profile, hi, 12);
    } else {
        draw_disc(r, len / 2, 1);
        draw_disc(r, -len / 2, -1);
    }
}

static void draw_plane(dGeomID g, const demo_camera *cam)
{
    dVector4 p;
    dGeomPlaneGetParams(g, p);
    double n[3] = {p[0], p[1], p[2]}, a[3], b[3], o[3];
    draw_normalize3(n);
    double t[3] = {fabs(n[0]) < 0.9 ? 1 : 0, fabs(n[0]) < 0.9 ? 0 : 1, 0};
    draw_cross3(n, t, a);
    draw_normalize3(a);
    draw_cross3(n, a, b);
    /* tiles around the camera target's foot on the plane */
    double off = draw_dot3(cam->target, n) - p[3];
    for (int k = 0; k < 3; k++) o[k] = cam->target[k] - off * n[k];
    double ca = floor(draw_dot3(o, a) / 0.25), cb = floor(draw_dot3(o, b) / 0.25);
    const int half = 24;
    glBegin(GL_QUADS);
    glNormal3dv(n);
    for (int i = -half; i < half; i++)
        for (int j = -half; j < half; j++) {
            float shade = ((i + j) & 1) ? 0.80f : 0.72f;
            colour(shade, shade, shade * 0.97f);
            double u0 = (ca + i) * 0.25, v0 = (cb + j) * 0.25;
            double q[4][2] = {{u0, v0}, {u0 + 0.25, v0}, {u0 + 0.25, v0 + 0.25}, {u0, v0 + 0.25}};
            for (int k = 0; k < 4; k++) {
                double x[3];
                for (int c = 0; c < 3; c++) x[c] = p[3] * n[c] + q[k][0] * a[c] + q[k][1] * b[c];
                glVertex3dv(x);
            }
        }
    glEnd();
}

static void draw_trimesh(dGeomID g)
{
    int n = dGeomTriMeshGetTriangleCount(g);
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < n; i++) {
        dVector3 v[3];
        dGeomTriMeshGetTriangle(g, i, &v[0], &v[1], &v[2]);
        double e1[3], e2[3], nn[3], a[3], b[3], c[3];
        for (int k = 0; k < 3; k++) {
            a[k] = v[0][k];
            b[k] = v[1][k];
            c[k] = v[2][k];
        }
        sub3(b, a, e1);
        sub3(c, a, e2);
        draw_cross3(e1, e2, nn);
        draw_normalize3(nn);
        glNormal3dv(nn);
        glVertex3dv(a);
        glVertex3dv(b);
        glVertex3dv(c);
    }
    glEnd();
}

static void draw_geom(dGeomID g, const demo_camera *cam, int casters_only)
{
    if (dGeomIsSpace(g)) {
        draw_geoms((dSpaceID)g, cam, casters_only);
        return;
    }
    int cls = dGeomGetClass(g);
    const float *rgb = dGeomGetData(g);
    if (rgb == demo_geom_hidden || (casters_only && cls == dPlaneClass)) return;
    static const float grey[3] = {0.62f, 0.62f, 0.66f};
    if (!rgb) rgb = grey;
    colour(rgb[0], rgb[1], rgb[2]);
    if (cls == dPlaneClass) {
        draw_plane(g, cam);
        return;
    }
    if (cls == dTriMeshClass) { /* triangles come in world coordinates */
        draw_trimesh(g);
        return;
    }
    glPushMatrix();
    geom_transform(g);
    if (cls == dBoxClass) {
        dVector3 L;
        dGeomBoxGetLengths(g, L);
        draw_box(L);
    } else if (cls == dSphereClass) {
        double par[4] = {dGeomSphereGetRadius(g), 0, 0, M_PI};
        draw_revolution(arc_profile, par, 24);
    } else if (cls == dCapsuleClass) {
        dReal r, len;
        dGeomCapsuleGetParams(g, &r, &len);
        draw_rounded(r, len, 1);
    } else if (cls == dCylinderClass) {
        dReal r, len;
        dGeomCylinderGetParams(g, &r, &len);
        draw_rounded(r, len, 0);
    }
    glPopMatrix();
}

void draw_geoms(dSpaceID space, const demo_camera *cam, int casters_only)
{
    for (int i = 0; space && i < dSpaceGetNumGeoms(space); i++) draw_geom(dSpaceGetGeom(space, i), cam, casters_only);
}

static void grow(double lo[3], double hi[3], const double *p)
{
    for (int k = 0; k < 3; k++) {
        lo[k] = fmin(lo[k], p[k]);
        hi[k] = fmax(hi[k], p[k]);
    }
}

static void geom_bounds(dGeomID g, double lo[3], double hi[3])
{
    if (dGeomIsSpace(g)) {
        dSpaceID s = (dSpaceID)g;
        for (int i = 0; i < dSpaceGetNumGeoms(s); i++) geom_bounds(dSpaceGetGeom(s, i), lo, hi);
        return;
    }
    if (dGeomGetData(g) == demo_geom_hidden || dGeomGetClass(g) == dPlaneClass) return;
    dReal a[6];
    dGeomGetAABB(g, a);
    double p0[3] = {a[0], a[2], a[4]}, p1[3] = {a[1], a[3], a[5]};
    grow(lo, hi, p0);
    grow(lo, hi, p1);
}

void draw_bounds(dSpaceID space, const draw_mesh *m, int n, double lo[3], double hi[3])
{
    for (int i = 0; space && i < dSpaceGetNumGeoms(space); i++) geom_bounds(dSpaceGetGeom(space, i), lo, hi);
    for (int i = 0; i < n; i++)
        for (size_t k = 0; k < (size_t)m[i].R * (size_t)m[i].C; k++) grow(lo, hi, m[i].x + 3 * k);
}

/* ------------------------------------------------------------------ cloth */

/* One four-point refinement along one grid direction: n points with stride
 * `stride` (in points) become 2n - 1; the ends are extrapolated linearly. */
static void refine_line(const double *in, int n, double *out)
{
    for (int i = 0; i < n; i++) memcpy(out + 6 * i, in + 3 * i, 3 * sizeof *out);
    for (int i = 0; i + 1 < n; i++)
        for (int k = 0; k < 3; k++) {
            double p0 = in[3 * i + k], p1 = in[3 * (i + 1) + k];
            double pm = i > 0 ? in[3 * (i - 1) + k] : 2 * p0 - p1;
            double pp = i + 2 < n ? in[3 * (i + 2) + k] : 2 * p1 - p0;
            out[3 * (2 * i + 1) + k] = (9 * (p0 + p1) - pm - pp) / 16;
        }
}

/* R x C grid -> (2R-1) x (2C-1); returns a new array (NULL on no memory). */
static double *refine_grid(const double *x, int R, int C)
{
    int R2 = 2 * R - 1, C2 = 2 * C - 1;
    int nmax = R2 > C2 ? R2 : C2;
    double *rows = malloc(3 * (size_t)R * (size_t)C2 * sizeof *rows);
    double *out = malloc(3 * (size_t)R2 * (size_t)C2 * sizeof *out);
    double *col_in = malloc(3 * (size_t)nmax * sizeof *col_in), *col_out = malloc(6 * (size_t)nmax * sizeof *col_out);
    if (!rows || !out || !col_in || !col_out) {
        free(rows);
        free(out);
        free(col_in);
        free(col_out);
        return NULL;
    }
    for (int r = 0; r < R; r++) refine_line(x + 3 * (size_t)r * C, C, rows + 3 * (size_t)r * C2);
    for (int c = 0; c < C2; c++) {
        for (int r = 0; r < R; r++) memcpy(col_in + 3 * r, rows + 3 * ((size_t)r * C2 + c), 3 * sizeof *col_in);
        refine_line(col_in, R, col_out);
        for (int r = 0; r < R2; r++) memcpy(out + 3 * ((size_t)r * C2 + c), col_out + 3 * r, 3 * sizeof *out);
    }
    free(rows);
    free(col_in);
    free(col_out);
    return out;
}

static void grid_normal(const double *x, int R, int C, int r, int c, double *n)
{
    double du[3], dv[3];
    int c0 = c > 0 ? c - 1 : c, c1 = c + 1 < C ? c + 1 : c;
    int r0 = r > 0 ? r - 1 : r, r1 = r + 1 < R ? r + 1 : r;
    sub3(x + 3 * ((size_t)r * C + c1), x + 3 * ((size_t)r * C + c0), du);
    sub3(x + 3 * ((size_t)r1 * C + c), x + 3 * ((size_t)r0 * C + c), dv);
    draw_cross3(du, dv, n);
    draw_normalize3(n);
}

void draw_mesh_free(draw_mesh *m)
{
    free(m->x);
    free(m->n);
    m->x = m->n = NULL;
    m->R = m->C = 0;
}

int draw_mesh_build(draw_mesh *m, dClothID cl, int smooth)
{
    const cloth *core = dClothGetCore(cl);
    int R = cloth_rows(core), C = cloth_cols(core);
    double *x = malloc(3 * (size_t)R * (size_t)C * sizeof *x);
    m->x = m->n = NULL;
    m->R = m->C = 0;
    if (!x) return -1;
    memcpy(x, dClothGetPositions(cl), 3 * (size_t)R * (size_t)C * sizeof *x);
    for (int l = 0; l < smooth; l++) {
        double *y = refine_grid(x, R, C);
        free(x);
        if (!y) return -1;
        x = y;
        R = 2 * R - 1;
        C = 2 * C - 1;
    }
    double *n = malloc(3 * (size_t)R * (size_t)C * sizeof *n);
    if (!n) {
        free(x);
        return -1;
    }
    for (int r = 0; r < R; r++)
        for (int c = 0; c < C; c++) grid_normal(x, R, C, r, c, n + 3 * ((size_t)r * C + c));
    *m = (draw_mesh){x, n, R, C};
    return 0;
}

void draw_mesh_triangles(const draw_mesh *m)
{
    GLfloat front[4] = {0.85f, 0.30f, 0.22f, 1}, back[4] = {0.25f, 0.45f, 0.80f, 1};
    glMaterialfv(GL_FRONT, GL_AMBIENT_AND_DIFFUSE, front);
    glMaterialfv(GL_BACK, GL_AMBIENT_AND_DIFFUSE, back);
    for (int r = 0; r + 1 < m->R; r++) {
        glBegin(GL_TRIANGLE_STRIP);
        for (int c = 0; c < m->C; c++)
            for (int k = 1; k >= 0; k--) {
                size_t i = (size_t)(r + k) * m->C + c;
                glNormal3dv(m->n + 3 * i);
                glVertex3dv(m->x + 3 * i);
            }
        glEnd();
    }
}

#endif /* DEMO_HAVE_GL */
