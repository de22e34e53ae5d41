/* Plugin: a cloth dropped on each ODE geom class comes to rest on it and
 * never inside it; a cloth on a dynamic body weighs on it, and a cloth on a
 * kinematic body rides along.
 *
 * For each of the 8 geom classes (box, sphere, capsule, cylinder, convex,
 * trimesh, plane, heightfield): one static geom in a dHashSpace, gravity
 * (0, 0, -9.81), the default plugin cloth (dClothDefaultDesc(): 21 x 21
 * nodes, 1 m x 1 m, cotton, M = 0.2 kg, thickness 5 mm, mu 0.3) horizontal,
 * centred on the z axis DROP = 5 cm above the geom's top, stepped by
 * dClothWorldStep(world, &cloth, 1, 1/60, 0) for SECONDS.
 *
 * The geoms, each centred on the z axis (the cloth's centre vertex lands on
 * the top):
 *   box          0.6 m cube turned YAW = 0.3 rad about z, top at z = 0.6
 *   sphere       radius 0.3 at the origin
 *   capsule      radius 0.15, length 0.6, lying along x, top at z = 0.15
 *   cylinder     radius 0.3, length 0.4, upright, top cap at z = 0.2
 *   convex       the box above as 6 planes, 8 points and 6 quads (counter-
 *                clockwise seen from outside; checked here first)
 *   trimesh      the box above as 12 triangles (the quads split, same winding)
 *   plane        z = 0
 *   heightfield  2 m x 2 m, 41 x 41 samples 5 cm apart, a bump
 *                A exp(-r^2 / s^2), A = 8 cm, s = 0.3 m, over flat ground
 *                z = 0 (ODE heightfields are y-up: turned +90 deg about x)
 * Why a 0.6 m box and not a smaller one: over a 0.4 m box the default cotton
 * comes to rest tented, the middle of the top several thicknesses from the
 * surface, held up by the cloth itself (the internal forces on those
 * vertices balance their weight, with no contact force on them). That is the
 * cloth model's stiffness, not contact handling, so it is not what this test
 * is about.
 *
 * Every vertex's signed distance to the geom's surface is computed here,
 * independently of the plugin, from the dimensions and placement this test
 * chose (not read back from the geom): closed forms for sphere, box (also for
 * the convex and trimesh boxes), capsule, cylinder and plane; for the
 * heightfield the exact distance to ODE's triangulated surface (each cell
 * (i, j) split along the diagonal from sample (i+1, j) to (i, j+1), as
 * ODE's dxHeightfieldData::GetHeight and its colliders do), the sign from
 * the height of that surface under the vertex. That this model is the geom
 * ODE sees is checked first, with ODE's own rays (check_geometry).
 *
 * Asserted for each class:
 *   - every step succeeds;
 *   - every step, no vertex is inside the geom by more than TOL = 0.2
 *     thickness (1 mm): vertices are meant to keep a thickness away (dcloth.h),
 *     so a vertex 1 mm inside is 6 mm off where it should be;
 *   - at the end, every vertex is at least (1 - 0.2) thickness from the
 *     surface: at rest the thickness itself holds, not only the surface;
 *   - at the end the kinetic energy is at most KE_REST = 1/2 M (1 cm/s)^2
 *     = 1e-5 J: were all vertices moving at 1 cm/s, each would move 0.17 mm
 *     per step, 1/30 of the thickness; the kinetic energy peaks near 0.1 J
 *     at impact (M g DROP = 0.098 J), so this is ~1e-4 of it;
 *   - the cloth rests on the geom: the centre vertex is within 1 cm of the
 *     axis, between top + thickness - TOL and top + thickness + TOL + SAG,
 *     and at least MIN_TOUCHING = 5 vertices (as many as the centre and its
 *     4 neighbours) are within 1.5 thickness of the surface. (Not every
 *     vertex over a flat top need touch it: like the tent above, the cloth
 *     can hold a wrinkle a few mm high on its own.)
 *     SAG: where the plugin holds the cloth's triangles, not only its
 *     vertices, a thickness away (triangles.c), a vertex over a top
 *     curved with radius rho (the surface's, plus the thickness) rides up to
 *     r^2 / (2 rho) higher, r = 3.5 cm the circumradius of a cloth triangle
 *     (half a 5 cm cell's diagonal): 2.05 mm on the sphere, 4.0 mm on the
 *     capsule (rho 0.155 m; an upper bound: it curves one way only),
 *     1.1 mm on the heightfield's bump (rho = s^2 / (2 A)); 0 on
 *     the flat tops;
 *   - over the last WINDOW = 0.5 s the vertical contact forces on the cloth
 *     (dClothGetContactForce), averaged, carry its weight to 1%: at rest the
 *     geom is its only support. (Its momentum, at the kinetic energy bound,
 *     changes by at most 2 M (1 cm/s) over the window, 0.4% of M g WINDOW);
 *   - the last step's stats: contacts > 0, one candidate geom, and
 *     max_penetration (how far the deepest vertex was inside its thickness
 *     before the step) <= 0.1 thickness: at rest nothing should be found
 *     inside its shell; a vertex found 0.5 mm inside at rest means contacts
 *     that let go and catch the cloth step after step.
 *
 * Then two bodies:
 *   dynamic    a 0.6 x 0.6 x 0.4 m box of BOX_MASS = 5 kg (25 cloths) on the
 *              plane z = 0 (ODE contact joints from dSpaceCollide, with
 *              dJointFeedback), left 1 s to settle, then the cloth dropped
 *              on it. Asserted: the same rest checks, against the box at
 *              the body's pose; the box moves less than 0.5 mm and turns
 *              less than 1e-3 rad; over the last WINDOW the plane's contact
 *              joints carry box + cloth, (BOX_MASS + M) g, to 1% (before the
 *              cloth: BOX_MASS g to 1%). Without the cloth's reactions on the
 *              box the plane would carry 3.8% less, so this shows the
 *              cloth's weight went to the body.
 *   kinematic  a 0.6 x 0.6 x 0.4 m kinematic box (dBodySetKinematic) under
 *              the cloth: 3 s at rest for the cloth to settle on it, then
 *              moving up at V_UP = 0.2 m/s for 1.5 s. Asserted: every step,
 *              no vertex inside the box by more than TOL; over the last
 *              RIDE_WINDOW = 0.5 s, every step, the centre vertex's vertical
 *              velocity is V_UP to 3%, and its height above the box's top
 *              is the thickness to TOL.
 *
 * Printed: per class, the worst signed distance over the run and at rest,
 * the kinetic energy at rest, the centre's offset, the support force ratio
 * and the stats; for the bodies, what they measured.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"

#define H (1.0 / 60)
#define SECONDS 5.0
#define WINDOW 0.5
#define DROP 0.05
#define TOL_FRAC 0.2
#define REST_FRAC 0.8
#define TOUCH_FRAC 1.5
#define MIN_TOUCHING 5
#define PEN_STATS_FRAC 0.1
#define KE_REST 1e-5
#define SUPPORT_REL 0.01

#define BOX_MASS 5.0
#define V_UP 0.2
#define RIDE_REL 0.03
#define RIDE_WINDOW 0.5

enum { K_BOX, K_SPHERE, K_CAPSULE, K_CYLINDER, K_CONVEX, K_TRIMESH, K_PLANE, K_HEIGHTFIELD, NKINDS, K_BODY = NKINDS };
static const char *kind_name[NKINDS] = {"box",    "sphere",  "capsule", "cylinder",
                                        "convex", "trimesh", "plane",   "heightfield"};

/* --------------------------------------------------------------- geometry */

#define YAW 0.3
#define BOX_HALF 0.3
static const double box_c[3] = {0, 0, BOX_HALF};
#define SPHERE_R 0.3
#define CAPSULE_R 0.15
#define CAPSULE_L 0.6
#define CYL_R 0.3
#define CYL_L 0.4
#define HF_N 41
#define HF_SIZE 2.0
#define HF_A 0.08
#define HF_S 0.3
#define HF_STEP (HF_SIZE / (HF_N - 1))
/* the bodies' box */
static const double body_half[3] = {0.3, 0.3, 0.2};

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double norm3(const double *a) { return sqrt(dot3(a, a)); }
static double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }

/* signed distance to an axis-aligned box of half extents e centred at 0 */
static double sd_box_local(const double p[3], const double e[3])
{
    double out = 0, in = -INFINITY;
    for (int k = 0; k < 3; k++) {
        double q = fabs(p[k]) - e[k];
        out += q > 0 ? q * q : 0;
        in = fmax(in, q);
    }
    return sqrt(out) + fmin(in, 0.0);
}

/* a box of half extents e at centre c, turned by yaw about z */
static double sd_box_yaw(const double x[3], const double c[3], double yaw, const double e[3])
{
    double d[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]}, cs = cos(yaw), sn = sin(yaw);
    double p[3] = {cs * d[0] + sn * d[1], -sn * d[0] + cs * d[1], d[2]};
    return sd_box_local(p, e);
}

/* a box of half extents e at a body's pose (ODE's 3x4 row-major R) */
static double sd_box_body(const double x[3], dBodyID b, const double e[3])
{
    const dReal *c = dBodyGetPosition(b), *R = dBodyGetRotation(b);
    double d[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]}, p[3];
    for (int k = 0; k < 3; k++) p[k] = R[k] * d[0] + R[4 + k] * d[1] + R[8 + k] * d[2];
    return sd_box_local(p, e);
}

static double hf_sample(int i, int j)
{
    double x = -0.5 * HF_SIZE + i * HF_STEP, z = -0.5 * HF_SIZE + j * HF_STEP;
    return HF_A * exp(-(x * x + z * z) / (HF_S * HF_S));
}

/* sample (i, j) in the heightfield's frame (x, height, z) */
static void hf_vertex(int i, int j, double v[3])
{
    v[0] = -0.5 * HF_SIZE + i * HF_STEP;
    v[1] = hf_sample(i, j);
    v[2] = -0.5 * HF_SIZE + j * HF_STEP;
}

/* height of the triangulated surface at (x, z) of the heightfield's frame */
static double hf_surface(double x, double z)
{
    double u = (x + 0.5 * HF_SIZE) / HF_STEP, w = (z + 0.5 * HF_SIZE) / HF_STEP;
    int i = (int)clampd(floor(u), 0, HF_N - 2), j = (int)clampd(floor(w), 0, HF_N - 2);
    double dx = u - i, dz = w - j;
    if (dx + dz <= 1) {
        double y0 = hf_sample(i, j);
        return y0 + (hf_sample(i + 1, j) - y0) * dx + (hf_sample(i, j + 1) - y0) * dz;
    }
    double y0 = hf_sample(i + 1, j + 1);
    return y0 + (hf_sample(i + 1, j) - y0) * (1 - dz) + (hf_sample(i, j + 1) - y0) * (1 - dx);
}

/* distance from p to triangle abc (closest point by Voronoi regions,
 * Ericson, Real-Time Collision Detection 5.1.5) */
static double dist_tri(const double p[3], const double a[3], const double b[3], const double c[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], q[3];
    for (int k = 0; k < 3; k++) {
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ap[k] = p[k] - a[k];
        bp[k] = p[k] - b[k];
        cp[k] = p[k] - c[k];
    }
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap), d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    double va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
    if (d1 <= 0 && d2 <= 0) {
        memcpy(q, a, sizeof q);
    } else if (d3 >= 0 && d4 <= d3) {
        memcpy(q, b, sizeof q);
    } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double v = d1 / (d1 - d3);
        for (int k = 0; k < 3; k++) q[k] = a[k] + v * ab[k];
    } else if (d6 >= 0 && d5 <= d6) {
        memcpy(q, c, sizeof q);
    } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double w = d2 / (d2 - d6);
        for (int k = 0; k < 3; k++) q[k] = a[k] + w * ac[k];
    } else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; k++) q[k] = b[k] + w * (c[k] - b[k]);
    } else {
        double den = 1.0 / (va + vb + vc), v = vb * den, w = vc * den;
        for (int k = 0; k < 3; k++) q[k] = a[k] + ab[k] * v + ac[k] * w;
    }
    double e[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    return norm3(e);
}

/* The heightfield is turned +90 deg about x: world (X, Y, Z) = (x, -z, y)
 * of its frame. The surface point straight below (or above) is |gv| away, so
 * the nearest one is within |gv| horizontally: only those cells are tried. */
static double sd_heightfield(const double X[3])
{
    double p[3] = {X[0], X[2], -X[1]};
    double gv = p[1] - hf_surface(p[0], p[2]), r = fabs(gv), best = r;
    int i0 = (int)clampd(floor((p[0] - r + 0.5 * HF_SIZE) / HF_STEP), 0, HF_N - 2);
    int i1 = (int)clampd(floor((p[0] + r + 0.5 * HF_SIZE) / HF_STEP), 0, HF_N - 2);
    int j0 = (int)clampd(floor((p[2] - r + 0.5 * HF_SIZE) / HF_STEP), 0, HF_N - 2);
    int j1 = (int)clampd(floor((p[2] + r + 0.5 * HF_SIZE) / HF_STEP), 0, HF_N - 2);
    for (int i = i0; i <= i1; i++)
        for (int j = j0; j <= j1; j++) {
            double A[3], B[3], C[3], D[3];
            hf_vertex(i, j, A);
            hf_vertex(i + 1, j, B);
            hf_vertex(i, j + 1, C);
            hf_vertex(i + 1, j + 1, D);
            best = fmin(best, fmin(dist_tri(p, A, B, C), dist_tri(p, D, B, C)));
        }
    return gv >= 0 ? best : -best;
}

/* the surface a test measures against: a geom class, or the bodies' box */
typedef struct shape {
    int kind;
    dBodyID body; /* K_BODY */
} shape;

static double sdist(const shape *s, const double x[3])
{
    static const double cube[3] = {BOX_HALF, BOX_HALF, BOX_HALF};
    switch (s->kind) {
    case K_BOX:
    case K_CONVEX:
    case K_TRIMESH: return sd_box_yaw(x, box_c, YAW, cube);
    case K_SPHERE: return norm3(x) - SPHERE_R;
    case K_CAPSULE: { /* axis along x through the origin */
        double d[3] = {x[0] - clampd(x[0], -0.5 * CAPSULE_L, 0.5 * CAPSULE_L), x[1], x[2]};
        return norm3(d) - CAPSULE_R;
    }
    case K_CYLINDER: { /* axis along z through the origin */
        double a = hypot(x[0], x[1]) - CYL_R, b = fabs(x[2]) - 0.5 * CYL_L;
        return hypot(fmax(a, 0), fmax(b, 0)) + fmin(fmax(a, b), 0.0);
    }
    case K_PLANE: return x[2];
    case K_HEIGHTFIELD: return sd_heightfield(x);
    case K_BODY: return sd_box_body(x, s->body, body_half);
    }
    return NAN;
}

/* z of the top of the surface on the z axis */
static double shape_top(const shape *s)
{
    switch (s->kind) {
    case K_BOX:
    case K_CONVEX:
    case K_TRIMESH: return box_c[2] + BOX_HALF;
    case K_SPHERE: return SPHERE_R;
    case K_CAPSULE: return CAPSULE_R;
    case K_CYLINDER: return 0.5 * CYL_L;
    case K_PLANE: return 0;
    case K_HEIGHTFIELD: return HF_A;
    case K_BODY: return dBodyGetPosition(s->body)[2] + body_half[2];
    }
    return NAN;
}

/* SAG (see the top): r^2 / (2 rho), r the circumradius of a cloth triangle */
static double centre_sag(const shape *s, double thickness)
{
    const double r = 0.5 * hypot(0.05, 0.05);
    switch (s->kind) {
    case K_SPHERE: return r * r / (2 * (SPHERE_R + thickness));
    case K_CAPSULE: return r * r / (2 * (CAPSULE_R + thickness));
    case K_HEIGHTFIELD: return r * r / (2 * (HF_S * HF_S / (2 * HF_A) + thickness));
    default: return 0;
    }
}

/* ---------------------------------------------------------- the box data */

/* vertex i at (+-a, +-a, +-a): bit 0 is x, bit 1 y, bit 2 z */
static dReal cvx_points[24];
/* faces +x, -x, +y, -y, +z, -z: n . p = a */
static dReal cvx_planes[24];
/* count, then indices, counter-clockwise seen from outside */
static const unsigned int cvx_polys[30] = {4, 1, 3, 7, 5, 4, 0, 4, 6, 2, 4, 2, 6, 7, 3,
                                           4, 0, 1, 5, 4, 4, 4, 5, 7, 6, 4, 0, 2, 3, 1};
static dTriIndex tri_idx[36];

static void build_box_data(void)
{
    static const double n[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int i = 0; i < 8; i++) {
        cvx_points[3 * i + 0] = (i & 1) ? BOX_HALF : -BOX_HALF;
        cvx_points[3 * i + 1] = (i & 2) ? BOX_HALF : -BOX_HALF;
        cvx_points[3 * i + 2] = (i & 4) ? BOX_HALF : -BOX_HALF;
    }
    for (int f = 0; f < 6; f++) {
        for (int k = 0; k < 3; k++) cvx_planes[4 * f + k] = n[f][k];
        cvx_planes[4 * f + 3] = BOX_HALF;
        /* quad (q0 q1 q2 q3) -> (q0 q1 q2), (q0 q2 q3): the same winding */
        const unsigned int *q = cvx_polys + 5 * f + 1;
        dTriIndex *t = tri_idx + 6 * f;
        t[0] = q[0], t[1] = q[1], t[2] = q[2];
        t[3] = q[0], t[4] = q[2], t[5] = q[3];
    }
}

/* The data is the test's own: every quad's winding normal is its plane's
 * (outward) normal, and its 4 points lie on the plane. */
static void check_box_data(void)
{
    for (int f = 0; f < 6; f++) {
        const unsigned int *q = cvx_polys + 5 * f + 1;
        const dReal *p0 = cvx_points + 3 * q[0], *p1 = cvx_points + 3 * q[1], *p2 = cvx_points + 3 * q[2];
        double e1[3], e2[3], c[3], off = 0;
        for (int k = 0; k < 3; k++) e1[k] = p1[k] - p0[k], e2[k] = p2[k] - p0[k];
        c[0] = e1[1] * e2[2] - e1[2] * e2[1];
        c[1] = e1[2] * e2[0] - e1[0] * e2[2];
        c[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double l = norm3(c);
        for (int v = 0; v < 4; v++)
            off = fmax(off, fabs(dot3(cvx_planes + 4 * f, cvx_points + 3 * q[v]) - cvx_planes[4 * f + 3]));
        CHECK(cvx_polys[5 * f] == 4 && fabs(dot3(c, cvx_planes + 4 * f) / l - 1) < 1e-12 && off < 1e-12,
              "box data, face %d: winding normal (%g %g %g), plane normal (%g %g %g), points off the plane by %g", f,
              c[0] / l, c[1] / l, c[2] / l, cvx_planes[4 * f], cvx_planes[4 * f + 1], cvx_planes[4 * f + 2], off);
    }
}

/* -------------------------------------------------------------- the cloth */

static dClothDesc desc_at(double z)
{
    dClothDesc d = dClothDefaultDesc();
    d.cloth.origin[0] = -0.5 * d.cloth.width;
    d.cloth.origin[1] = -0.5 * d.cloth.height;
    d.cloth.origin[2] = z;
    return d;
}

static double cloth_mass(dClothID c)
{
    double m = 0;
    for (int i = 0; i < dClothGetVertexCount(c); i++) m += cloth_masses(dClothGetCore(c))[i];
    return m;
}

static int centre_vertex(const dClothDesc *d) { return (d->cloth.rows / 2) * d->cloth.cols + d->cloth.cols / 2; }

/* the smallest signed distance over the vertices */
static double min_sd(const shape *s, dClothID c)
{
    const dReal *x = dClothGetPositions(c);
    double m = INFINITY;
    for (int i = 0; i < dClothGetVertexCount(c); i++) m = fmin(m, sdist(s, x + 3 * i));
    return m;
}

static double support_z(dClothID c)
{
    double fz = 0;
    for (int i = 0; i < dClothGetVertexCount(c); i++) {
        double f[3];
        dClothGetContactForce(c, i, f);
        fz += f[2];
    }
    return fz;
}

/* Distance between segments p0p1 and q0q1 (Ericson 5.1.9, closest points
 * of two segments, clamped). */
static double dist_segseg(const double p0[3], const double p1[3], const double q0[3], const double q1[3])
{
    double d1[3], d2[3], r[3];
    for (int k = 0; k < 3; k++) d1[k] = p1[k] - p0[k], d2[k] = q1[k] - q0[k], r[k] = p0[k] - q0[k];
    double a = dot3(d1, d1), e = dot3(d2, d2), f = dot3(d2, r), s, t;
    if (a <= 1e-30 && e <= 1e-30) {
        s = t = 0;
    } else if (a <= 1e-30) {
        s = 0;
        t = clampd(f / e, 0, 1);
    } else {
        double c = dot3(d1, r);
        if (e <= 1e-30) {
            t = 0;
            s = clampd(-c / a, 0, 1);
        } else {
            double b = dot3(d1, d2), den = a * e - b * b;
            s = den > 0 ? clampd((b * f - c * e) / den, 0, 1) : 0;
            t = (b * s + f) / e;
            if (t < 0) t = 0, s = clampd(-c / a, 0, 1);
            else if (t > 1) t = 1, s = clampd((b - c) / a, 0, 1);
        }
    }
    double w[3];
    for (int k = 0; k < 3; k++) w[k] = (p0[k] + s * d1[k]) - (q0[k] + t * d2[k]);
    return norm3(w);
}

/* Distance between segment p0p1 and triangle abc: 0 if the segment crosses
 * the triangle, else the least of its ends to the triangle and of the
 * segment to the triangle's three edges. */
static double dist_segtri(const double p0[3], const double p1[3], const double *a, const double *b, const double *c)
{
    double e1[3], e2[3], d[3], pv[3], tv[3], qv[3];
    for (int k = 0; k < 3; k++) e1[k] = b[k] - a[k], e2[k] = c[k] - a[k], d[k] = p1[k] - p0[k], tv[k] = p0[k] - a[k];
    pv[0] = d[1] * e2[2] - d[2] * e2[1];
    pv[1] = d[2] * e2[0] - d[0] * e2[2];
    pv[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = dot3(e1, pv);
    if (fabs(det) > 1e-300) { /* Moller-Trumbore on the segment */
        double u = dot3(tv, pv) / det;
        qv[0] = tv[1] * e1[2] - tv[2] * e1[1];
        qv[1] = tv[2] * e1[0] - tv[0] * e1[2];
        qv[2] = tv[0] * e1[1] - tv[1] * e1[0];
        double v = dot3(d, qv) / det, t = dot3(e2, qv) / det;
        if (u >= 0 && v >= 0 && u + v <= 1 && t >= 0 && t <= 1) return 0.0;
    }
    double m = fmin(dist_tri(p0, a, b, c), dist_tri(p1, a, b, c));
    m = fmin(m, dist_segseg(p0, p1, a, b));
    m = fmin(m, dist_segseg(p0, p1, b, c));
    return fmin(m, dist_segseg(p0, p1, c, a));
}

/* The geom's edges and corners against the cloth's triangles, exactly: the
 * 12 edges of the yawed cube (box-like shapes), or the cylinder's two rims
 * as chords of 2 mm (inside the rim by at most 2e-6 m). A corner poking
 * through a triangle between its vertices reads 0 here while every vertex
 * stays clear (the paper's flaw at the table corners). INFINITY for shapes
 * without edges. */
static double edge_clearance(const shape *s, dClothID c)
{
    int nt = dClothGetTriangleCount(c);
    const int *tri = dClothGetTriangles(c);
    const dReal *x = dClothGetPositions(c);
    double best = INFINITY;
    double seg[1000][2][3];
    int ns = 0;
    if (s->kind == K_BOX || s->kind == K_CONVEX || s->kind == K_TRIMESH) {
        double cy = cos(YAW), sy = sin(YAW);
        for (int e = 0; e < 12; e++) { /* along axis e / 4, the other two at the signs of e % 4 */
            int ax = e / 4, o1 = (ax + 1) % 3, o2 = (ax + 2) % 3;
            for (int end = 0; end < 2; end++) {
                double l[3];
                l[ax] = end ? BOX_HALF : -BOX_HALF;
                l[o1] = (e & 1) ? BOX_HALF : -BOX_HALF;
                l[o2] = (e & 2) ? BOX_HALF : -BOX_HALF;
                double *p = seg[ns][end];
                p[0] = box_c[0] + cy * l[0] - sy * l[1];
                p[1] = box_c[1] + sy * l[0] + cy * l[1];
                p[2] = box_c[2] + l[2];
            }
            ns++;
        }
    } else if (s->kind == K_CYLINDER) {
        int n = (int)(2 * M_PI * CYL_R / 2e-3);
        if (n > 480) n = 480;
        for (int rim = 0; rim < 2; rim++)
            for (int k = 0; k < n; k++)
                for (int end = 0; end < 2; end++) {
                    double a = 2 * M_PI * (k + end) / n, *p = seg[ns][end];
                    p[0] = CYL_R * cos(a);
                    p[1] = CYL_R * sin(a);
                    p[2] = rim ? 0.5 * CYL_L : -0.5 * CYL_L;
                    ns += end;
                }
    } else {
        return INFINITY;
    }
    for (int q = 0; q < ns; q++) {
        double lo[3], hi[3];
        for (int a = 0; a < 3; a++) lo[a] = fmin(seg[q][0][a], seg[q][1][a]), hi[a] = fmax(seg[q][0][a], seg[q][1][a]);
        for (int t = 0; t < nt; t++) {
            const double *A = x + 3 * tri[3 * t], *B = x + 3 * tri[3 * t + 1], *C = x + 3 * tri[3 * t + 2];
            int far = 0; /* bounds apart by more than the best so far */
            for (int a = 0; a < 3 && !far; a++)
                far = fmin(A[a], fmin(B[a], C[a])) > hi[a] + best || fmax(A[a], fmax(B[a], C[a])) < lo[a] - best;
            if (!far) best = fmin(best, dist_segtri(seg[q][0], seg[q][1], A, B, C));
        }
    }
    return best;
}

/* What a run measured. */
typedef struct figures {
    int steps_ok;
    double worst_run; /* m, min signed distance over every vertex, every step */
    int worst_step;
    double worst_rest; /* m, the same at the end */
    double ke;         /* J, at the end */
    double centre_dz;  /* m, centre z - (top + thickness), end */
    double sag;        /* m, SAG of the surface */
    double centre_r;   /* m, centre's distance from the z axis */
    int touching;      /* vertices within TOUCH_FRAC thickness, end */
    double support;    /* window mean of the vertical contact forces / (M g) */
    int contacts, candidates;
    double max_pen; /* m, last step's stats */
    double edge;    /* m, the geom's edges and corners to the nearest
                           cloth triangle, least over the run (INFINITY:
                           a shape without edges) */
    int edge_step;
    double edge_rest; /* m, the same at the end */
    int kind;
} figures;

/* A run's figures before its first step. */
static figures figures_for(int kind)
{
    figures f;
    memset(&f, 0, sizeof f);
    f.worst_run = INFINITY;
    f.edge = INFINITY;
    f.kind = kind;
    return f;
}

/* The rest checks shared by the static classes and the dynamic body. */
static void check_rest(const char *name, const dClothDesc *d, const figures *f, int check_candidates)
{
    double th = d->thickness, tol = TOL_FRAC * th;
    CHECK(f->worst_run >= -tol, "%s: a vertex went %.3g mm inside the surface (step %d; tolerance %.3g mm)", name,
          -1e3 * f->worst_run, f->worst_step, 1e3 * tol);
    CHECK(f->worst_rest >= REST_FRAC * th, "%s: at rest a vertex is %.3g mm from the surface, < %.3g mm", name,
          1e3 * f->worst_rest, 1e3 * REST_FRAC * th);
    CHECK(f->ke <= KE_REST, "%s: kinetic energy %.3g J at the end, > %.3g J", name, f->ke, KE_REST);
    CHECK(f->centre_dz >= -tol && f->centre_dz <= tol + f->sag && f->centre_r <= 0.01,
          "%s: the centre vertex is %.3g mm above top + thickness (allowed %.3g .. %.3g mm) and %.3g mm off the axis "
          "(allowed 10 mm)",
          name, 1e3 * f->centre_dz, -1e3 * tol, 1e3 * (tol + f->sag), 1e3 * f->centre_r);
    CHECK(f->touching >= MIN_TOUCHING, "%s: %d vertices within %.3g mm of the surface, fewer than %d", name,
          f->touching, 1e3 * TOUCH_FRAC * th, MIN_TOUCHING);
    CHECK(fabs(f->support - 1) <= SUPPORT_REL,
          "%s: the vertical contact forces carry %.4f of the cloth's weight over the last %g s", name, f->support,
          WINDOW);
    CHECK(f->contacts > 0 && (!check_candidates || f->candidates == 1), "%s: stats: %d contacts, %d candidate geoms",
          name, f->contacts, f->candidates);
    CHECK(f->max_pen <= PEN_STATS_FRAC * th, "%s: stats: max_penetration %.3g mm > %.3g mm", name, 1e3 * f->max_pen,
          1e3 * PEN_STATS_FRAC * th);
    /* no edge or corner through a triangle, at any step checked (every
     * third): a mesh's triangles meet the cloth's as prisms (triangles.c),
     * which vertex contacts alone would not keep out. */
    CHECK(f->edge > 0.0, "%s: an edge or corner of the geom passes through a cloth triangle (step %d)", name,
          f->edge_step);
}

static void print_figures(const char *name, const figures *f)
{
    printf("%-11s worst signed distance: run %+7.3f mm (step %3d), rest %+7.3f mm; KE %.2e J; centre %+7.3f mm "
           "above top + th; %3d vertices within 1.5 th; support %.4f M g; stats %d contacts, max_penetration "
           "%.3f mm; edges to triangles %.3f mm (step %d), at rest %.3f mm\n",
           name, 1e3 * f->worst_run, f->worst_step, 1e3 * f->worst_rest, f->ke, 1e3 * f->centre_dz, f->touching,
           f->support, f->contacts, 1e3 * f->max_pen, 1e3 * f->edge, f->edge_step, 1e3 * f->edge_rest);
}

/* Step n times, tracking the worst distance; the support is averaged over
 * the last WINDOW. pre (may be NULL) runs before each step (ODE's contacts),
 * post (may be NULL) after it, told whether the step is in the window. */
typedef struct hooks {
    void (*pre)(void *);
    void (*post)(void *, int in_window);
    void *data;
} hooks;

static void run_steps(dWorldID w, dClothID c, const shape *s, const char *name, int n, figures *f, const hooks *hk,
                      double weight)
{
    int window = (int)(WINDOW / H + 0.5);
    double support = 0;
    for (int step = 1; step <= n; step++) {
        if (hk && hk->pre) hk->pre(hk->data);
        cloth_status st = dClothWorldStep(w, &c, 1, H, 0);
        if (!CHECK(st == CLOTH_OK, "%s: step %d: %s", name, step, dClothGetLastError(c))) return;
        double m = min_sd(s, c);
        if (m < f->worst_run) f->worst_run = m, f->worst_step = step;
        if (step % 3 == 0 || step == n) {
            double e = edge_clearance(s, c);
            if (e < f->edge) f->edge = e, f->edge_step = step;
            if (step == n) f->edge_rest = e;
        }
        if (step > n - window) support += support_z(c) / window;
        if (hk && hk->post) hk->post(hk->data, step > n - window);
    }
    f->steps_ok = 1;
    f->support = support / weight;
}

static void measure_rest(dClothID c, const dClothDesc *d, const shape *s, figures *f)
{
    const dReal *x = dClothGetPositions(c);
    int ctr = centre_vertex(d);
    f->worst_rest = min_sd(s, c);
    f->ke = cloth_energies(dClothGetCore(c)).kinetic;
    f->centre_dz = x[3 * ctr + 2] - (shape_top(s) + d->thickness);
    f->sag = centre_sag(s, d->thickness);
    f->centre_r = hypot(x[3 * ctr], x[3 * ctr + 1]);
    for (int i = 0; i < dClothGetVertexCount(c); i++) f->touching += sdist(s, x + 3 * i) <= TOUCH_FRAC * d->thickness;
    const dClothStepStats *st = dClothGetStats(c);
    f->contacts = st->contacts;
    f->candidates = st->candidates;
    f->max_pen = st->max_penetration;
}

/* ------------------------------------------------------ the static classes */

/* The test's surfaces are the geoms ODE (and so the plugin) sees: vertical
 * rays cast down at ODE's geom over the cloth's footprint land on the test's
 * surface (signed distance 0 to 1e-9 m), and those that miss it do not
 * enter the test's solid either (sampled every mm). This checks the test's
 * own model (dimensions, placement, the heightfield's frame and
 * triangulation), not the plugin. */
static void check_geometry(int k, dGeomID g)
{
    const shape s = {k, 0};
    const double z0 = shape_top(&s) + 0.5;
    dGeomID ray = dCreateRay(0, 2.0);
    dGeomRaySetClosestHit(ray, 1);
    int hits = 0;
    double worst = 0;
    for (int a = 0; a <= 20; a++)
        for (int b = 0; b <= 20; b++) {
            double x = -0.5 + 0.05 * a + 0.0123, y = -0.5 + 0.05 * b + 0.0071; /* off the sample grid */
            dGeomRaySet(ray, x, y, z0, 0, 0, -1);
            dContactGeom cg[8];
            int n = dCollide(ray, g, 8, cg, sizeof cg[0]);
            if (n <= 0) { /* a miss: the test's surface is missed too (sampled every mm) */
                for (int t = 0; t <= 2000; t++) {
                    double p[3] = {x, y, z0 - 1e-3 * t};
                    worst = fmax(worst, -sdist(&s, p));
                }
                continue;
            }
            double dmin = INFINITY;
            for (int i = 0; i < n; i++) dmin = fmin(dmin, cg[i].depth);
            double hit[3] = {x, y, z0 - dmin};
            worst = fmax(worst, fabs(sdist(&s, hit)));
            hits++;
        }
    dGeomDestroy(ray);
    printf("%-11s geometry: %d of 441 vertical rays hit ODE's geom, at most %.2g m off the test's surface\n",
           kind_name[k], hits, worst);
    CHECK(hits > 0 && worst <= 1e-9,
          "%s: %d rays hit ODE's geom; hits off, or misses inside, the test's surface by up to %.3g m", kind_name[k],
          hits, worst);
}

static void run_class(int k)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dTriMeshDataID tmd = NULL;
    dHeightfieldDataID hfd = NULL;
    static double heights[HF_N * HF_N];
    dGeomID g = 0;
    dMatrix3 R;
    switch (k) {
    case K_BOX: g = dCreateBox(sp, 2 * BOX_HALF, 2 * BOX_HALF, 2 * BOX_HALF); break;
    case K_SPHERE: g = dCreateSphere(sp, SPHERE_R); break;
    case K_CAPSULE:
        g = dCreateCapsule(sp, CAPSULE_R, CAPSULE_L);
        dRFromAxisAndAngle(R, 0, 1, 0, M_PI / 2); /* its axis (local z) along world x */
        dGeomSetRotation(g, R);
        break;
    case K_CYLINDER: g = dCreateCylinder(sp, CYL_R, CYL_L); break;
    case K_CONVEX: g = dCreateConvex(sp, cvx_planes, 6, cvx_points, 8, cvx_polys); break;
    case K_TRIMESH:
        tmd = dGeomTriMeshDataCreate();
        dGeomTriMeshDataBuildDouble(tmd, cvx_points, 3 * sizeof(dReal), 8, tri_idx, 36, 3 * sizeof(dTriIndex));
        g = dCreateTriMesh(sp, tmd, NULL, NULL, NULL);
        break;
    case K_PLANE: g = dCreatePlane(sp, 0, 0, 1, 0); break;
    case K_HEIGHTFIELD:
        for (int j = 0; j < HF_N; j++)
            for (int i = 0; i < HF_N; i++) heights[i + j * HF_N] = hf_sample(i, j);
        hfd = dGeomHeightfieldDataCreate();
        /* scale 1, offset 0, a 0.1 m slab under the lowest sample, no wrap */
        dGeomHeightfieldDataBuildDouble(hfd, heights, 0, HF_SIZE, HF_SIZE, HF_N, HF_N, 1.0, 0.0, 0.1, 0);
        g = dCreateHeightfield(sp, hfd, 1);
        dRFromAxisAndAngle(R, 1, 0, 0, M_PI / 2); /* its up (local y) along world z */
        dGeomSetRotation(g, R);
        break;
    }
    if (k == K_BOX || k == K_CONVEX || k == K_TRIMESH) {
        dRFromAxisAndAngle(R, 0, 0, 1, YAW);
        dGeomSetRotation(g, R);
        dGeomSetPosition(g, box_c[0], box_c[1], box_c[2]);
    }

    check_geometry(k, g);
    shape s = {k, 0};
    dClothDesc d = desc_at(shape_top(&s) + DROP);
    dClothID c = NULL;
    cloth_error err;
    figures f = figures_for(k);
    if (CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "%s: dClothCreate: %s", kind_name[k], err.message)) {
        dClothSetFailureMode(c, DCLOTH_FAILURE_STOP); /* a failed step is an error here */
        if (k == K_CONVEX)
            CHECK(dClothSetConvexPoints(c, g, cvx_points, 8) == CLOTH_OK, "convex points: %s", dClothGetLastError(c));
        double weight = 9.81 * cloth_mass(c);
        run_steps(w, c, &s, kind_name[k], (int)(SECONDS / H + 0.5), &f, NULL, weight);
        if (f.steps_ok) {
            measure_rest(c, &d, &s, &f);
            print_figures(kind_name[k], &f);
            check_rest(kind_name[k], &d, &f, 1);
        }
        dClothDestroy(c);
    }
    dGeomDestroy(g);
    if (tmd) dGeomTriMeshDataDestroy(tmd);
    if (hfd) dGeomHeightfieldDataDestroy(hfd);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

/* ------------------------------------------------------------ the bodies */

#define MAX_FEEDBACK 16

typedef struct ode_contacts {
    dWorldID world;
    dSpaceID space;
    dJointGroupID group;
    dJointFeedback fb[MAX_FEEDBACK];
    int nfb;
    double fz_window; /* N, the plane's force on the box averaged over WINDOW */
} ode_contacts;

static void near_cb(void *data, dGeomID a, dGeomID b)
{
    ode_contacts *oc = data;
    if (!dGeomGetBody(a)) { /* the body's geom first: it is then the joint's body 1 (feedback f1) */
        dGeomID t = a;
        a = b;
        b = t;
    }
    dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
    if (!ba) return;
    dContact ct[8];
    int n = dCollide(a, b, 8, &ct[0].geom, sizeof ct[0]);
    for (int i = 0; i < n && oc->nfb < MAX_FEEDBACK; i++) {
        memset(&ct[i].surface, 0, sizeof ct[i].surface);
        ct[i].surface.mu = dInfinity;
        dJointID j = dJointCreateContact(oc->world, oc->group, &ct[i]);
        dJointAttach(j, ba, bb);
        dJointSetFeedback(j, &oc->fb[oc->nfb++]);
    }
}

static void ode_collide(void *data)
{
    ode_contacts *oc = data;
    dJointGroupEmpty(oc->group);
    oc->nfb = 0;
    dSpaceCollide(oc->space, oc, near_cb);
}

/* vertical force of the plane's contact joints on the box (their body 1),
 * last world step */
static double plane_force(const ode_contacts *oc)
{
    double fz = 0;
    for (int i = 0; i < oc->nfb; i++) fz += oc->fb[i].f1[2];
    return fz;
}

static void plane_force_window(void *data, int in_window)
{
    ode_contacts *oc = data;
    if (in_window) oc->fz_window += plane_force(oc) / (int)(WINDOW / H + 0.5);
}

static void run_dynamic(void)
{
    const char *name = "dynamic";
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dGeomID plane = dCreatePlane(sp, 0, 0, 1, 0);
    dBodyID b = dBodyCreate(w);
    dMass m;
    dMassSetBoxTotal(&m, BOX_MASS, 2 * body_half[0], 2 * body_half[1], 2 * body_half[2]);
    dBodySetMass(b, &m);
    dBodySetPosition(b, 0, 0, body_half[2]);
    dGeomID g = dCreateBox(sp, 2 * body_half[0], 2 * body_half[1], 2 * body_half[2]);
    dGeomSetBody(g, b);
    ode_contacts oc;
    memset(&oc, 0, sizeof oc);
    oc.world = w;
    oc.space = sp;
    oc.group = dJointGroupCreate(0);

    /* the box alone settles on the plane */
    int window = (int)(WINDOW / H + 0.5), settle = (int)(1.0 / H + 0.5);
    double fz_alone = 0;
    for (int step = 1; step <= settle; step++) {
        ode_collide(&oc);
        dWorldStep(w, H);
        if (step > settle - window) fz_alone += plane_force(&oc) / window;
    }
    dVector3 p0;
    memcpy(p0, dBodyGetPosition(b), sizeof p0);
    CHECK(fabs(fz_alone / (BOX_MASS * 9.81) - 1) <= SUPPORT_REL,
          "%s: alone, the plane's contacts carry %.4f of the box's weight", name, fz_alone / (BOX_MASS * 9.81));

    shape s = {K_BODY, b};
    dClothDesc d = desc_at(shape_top(&s) + DROP);
    dClothID c = NULL;
    cloth_error err;
    figures f = figures_for(K_BODY);
    if (CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "%s: dClothCreate: %s", name, err.message)) {
        dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
        double mc = cloth_mass(c), weight = 9.81 * mc;
        oc.fz_window = 0;
        hooks hk = {ode_collide, plane_force_window, &oc};
        run_steps(w, c, &s, name, (int)(SECONDS / H + 0.5), &f, &hk, weight);
        double fz_both = oc.fz_window;
        if (f.steps_ok) {
            measure_rest(c, &d, &s, &f);
            const dReal *p = dBodyGetPosition(b), *R = dBodyGetRotation(b);
            double dp[3] = {p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]};
            double tilt = acos(clampd(R[10], -1, 1)); /* body z against world z */
            double ratio = fz_both / ((BOX_MASS + mc) * 9.81);
            print_figures(name, &f);
            printf("%-11s box moved %.3g mm, tilted %.3g rad; plane carries %.4f (box + cloth) g (box alone: %.4f, "
                   "box + cloth / box alone = %.4f, expected %.4f)\n",
                   name, 1e3 * norm3(dp), tilt, ratio, fz_alone / (BOX_MASS * 9.81), fz_both / fz_alone,
                   (BOX_MASS + mc) / BOX_MASS);
            check_rest(name, &d, &f, 0);
            CHECK(norm3(dp) <= 5e-4 && tilt <= 1e-3, "%s: the box moved %.3g mm and tilted %.3g rad", name,
                  1e3 * norm3(dp), tilt);
            CHECK(fabs(ratio - 1) <= SUPPORT_REL, "%s: the plane carries %.4f of box + cloth (box alone: %.4f)", name,
                  ratio, fz_both / (BOX_MASS * 9.81));
        }
        dClothDestroy(c);
    }
    dJointGroupDestroy(oc.group);
    dGeomDestroy(g);
    dGeomDestroy(plane);
    dBodyDestroy(b);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

static void run_kinematic(void)
{
    const char *name = "kinematic";
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dBodyID b = dBodyCreate(w);
    dBodySetKinematic(b);
    dBodySetPosition(b, 0, 0, body_half[2]);
    dGeomID g = dCreateBox(sp, 2 * body_half[0], 2 * body_half[1], 2 * body_half[2]);
    dGeomSetBody(g, b);

    shape s = {K_BODY, b};
    dClothDesc d = desc_at(shape_top(&s) + DROP);
    double th = d.thickness, tol = TOL_FRAC * th;
    dClothID c = NULL;
    cloth_error err;
    if (CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "%s: dClothCreate: %s", name, err.message)) {
        dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
        int ctr = centre_vertex(&d), rest = (int)(3.0 / H + 0.5), ride = (int)(1.5 / H + 0.5);
        int window = (int)(RIDE_WINDOW / H + 0.5), bad_v = 0, bad_h = 0, worst_step = 0;
        double worst = INFINITY, vz_lo = INFINITY, vz_hi = -INFINITY, dz_worst = 0;
        for (int step = 1; step <= rest + ride; step++) {
            if (step == rest + 1) dBodySetLinearVel(b, 0, 0, V_UP);
            if (!CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "%s: step %d: %s", name, step,
                       dClothGetLastError(c)))
                break;
            double md = min_sd(&s, c);
            if (md < worst) worst = md, worst_step = step;
            if (step > rest + ride - window) {
                double vz = cloth_velocities(dClothGetCore(c))[3 * ctr + 2];
                double dz = dClothGetPositions(c)[3 * ctr + 2] - (shape_top(&s) + th);
                vz_lo = fmin(vz_lo, vz);
                vz_hi = fmax(vz_hi, vz);
                dz_worst = fabs(dz) > fabs(dz_worst) ? dz : dz_worst;
                if (!(fabs(vz - V_UP) <= RIDE_REL * V_UP) && bad_v++ < 3)
                    CHECK(0, "%s: step %d: the centre vertex rises at %.5f m/s, the body at %g m/s", name, step, vz,
                          V_UP);
                if (!(fabs(dz) <= tol) && bad_h++ < 3)
                    CHECK(0, "%s: step %d: the centre vertex is %.3g mm above top + thickness", name, step, 1e3 * dz);
            }
        }
        printf("%-11s worst signed distance %+7.3f mm (step %d); over the last %g s the centre vertex rose at "
               "%.5f..%.5f m/s (body %g m/s), at most %+.3f mm off top + thickness; body rose %.4f m in %g s\n",
               name, 1e3 * worst, worst_step, RIDE_WINDOW, vz_lo, vz_hi, V_UP, 1e3 * dz_worst,
               dBodyGetPosition(b)[2] - body_half[2], ride * H);
        CHECK(worst >= -tol, "%s: a vertex went %.3g mm inside the box (step %d; tolerance %.3g mm)", name,
              -1e3 * worst, worst_step, 1e3 * tol);
        CHECK(dClothGetStats(c)->contacts > 0, "%s: no contacts in the last step", name);
        dClothDestroy(c);
    }
    dGeomDestroy(g);
    dBodyDestroy(b);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

int main(void)
{
    dInitODE2(0);
    build_box_data();
    check_box_data();
    for (int k = 0; k < NKINDS; k++) {
        run_class(k);
        fflush(stdout);
    }
    run_dynamic();
    run_kinematic();
    dCloseODE();
    return check_summary();
}
