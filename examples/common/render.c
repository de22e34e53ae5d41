/* Pictures of a cloth scene with the fixed-function OpenGL pipeline: one
 * scene-drawing function (demo_draw_scene) used by the offscreen renderer
 * here (OSMesa, which ships a GL 2.1 compatibility context) and by the
 * --view window (view.c: GLFW's context on the system's libGL).
 *
 * The cloth is drawn smooth-shaded from its grid, optionally subdivided
 * for display by the four-point interpolating scheme (Dyn, Levin, Gregory)
 * applied along rows and then columns, so the simulated vertices stay where
 * they are and only in-between points are added. Both faces are lit
 * (GL_LIGHT_MODEL_TWO_SIDE), each in its own colour: the face seen from
 * axis_u x axis_v ("top" of the cloth as created) warm, the other cool.
 * The geoms of the space are drawn flat-coloured (a geom's data, when it is
 * set, is read as a `const float[3]` colour: a demo convention). Offscreen
 * pictures are rendered at twice the size and averaged down 2x2
 * (antialiasing). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "demo.h"

const float demo_geom_hidden[3] = {0, 0, 0};

/* The drawing needs OpenGL: from OSMesa (offscreen pictures) or from the
 * system's libGL next to GLFW (the --view window, view.c); both share it. */
#if defined(ODECLOTH_HAVE_OSMESA) || defined(ODECLOTH_HAVE_GLFW)
#define DEMO_HAVE_GL 1
#endif

#ifdef ODECLOTH_HAVE_OSMESA
#include <GL/osmesa.h>
#endif
#ifdef DEMO_HAVE_GL
#include <GL/gl.h>

/* ---------------------------------------------------------------- helpers */

static void sub3(const double *a, const double *b, double *o)
{
    for (int k = 0; k < 3; k++) o[k] = a[k] - b[k];
}

static void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void normalize3(double *a)
{
    double n = sqrt(dot3(a, a));
    if (n > 0.0)
        for (int k = 0; k < 3; k++) a[k] /= n;
}

static void look_at(const demo_camera *cam)
{
    double f[3], s[3], u[3], up[3] = {0, 0, 1};
    sub3(cam->target, cam->eye, f);
    normalize3(f);
    cross3(f, up, s);
    if (dot3(s, s) < 1e-12) { /* looking straight down or up */
        double y[3] = {0, 1, 0};
        cross3(f, y, s);
    }
    normalize3(s);
    cross3(s, f, u);
    double m[16] = {s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
                    -dot3(s, cam->eye), -dot3(u, cam->eye), dot3(f, cam->eye), 1};
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
    normalize3(n);
    double t[3] = {fabs(n[0]) < 0.9 ? 1 : 0, fabs(n[0]) < 0.9 ? 0 : 1, 0};
    cross3(n, t, a);
    normalize3(a);
    cross3(n, a, b);
    /* tiles around the camera target's foot on the plane */
    double off = dot3(cam->target, n) - p[3];
    for (int k = 0; k < 3; k++) o[k] = cam->target[k] - off * n[k];
    double ca = floor(dot3(o, a) / 0.25), cb = floor(dot3(o, b) / 0.25);
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
        cross3(e1, e2, nn);
        normalize3(nn);
        glNormal3dv(nn);
        glVertex3dv(a);
        glVertex3dv(b);
        glVertex3dv(c);
    }
    glEnd();
}

static void draw_geom(dGeomID g, const demo_camera *cam)
{
    if (dGeomIsSpace(g)) {
        dSpaceID s = (dSpaceID)g;
        for (int i = 0; i < dSpaceGetNumGeoms(s); i++) draw_geom(dSpaceGetGeom(s, i), cam);
        return;
    }
    int cls = dGeomGetClass(g);
    const float *rgb = dGeomGetData(g);
    if (rgb == demo_geom_hidden) return;
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
    cross3(du, dv, n);
    normalize3(n);
}

static int draw_cloth(dClothID cl, int smooth)
{
    const cloth *core = dClothGetCore(cl);
    int R = cloth_rows(core), C = cloth_cols(core);
    double *x = malloc(3 * (size_t)R * (size_t)C * sizeof *x);
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
    GLfloat front[4] = {0.85f, 0.30f, 0.22f, 1}, back[4] = {0.25f, 0.45f, 0.80f, 1};
    glMaterialfv(GL_FRONT, GL_AMBIENT_AND_DIFFUSE, front);
    glMaterialfv(GL_BACK, GL_AMBIENT_AND_DIFFUSE, back);
    for (int r = 0; r + 1 < R; r++) {
        glBegin(GL_TRIANGLE_STRIP);
        for (int c = 0; c < C; c++)
            for (int k = 1; k >= 0; k--) {
                size_t i = (size_t)(r + k) * C + c;
                glNormal3dv(n + 3 * i);
                glVertex3dv(x + 3 * i);
            }
        glEnd();
    }
    free(x);
    free(n);
    return 0;
}

int demo_draw_scene(const demo_camera *cam, dSpaceID space, dClothID *cloths, int ncloths, int smooth, int w, int h)
{
    glViewport(0, 0, w, h);
    glClearColor(0.93f, 0.95f, 0.98f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_LIGHTING);
    glEnable(GL_NORMALIZE);
    glShadeModel(GL_SMOOTH);
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
    GLfloat amb[4] = {0.22f, 0.22f, 0.24f, 1};
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, amb);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    double zn = 0.05, zf = 50, top = zn * tan(cam->fov_deg * M_PI / 360), right = top * w / h;
    glFrustum(-right, right, -top, top, zn, zf);
    glMatrixMode(GL_MODELVIEW);
    look_at(cam);
    /* a key light from above front left, a dimmer fill from the other side
     * (directional, fixed in the world) */
    GLfloat key_pos[4] = {-0.35f, -0.55f, 1.0f, 0}, fill_pos[4] = {0.6f, 0.4f, 0.35f, 0};
    GLfloat key_d[4] = {0.75f, 0.75f, 0.72f, 1}, fill_d[4] = {0.28f, 0.28f, 0.32f, 1}, none[4] = {0, 0, 0, 1};
    glEnable(GL_LIGHT0);
    glEnable(GL_LIGHT1);
    glLightfv(GL_LIGHT0, GL_POSITION, key_pos);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, key_d);
    glLightfv(GL_LIGHT0, GL_SPECULAR, none);
    glLightfv(GL_LIGHT1, GL_POSITION, fill_pos);
    glLightfv(GL_LIGHT1, GL_DIFFUSE, fill_d);
    glLightfv(GL_LIGHT1, GL_SPECULAR, none);
    if (space)
        for (int i = 0; i < dSpaceGetNumGeoms(space); i++) draw_geom(dSpaceGetGeom(space, i), cam);
    for (int i = 0; i < ncloths; i++)
        if (draw_cloth(cloths[i], smooth)) {
            fprintf(stderr, "render: out of memory for the cloth mesh\n");
            return -1;
        }
    return 0;
}
#endif /* DEMO_HAVE_GL */

/* ------------------------------------------------------- offscreen (OSMesa) */

#ifdef ODECLOTH_HAVE_OSMESA

static OSMesaContext ctx;
static unsigned char *buffer;
static int buf_w, buf_h;
static char failure[160];

int demo_render_available(void) { return 1; }
const char *demo_render_unavailable_reason(void) { return failure; }

void demo_render_shutdown(void)
{
    if (ctx) OSMesaDestroyContext(ctx);
    ctx = NULL;
    free(buffer);
    buffer = NULL;
    buf_w = buf_h = 0;
}

static int ensure_context(int w, int h)
{
    if (!ctx) {
        ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);
        if (!ctx) {
            snprintf(failure, sizeof failure, "OSMesaCreateContextExt failed");
            return -1;
        }
    }
    if (w != buf_w || h != buf_h) {
        unsigned char *b = realloc(buffer, 4 * (size_t)w * (size_t)h);
        if (!b) {
            snprintf(failure, sizeof failure, "out of memory for a %d x %d frame", w, h);
            return -1;
        }
        buffer = b;
        buf_w = w;
        buf_h = h;
    }
    if (!OSMesaMakeCurrent(ctx, buffer, GL_UNSIGNED_BYTE, w, h)) {
        snprintf(failure, sizeof failure, "OSMesaMakeCurrent failed for %d x %d", w, h);
        return -1;
    }
    return 0;
}

demo_image *demo_render(const demo_camera *cam, dSpaceID space, dClothID *cloths, int ncloths, int smooth, int w,
                        int h)
{
    const int ss = 2; /* supersampling */
    if (w <= 0 || h <= 0 || ensure_context(ss * w, ss * h)) {
        if (w <= 0 || h <= 0) snprintf(failure, sizeof failure, "bad picture size %d x %d", w, h);
        fprintf(stderr, "render: %s\n", failure);
        return NULL;
    }
    int W = ss * w, H = ss * h;
    if (demo_draw_scene(cam, space, cloths, ncloths, smooth, W, H)) return NULL;
    glFinish();
    static const unsigned char bg[3] = {255, 255, 255};
    demo_image *im = demo_image_create(w, h, bg);
    if (!im) {
        fprintf(stderr, "render: out of memory for a %d x %d image\n", w, h);
        return NULL;
    }
    /* OSMesa's row 0 is the bottom; average ss x ss blocks */
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int k = 0; k < 3; k++) {
                int sum = 0;
                for (int dy = 0; dy < ss; dy++)
                    for (int dx = 0; dx < ss; dx++)
                        sum += buffer[4 * ((size_t)(H - 1 - (ss * y + dy)) * W + (size_t)(ss * x + dx)) + k];
                im->rgb[3 * ((size_t)y * w + x) + k] = (unsigned char)((sum + ss * ss / 2) / (ss * ss));
            }
    return im;
}

#else /* no OSMesa: metrics only */

int demo_render_available(void) { return 0; }
const char *demo_render_unavailable_reason(void)
{
    return "built without OSMesa (install libosmesa6-dev and rebuild): no pictures, metrics only";
}
void demo_render_shutdown(void) {}

demo_image *demo_render(const demo_camera *cam, dSpaceID space, dClothID *cloths, int ncloths, int smooth, int w,
                        int h)
{
    (void)cam, (void)space, (void)cloths, (void)ncloths, (void)smooth, (void)w, (void)h;
    fprintf(stderr, "render: %s\n", demo_render_unavailable_reason());
    return NULL;
}
#endif
