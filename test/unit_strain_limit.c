/* Unit: the elongation-limit projection (strain_limit.c, Goldenthal et al.
 * 2007) against closed forms on tiny cloths, called directly through
 * internal.h with a filter S built here (identity for a free vertex, 0 for a
 * pin, I - n n^T for a plane, a a^T for a line, as build_constraints in
 * step.c does) and the cloth's constraints set to match.
 *
 * The projection is the mass-weighted least change of the positions that
 * brings every sequential link to d <= lmax = (1 + delta) l0, with
 * dx_i = -W_i G^T lambda, W_i = S_i / m_i; velocities change by dx / cfac.
 * Cases (3 x 3 cloth, 1 m x 1 m, l0 0.5 m and 0.5 sqrt 2 m, delta 0.03):
 *   1. one link over (d = 1.05 l0) between two free vertices whose masses
 *      (0.3 and 0.07 kg, set in c->mass) differ: exactly one link reported;
 *      the ends move along u by m_j/(m_i+m_j) C and -m_i/(m_i+m_j) C
 *      (C = d - lmax) to 1e-7 of C, every other vertex bitwise unchanged, the
 *      link lands at lmax (1 +- 1e-8), sum m_i dx_i = 0 and momentum
 *      unchanged (1e-12 of sum m_i |dx_i|);
 *   2. the same link with vertex 0 pinned: the pin is bitwise unchanged (x
 *      and v) and the free end lands at x_0 + lmax u_original (1e-9 lmax);
 *   3. vertex 1 on a plane (normal not along the link), vertex 0 pinned: dx_1
 *      . n = 0 (1e-12 |dx_1|), and vertex 1 lands on the closed form: the
 *      point nearest x_1 of the circle where the plane through x_1 meets the
 *      sphere of radius lmax about x_0;
 *      the same on a line: dx_1 parallel to the line and landing at the
 *      nearer intersection of the line with that sphere;
 *   4. in every case v changes by exactly dx / cfac (1e-12 relative; cfac
 *      0.01 and 2/3 0.01).
 * And: no link over -> x and v bitwise unchanged, return 0; iterations 0 ->
 * the count, nothing changed; random 5 x 5 cloths (random masses, stretched
 * 3 % or 8 % with noise, 38-70 links over; see case_random): free, and with
 * a pin, a plane and a line, after 100 Newton steps every link <= lmax
 * (1 + 1e-8), the pin bitwise, the plane and line vertices on their
 * constraint (1e-11 m), centre of mass and momentum unchanged (free: 1e-12,
 * or 1e-10 when every link is over), dv = dx / cfac; with an infeasible line
 * the constraints still hold, the result is finite and the summed squared
 * excess does not rise. The per-vertex scratch is left zeroed. And through
 * cloth_step (gravity 0, k_t tiny, k_delta 0, an outward initial velocity
 * that stretches every link ~10 %): all 20 links limited, every link <= lmax
 * (1 + 1e-8), x1 = x0 + h v1 (1e-12), momentum unchanged (1e-9).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "check.h"

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double norm3(const double a[3]) { return sqrt(dot3(a, a)); }
static double dist3(const double *a, const double *b)
{
    double w[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    return norm3(w);
}

static cloth *make(int rows, int cols)
{
    cloth_desc d = cloth_default_desc();
    cloth *c = NULL;
    cloth_error err;
    d.rows = rows;
    d.cols = cols;
    d.width = 1.0;
    d.height = 1.0;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK && c, "cloth_create: %s", err.message)) return NULL;
    CHECK(d.material.delta == 0.03, "the default delta is %g; the cases below assume 0.03", d.material.delta);
    return c;
}

/* S as build_constraints (step.c) makes it, from the cloth's constraints. */
static void build_S(const cloth *c, double *S)
{
    for (int i = 0; i < cloth_vertex_count(c); i++) {
        cloth_constraint k;
        double *Si = S + 9 * (size_t)i;
        cloth_get_constraint(c, i, &k);
        for (int r = 0; r < 3; r++)
            for (int s = 0; s < 3; s++) {
                double id = r == s ? 1.0 : 0.0, nn = k.axis[r] * k.axis[s];
                Si[3 * r + s] = k.ndof == 0 ? id : k.ndof == 3 ? 0.0 : k.ndof == 1 ? id - nn : nn;
            }
    }
}

static double limit_of(const cloth *c) { return 1.0 + cloth_get_desc(c).material.delta; }

/* Number of sequential links with d > lmax (1 + rel). */
static int count_over(const cloth *c, const double *x, double rel)
{
    int n = 0;
    for (int e = 0; e < cloth_link_count(c, CLOTH_SEQUENTIAL); e++) {
        cloth_link L;
        cloth_get_link(c, CLOTH_SEQUENTIAL, e, &L);
        if (dist3(x + 3 * L.i, x + 3 * L.j) > limit_of(c) * L.rest * (1.0 + rel)) n++;
    }
    return n;
}

/* The checks every case shares: dv = dx / cfac (rel 1e-12 of the largest
 * |dx| / cfac), and, if conserve > 0, sum m dx = 0 and sum m dv = 0 (to
 * `conserve` of sum m |dx|, resp. / cfac). */
static void check_common(const cloth *c, const char *what, const double *x0, const double *x, const double *v0,
                         const double *v, double cfac, double conserve)
{
    int n = cloth_vertex_count(c);
    const double *m = cloth_masses(c);
    double dxmax = 0.0, err = 0.0, mdx[3] = {0, 0, 0}, mdv[3] = {0, 0, 0}, scale = 0.0;
    for (int i = 0; i < n; i++) {
        double dxi[3];
        for (int a = 0; a < 3; a++) {
            double dx = x[3 * i + a] - x0[3 * i + a], dv = v[3 * i + a] - v0[3 * i + a];
            dxi[a] = dx;
            if (fabs(dx) > dxmax) dxmax = fabs(dx);
            if (fabs(dv - dx / cfac) > err) err = fabs(dv - dx / cfac);
            mdx[a] += m[i] * dx;
            mdv[a] += m[i] * dv;
        }
        scale += m[i] * norm3(dxi);
    }
    CHECK(dxmax > 0.0, "%s: nothing moved", what);
    CHECK(err <= 1e-12 * dxmax / cfac, "%s: dv differs from dx / cfac by %.3g (max |dx| / cfac %.3g)", what, err,
          dxmax / cfac);
    if (conserve > 0) {
        CHECK(norm3(mdx) <= conserve * scale,
              "%s: the centre of mass moved: |sum m dx| %.3g, sum m |dx| %.3g (rel "
              "%.3g > %.3g)",
              what, norm3(mdx), scale, norm3(mdx) / scale, conserve);
        CHECK(norm3(mdv) <= conserve * scale / cfac, "%s: momentum changed by %.3g (sum m |dx| / cfac %.3g)", what,
              norm3(mdv), scale / cfac);
    }
}

/* The scratch oc_strain_limit keeps zeroed between calls. */
static void check_scratch(const cloth *c, const char *what)
{
    int nz = 0;
    for (int k = 0; k < 3 * c->n; k++) nz += c->sl_vtx[k] != 0.0;
    CHECK(nz == 0, "%s: oc_strain_limit left %d non-zero entries in its per-vertex scratch", what, nz);
}

/* A 3 x 3 cloth at rest with vertex 0 moved so that link 0-1 (the first
 * row's first link) is d = 1.05 l0 and no other link is over; random
 * velocities. U, V, N: the grid's frame. */
typedef struct scene {
    cloth *c;
    double *x, *v, *x0, *v0, *S;
    double U[3], V[3], N[3], l0;
} scene;

static int scene_make(scene *s, double m0, double m1, uint64_t seed)
{
    rng r = rng_seed(seed);
    memset(s, 0, sizeof *s);
    s->c = make(3, 3);
    if (!s->c) return 0;
    int n = 9;
    s->x = malloc(3 * n * sizeof(double));
    s->v = malloc(3 * n * sizeof(double));
    s->x0 = malloc(3 * n * sizeof(double));
    s->v0 = malloc(3 * n * sizeof(double));
    s->S = malloc(9 * n * sizeof(double));
    memcpy(s->x, cloth_positions(s->c), 3 * n * sizeof(double));
    for (int a = 0; a < 3; a++) {
        s->U[a] = s->x[3 + a] - s->x[a];
        s->V[a] = s->x[9 + a] - s->x[a];
    }
    s->l0 = norm3(s->U);
    {
        double lv = norm3(s->V);
        for (int a = 0; a < 3; a++) {
            s->U[a] /= s->l0;
            s->V[a] /= lv;
        }
    }
    s->N[0] = s->U[1] * s->V[2] - s->U[2] * s->V[1];
    s->N[1] = s->U[2] * s->V[0] - s->U[0] * s->V[2];
    s->N[2] = s->U[0] * s->V[1] - s->U[1] * s->V[0];
    /* vertex 0 to x_0 - a U + 0.1 l0 V + 0.06 l0 N with |x_1 - x_0| = 1.05 l0 */
    {
        double t = 0.1 * s->l0, w = 0.06 * s->l0, d = 1.05 * s->l0;
        double along = sqrt(d * d - t * t - w * w); /* = l0 + a */
        for (int a = 0; a < 3; a++) s->x[a] += -(along - s->l0) * s->U[a] + t * s->V[a] + w * s->N[a];
    }
    for (int k = 0; k < 3 * n; k++) s->v[k] = rng_range(&r, -1, 1);
    s->c->mass[0] = m0; /* unequal masses (internal: the test sets them) */
    s->c->mass[1] = m1;
    memcpy(s->x0, s->x, 3 * n * sizeof(double));
    memcpy(s->v0, s->v, 3 * n * sizeof(double));
    return 1;
}

static void scene_free(scene *s)
{
    cloth_destroy(s->c);
    free(s->x);
    free(s->v);
    free(s->x0);
    free(s->v0);
    free(s->S);
}

/* Everything but the listed vertices bitwise unchanged (x and v). */
static void check_others_still(const scene *s, const char *what, int a, int b)
{
    int moved = 0;
    for (int i = 0; i < 9; i++) {
        if (i == a || i == b) continue;
        if (memcmp(s->x + 3 * i, s->x0 + 3 * i, 3 * sizeof(double)) != 0 ||
            memcmp(s->v + 3 * i, s->v0 + 3 * i, 3 * sizeof(double)) != 0)
            moved++;
    }
    CHECK(moved == 0, "%s: %d vertices outside the over-stretched link moved", what, moved);
}

/* 1: one link over between two free vertices of unequal masses. */
static void case_free_pair(double cfac)
{
    scene s;
    const double m0 = 0.3, m1 = 0.07;
    if (!scene_make(&s, m0, m1, 0x5EED0601u)) return;
    double lmax = limit_of(s.c) * s.l0, d = dist3(s.x, s.x + 3), C = d - lmax, u[3];
    for (int a = 0; a < 3; a++) u[a] = (s.x[3 + a] - s.x[a]) / d;
    CHECK(count_over(s.c, s.x, 0.0) == 1, "case 1 setup: %d links over, want 1", count_over(s.c, s.x, 0.0));
    build_S(s.c, s.S);
    int first = oc_strain_limit(s.c, s.x, s.v, s.S, cfac, 20);
    CHECK(first == 1, "case 1: oc_strain_limit reports %d links over, want 1", first);
    double d1 = dist3(s.x, s.x + 3);
    CHECK(d1 <= lmax * (1 + 1e-8) && d1 >= lmax * (1 - 1e-8), "case 1: link at %.17g, want lmax %.17g", d1, lmax);
    CHECK(count_over(s.c, s.x, 1e-8) == 0, "case 1: %d links over after", count_over(s.c, s.x, 1e-8));
    /* closed form: dx_0 = m1/(m0+m1) C u, dx_1 = -m0/(m0+m1) C u */
    {
        double e0 = 0.0, e1 = 0.0;
        for (int a = 0; a < 3; a++) {
            double w0 = s.x[a] - s.x0[a] - m1 / (m0 + m1) * C * u[a];
            double w1 = s.x[3 + a] - s.x0[3 + a] + m0 / (m0 + m1) * C * u[a];
            e0 += w0 * w0;
            e1 += w1 * w1;
        }
        CHECK(sqrt(e0) <= 1e-7 * C && sqrt(e1) <= 1e-7 * C,
              "case 1: dx_0 off the closed form m1/(m0+m1) C u by %.3g, dx_1 off -m0/(m0+m1) C u by %.3g (C %.3g)",
              sqrt(e0), sqrt(e1), C);
    }
    check_others_still(&s, "case 1", 0, 1);
    check_common(s.c, "case 1", s.x0, s.x, s.v0, s.v, cfac, 1e-12);
    check_scratch(s.c, "case 1");
    printf("%-44s C %.4f m: |x_1 - x_0| - lmax = %.2e, dx_0 %.6f, dx_1 %.6f\n", "1 free pair (masses 0.3, 0.07)", C,
           d1 - lmax, dist3(s.x, s.x0), dist3(s.x + 3, s.x0 + 3));

    /* nothing over now: a second call changes nothing, bitwise */
    {
        double *xs = malloc(27 * sizeof(double)), *vs = malloc(27 * sizeof(double));
        memcpy(xs, s.x, 27 * sizeof(double));
        memcpy(vs, s.v, 27 * sizeof(double));
        int again = oc_strain_limit(s.c, s.x, s.v, s.S, cfac, 20);
        CHECK(again == 0 && memcmp(xs, s.x, 27 * sizeof(double)) == 0 && memcmp(vs, s.v, 27 * sizeof(double)) == 0,
              "case 1: a second projection (nothing over) returned %d or changed the state", again);
        free(xs);
        free(vs);
    }
    scene_free(&s);

    /* iterations 0: the count, and nothing changes */
    if (!scene_make(&s, m0, m1, 0x5EED0601u)) return;
    build_S(s.c, s.S);
    {
        int k = oc_strain_limit(s.c, s.x, s.v, s.S, cfac, 0);
        CHECK(k == 1 && memcmp(s.x, s.x0, 27 * sizeof(double)) == 0 && memcmp(s.v, s.v0, 27 * sizeof(double)) == 0,
              "0 iterations: returned %d (want 1) or changed the state", k);
    }
    scene_free(&s);
}

/* 2: vertex 0 pinned: it stays, bitwise; vertex 1 lands at x_0 + lmax u. */
static void case_pinned(double cfac)
{
    scene s;
    if (!scene_make(&s, 0.3, 0.07, 0x5EED0602u)) return;
    CHECK(cloth_pin(s.c, 0, s.x) == CLOTH_OK, "pin: %s", cloth_last_error(s.c));
    double lmax = limit_of(s.c) * s.l0, d = dist3(s.x, s.x + 3), u[3];
    for (int a = 0; a < 3; a++) u[a] = (s.x[3 + a] - s.x[a]) / d;
    build_S(s.c, s.S);
    int first = oc_strain_limit(s.c, s.x, s.v, s.S, cfac, 20);
    CHECK(first == 1, "case 2: oc_strain_limit reports %d links over, want 1", first);
    CHECK(memcmp(s.x, s.x0, 3 * sizeof(double)) == 0 && memcmp(s.v, s.v0, 3 * sizeof(double)) == 0,
          "case 2: the pinned vertex moved: dx (%.3g %.3g %.3g)", s.x[0] - s.x0[0], s.x[1] - s.x0[1], s.x[2] - s.x0[2]);
    double e = 0.0;
    for (int a = 0; a < 3; a++) {
        double w = s.x[3 + a] - (s.x0[a] + lmax * u[a]);
        e += w * w;
    }
    CHECK(sqrt(e) <= 1e-9 * lmax, "case 2: the free end is %.3g m from x_0 + lmax u", sqrt(e));
    check_others_still(&s, "case 2", 0, 1);
    check_common(s.c, "case 2", s.x0, s.x, s.v0, s.v, cfac, 0);
    check_scratch(s.c, "case 2");
    printf("%-44s free end off x_0 + lmax u by %.2e m\n", "2 pinned end", sqrt(e));
    scene_free(&s);
}

/* 3: vertex 1 on a plane (ndof 1) or a line (ndof 2), vertex 0 pinned. */
static void case_plane_line(double cfac, int ndof)
{
    scene s;
    const char *what = ndof == 1 ? "case 3 (plane)" : "case 3 (line)";
    if (!scene_make(&s, 0.3, 0.07, 0x5EED0603u + (uint64_t)ndof)) return;
    CHECK(cloth_pin(s.c, 0, s.x) == CLOTH_OK, "pin: %s", cloth_last_error(s.c));
    /* the axis: a mix of U, V, N, so neither along nor across the link */
    cloth_constraint k;
    memset(&k, 0, sizeof k);
    k.vertex = 1;
    k.ndof = ndof;
    for (int a = 0; a < 3; a++) {
        k.axis[a] = ndof == 1 ? 0.6 * s.U[a] + 0.3 * s.V[a] + 0.74 * s.N[a]
                              : 0.9 * s.U[a] + 0.35 * s.V[a] - 0.25 * s.N[a];
        k.target[a] = s.x[3 + a];
    }
    CHECK(cloth_set_constraint(s.c, &k) == CLOTH_OK, "set_constraint: %s", cloth_last_error(s.c));
    cloth_get_constraint(s.c, 1, &k); /* the normalised axis */
    double lmax = limit_of(s.c) * s.l0, *x0 = s.x0, *x1 = s.x0 + 3, want[3];
    double w[3] = {x1[0] - x0[0], x1[1] - x0[1], x1[2] - x0[2]};
    if (ndof == 1) {
        /* plane through x_1, normal n: centre p = x_0 + (w.n) n, radius
         * sqrt(lmax^2 - (w.n)^2); nearest point to x_1: along x_1 - p */
        double h = dot3(w, k.axis), p[3], q[3];
        for (int a = 0; a < 3; a++) p[a] = x0[a] + h * k.axis[a];
        for (int a = 0; a < 3; a++) q[a] = x1[a] - p[a];
        double r = sqrt(lmax * lmax - h * h), nq = norm3(q);
        for (int a = 0; a < 3; a++) want[a] = p[a] + r * q[a] / nq;
    } else {
        /* line x_1 + t a: |w + t a| = lmax, the root of smaller |t| */
        double b = dot3(w, k.axis), cc = dot3(w, w) - lmax * lmax;
        double t1 = -b + sqrt(b * b - cc), t2 = -b - sqrt(b * b - cc);
        double t = fabs(t1) < fabs(t2) ? t1 : t2;
        for (int a = 0; a < 3; a++) want[a] = x1[a] + t * k.axis[a];
    }
    build_S(s.c, s.S);
    int first = oc_strain_limit(s.c, s.x, s.v, s.S, cfac, 50);
    CHECK(first == 1, "%s: oc_strain_limit reports %d links over, want 1", what, first);
    CHECK(memcmp(s.x, s.x0, 3 * sizeof(double)) == 0 && memcmp(s.v, s.v0, 3 * sizeof(double)) == 0,
          "%s: the pinned vertex moved", what);
    double dx[3] = {s.x[3] - x1[0], s.x[4] - x1[1], s.x[5] - x1[2]}, ndx = norm3(dx);
    if (ndof == 1) {
        CHECK(fabs(dot3(dx, k.axis)) <= 1e-12 * ndx, "%s: dx_1 . n = %.3g (|dx_1| %.3g): left the plane", what,
              dot3(dx, k.axis), ndx);
    } else {
        double along = dot3(dx, k.axis), perp[3];
        for (int a = 0; a < 3; a++) perp[a] = dx[a] - along * k.axis[a];
        CHECK(norm3(perp) <= 1e-12 * ndx, "%s: dx_1 has %.3g across the line (|dx_1| %.3g)", what, norm3(perp), ndx);
    }
    double d1 = dist3(s.x, s.x + 3), e = dist3(s.x + 3, want);
    CHECK(d1 <= lmax * (1 + 1e-8) && d1 >= lmax * (1 - 1e-8), "%s: link at %.17g, want lmax %.17g", what, d1, lmax);
    CHECK(e <= 1e-8 * lmax, "%s: vertex 1 is %.3g m from the closed-form landing point", what, e);
    check_others_still(&s, what, 0, 1);
    check_common(s.c, what, s.x0, s.x, s.v0, s.v, cfac, 0);
    check_scratch(s.c, what);
    printf("%-44s |dx_1| %.5f, off the closed form by %.2e m\n",
           ndof == 1 ? "3 plane (vertex 0 pinned)" : "3 line (vertex 0 pinned)", ndx, e);
    scene_free(&s);
}

/* Sum of squared excess lengths (d - lmax)^2 over the links over lmax. */
static double excess2(const cloth *c, const double *x)
{
    double sum = 0.0;
    for (int e = 0; e < cloth_link_count(c, CLOTH_SEQUENTIAL); e++) {
        cloth_link L;
        cloth_get_link(c, CLOTH_SEQUENTIAL, e, &L);
        double d = dist3(x + 3 * L.i, x + 3 * L.j), lmax = limit_of(c) * L.rest;
        if (d > lmax) sum += (d - lmax) * (d - lmax);
    }
    return sum;
}

enum { R_FREE, R_CONSTRAINED, R_INFEASIBLE };

/* Random 5 x 5 cloths (random masses 0.01-0.1 kg) stretched by `stretch`
 * about their centre, with noise, so that many links are over.
 *   R_FREE: no constraints; the centre of mass and momentum stay (to
 *     `conserve`; when every link is over, the first link system is
 *     singular - 72 rows, at most 69 independent - and the damped
 *     multipliers reach ~100 for a step of ~0.06, so rounding leaves
 *     ~1e-12 of the step).
 *   R_CONSTRAINED: a pin at 0, a plane (random normal) at 12, a line at 24
 *     whose direction is within 37 degrees of the way to vertex 0, so the
 *     limit can be met: it is, the pin stays bitwise, the others stay on
 *     their plane and line to 1e-11 m (rounding).
 *   R_INFEASIBLE: the line at 24 perpendicular to x_24 - x_0, which is
 *     longer than the 4 diagonal links between them can reach
 *     (4 lmax_diag): no state meets the limit. The projection must still
 *     honour the constraints, stay finite, keep dv = dx / cfac and not
 *     increase the summed squared excess (its backtracking keeps only steps
 *     that lower it). */
static void case_random(double cfac, int mode, double stretch, double conserve, uint64_t seed)
{
    rng r = rng_seed(seed);
    cloth *c = make(5, 5);
    if (!c) return;
    char what[96];
    snprintf(what, sizeof what, "random 5x5 x%.2f (%s)", stretch,
             mode == R_FREE          ? "free"
             : mode == R_CONSTRAINED ? "pin, plane, line"
                                     : "infeasible line");
    int n = 25;
    double *x = malloc(3 * n * sizeof(double)), *v = malloc(3 * n * sizeof(double));
    double *x0 = malloc(3 * n * sizeof(double)), *v0 = malloc(3 * n * sizeof(double));
    double *S = malloc(9 * n * sizeof(double)), cen[3] = {0, 0, 0}, spacing = 0.25;
    memcpy(x, cloth_positions(c), 3 * n * sizeof(double));
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) cen[a] += x[3 * i + a] / n;
    for (int i = 0; i < n; i++) {
        c->mass[i] = rng_range(&r, 0.01, 0.1);
        for (int a = 0; a < 3; a++) {
            x[3 * i + a] = cen[a] + stretch * (x[3 * i + a] - cen[a]) + rng_range(&r, -0.04, 0.04) * spacing;
            v[3 * i + a] = rng_range(&r, -1, 1);
        }
    }
    if (mode != R_FREE) {
        cloth_constraint k;
        double w[3] = {x[0] - x[72], x[1] - x[73], x[2] - x[74]}, nw = norm3(w), ru[3];
        memset(&k, 0, sizeof k);
        CHECK(cloth_pin(c, 0, x) == CLOTH_OK, "pin: %s", cloth_last_error(c));
        k.vertex = 12;
        k.ndof = 1;
        rng_unit_vector(&r, k.axis);
        memcpy(k.target, x + 36, sizeof k.target);
        CHECK(cloth_set_constraint(c, &k) == CLOTH_OK, "plane: %s", cloth_last_error(c));
        k.vertex = 24;
        k.ndof = 2;
        rng_unit_vector(&r, ru);
        if (mode == R_CONSTRAINED) {
            for (int a = 0; a < 3; a++) k.axis[a] = w[a] / nw + 0.6 * ru[a];
        } else {
            double t = dot3(ru, w) / (nw * nw);
            for (int a = 0; a < 3; a++) k.axis[a] = ru[a] - t * w[a]; /* perpendicular to w */
            CHECK(nw > 4.0 * limit_of(c) * spacing * sqrt(2.0) * 1.01,
                  "%s setup: |x_24 - x_0| %.4f is within reach of 4 diagonals (%.4f)", what, nw,
                  4.0 * limit_of(c) * spacing * sqrt(2.0));
        }
        memcpy(k.target, x + 72, sizeof k.target);
        CHECK(cloth_set_constraint(c, &k) == CLOTH_OK, "line: %s", cloth_last_error(c));
    }
    memcpy(x0, x, 3 * n * sizeof(double));
    memcpy(v0, v, 3 * n * sizeof(double));
    int over = count_over(c, x, 0.0);
    double ex0 = excess2(c, x);
    CHECK(over >= 20, "%s setup: only %d links over", what, over);
    build_S(c, S);
    int first = oc_strain_limit(c, x, v, S, cfac, 100);
    CHECK(first == over, "%s: oc_strain_limit reports %d links over, counted %d", what, first, over);
    CHECK(oc_all_finite(x, 3 * (size_t)n) && oc_all_finite(v, 3 * (size_t)n), "%s: non-finite result", what);
    double ex1 = excess2(c, x);
    if (mode != R_INFEASIBLE) {
        int after = count_over(c, x, 1e-8);
        CHECK(after == 0, "%s: %d links still over lmax (1 + 1e-8) after 100 steps (max strain %.9f)", what, after,
              oc_max_strain_of(c, x));
    } else {
        CHECK(ex1 <= ex0, "%s: the summed squared excess rose from %.6g to %.6g", what, ex0, ex1);
    }
    if (mode != R_FREE) {
        cloth_constraint k;
        CHECK(memcmp(x, x0, 3 * sizeof(double)) == 0 && memcmp(v, v0, 3 * sizeof(double)) == 0, "%s: the pin moved",
              what);
        cloth_get_constraint(c, 12, &k);
        double dx[3] = {x[36] - x0[36], x[37] - x0[37], x[38] - x0[38]};
        /* rounding only: 1e-11 m on a 1 m cloth (the filter is applied to
         * multipliers ~100 times the step, and the infeasible case takes 100
         * steps back and forth) */
        CHECK(fabs(dot3(dx, k.axis)) <= 1e-11, "%s: the plane vertex left its plane by %.3g m (|dx| %.3g)", what,
              dot3(dx, k.axis), norm3(dx));
        cloth_get_constraint(c, 24, &k);
        double dy[3] = {x[72] - x0[72], x[73] - x0[73], x[74] - x0[74]}, al = dot3(dy, k.axis), perp[3];
        for (int a = 0; a < 3; a++) perp[a] = dy[a] - al * k.axis[a];
        CHECK(norm3(perp) <= 1e-11, "%s: the line vertex left its line by %.3g m (|dx| %.3g)", what, norm3(perp),
              norm3(dy));
    }
    check_common(c, what, x0, x, v0, v, cfac, mode == R_FREE ? conserve : 0.0);
    check_scratch(c, what);
    printf("%-44s %d links over before, max strain after %.10f, sum excess^2 %.3g -> %.3g\n", what, over,
           oc_max_strain_of(c, x), ex0, ex1);
    free(x);
    free(v);
    free(x0);
    free(v0);
    free(S);
    cloth_destroy(c);
}

/* Through cloth_step: soft, no gravity, no stiffening, an outward velocity. */
static void case_step(void)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = CLOTH_LINEARIZED; /* the linearised step's projection is tested */
    cloth *c = NULL;
    cloth_error err;
    d.rows = d.cols = 3;
    d.gravity[0] = d.gravity[1] = d.gravity[2] = 0.0;
    d.material.k_t = 1e-3;
    d.material.k_c = 1e-3;
    d.material.k_b = 1e-3;
    d.material.k_s = 1e-3;
    d.material.k_delta = 0.0;
    d.material.c_t = d.material.c_b = 0.0;
    d.solver.cg_tolerance = 1e-13;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return;
    int n = 9;
    double v[27], x0[27], cen[3] = {0, 0, 0}, h = 0.01, p0[3] = {0, 0, 0}, p1[3] = {0, 0, 0}, pscale = 0.0;
    const double *m = cloth_masses(c);
    memcpy(x0, cloth_positions(c), sizeof x0);
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) cen[a] += x0[3 * i + a] / n;
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) {
            v[3 * i + a] = 10.0 * (x0[3 * i + a] - cen[a]) + (a == 0 ? 0.3 : a == 1 ? -0.2 : 0.1);
            p0[a] += m[i] * v[3 * i + a];
        }
    for (int i = 0; i < n; i++) pscale += m[i] * norm3(v + 3 * i);
    CHECK(cloth_set_velocities(c, v) == CLOTH_OK, "set_velocities: %s", cloth_last_error(c));
    cloth_step_stats st;
    CHECK(cloth_step(c, h, &st) == CLOTH_OK, "step: %s", cloth_last_error(c));
    CHECK(st.strain_limited == cloth_link_count(c, CLOTH_SEQUENTIAL),
          "step: %d links limited, want all %d (each stretched ~10 %%)", st.strain_limited,
          cloth_link_count(c, CLOTH_SEQUENTIAL));
    double ms = cloth_max_strain(c), delta = d.material.delta;
    CHECK(ms <= (1.0 + delta) * (1.0 + 1e-8) - 1.0, "step: max strain %.10f > (1 + delta)(1 + 1e-8) - 1, delta %.3f",
          ms, delta);
    const double *x = cloth_positions(c), *v1 = cloth_velocities(c);
    double cons = 0.0;
    for (int k = 0; k < 27; k++) cons = fmax(cons, fabs(x[k] - (x0[k] + h * v1[k])));
    CHECK(cons <= 1e-12, "step: x1 - (x0 + h v1) = %.3g", cons);
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) p1[a] += m[i] * v1[3 * i + a];
    double dp[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    CHECK(norm3(dp) <= 1e-9 * pscale, "step: momentum changed by %.3g (sum m|v| %.3g)", norm3(dp), pscale);
    printf("%-44s %d links limited, max strain %.10f, |dp| %.2e\n", "through cloth_step", st.strain_limited, ms,
           norm3(dp));
    cloth_destroy(c);
}

int main(void)
{
    const double cfacs[2] = {0.01, 2.0 / 3.0 * 0.01}; /* backward Euler and BDF2 with h = 0.01 */
    for (int k = 0; k < 2; k++) {
        printf("cfac %.6f\n", cfacs[k]);
        case_free_pair(cfacs[k]);
        case_pinned(cfacs[k]);
        case_plane_line(cfacs[k], 1);
        case_plane_line(cfacs[k], 2);
        case_random(cfacs[k], R_FREE, 1.03, 1e-12, 0x5EED0611u + (uint64_t)k);
        case_random(cfacs[k], R_FREE, 1.08, 1e-10, 0x5EED0621u + (uint64_t)k);
        case_random(cfacs[k], R_CONSTRAINED, 1.08, 0.0, 0x5EED0631u + (uint64_t)k);
        case_random(cfacs[k], R_INFEASIBLE, 1.08, 0.0, 0x5EED0641u + (uint64_t)k);
    }
    case_step();
    return check_summary();
}
