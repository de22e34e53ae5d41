/* Physics: internal forces conserve linear and angular momentum.
 *
 * Every link force (spring and damper) acts along the link, equal and
 * opposite on its two ends, so for any state the internal forces
 * (cloth_internal_forces: springs + damping, no gravity) satisfy
 *     sum_i f_i = 0                 |sum| <= 1e-10 sum_i |f_i|
 *     sum_i x_i x f_i = 0           |sum| <= 1e-10 sum_i |x_i| |f_i|
 * We check this on random states: positions near the rest grid (squeezed so
 * that many interlaced links are plastic, then moved again so plastic links
 * sit on both sides of l1), random velocities, for cotton, wool, a material
 * with alpha = 1 and an elastic one, in several grid sizes and far from the
 * origin.
 *
 * And the related invariances, which are what conservation means for a
 * model: translating all positions, or adding a rigid-body velocity
 * V + w x x_i, leaves the internal forces unchanged (the damping only sees
 * the rate of change of link lengths, which a rigid motion does not change);
 * rotating positions and velocities by R rotates the forces by R.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double norm3(const double a[3]) { return sqrt(dot3(a, a)); }
static void cross3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* relative max-norm difference of two force arrays */
static double rel_diff(const double *a, const double *b, int m)
{
    double e = 0, s = 0;
    for (int k = 0; k < m; k++) {
        if (fabs(a[k] - b[k]) > e) e = fabs(a[k] - b[k]);
        if (fabs(a[k]) > s) s = fabs(a[k]);
    }
    return s > 0 ? e / s : e;
}

static void run_case(const char *name, int R, int C, cloth_material mat, const double shift[3], uint64_t seed)
{
    rng r = rng_seed(seed);
    cloth_desc d = cloth_default_desc();
    cloth *c = NULL;
    cloth_error err;
    int n, nplastic;
    double *x, *v, *f, *f2, *x2, *v2, *rest, u[3], spacing;
    long failed_before = check_failures();
    double worst_f = 0, worst_t = 0;

    d.rows = R;
    d.cols = C;
    d.material = mat;
    for (int a = 0; a < 3; a++) d.origin[a] += shift[a];
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK && c, "%s: cloth_create: %s", name, err.message)) return;
    n = cloth_vertex_count(c);
    spacing = d.width / (C - 1);
    x = malloc(sizeof(double) * 3 * n);
    v = malloc(sizeof(double) * 3 * n);
    f = malloc(sizeof(double) * 3 * n);
    f2 = malloc(sizeof(double) * 3 * n);
    x2 = malloc(sizeof(double) * 3 * n);
    v2 = malloc(sizeof(double) * 3 * n);
    rest = malloc(sizeof(double) * 3 * n);
    memcpy(rest, cloth_positions(c), sizeof(double) * 3 * n);
    for (int a = 0; a < 3; a++) u[a] = (rest[3 + a] - rest[a]) / spacing;

    nplastic = 0;
    for (int trial = 0; trial < 5; trial++) {
        double sumf[3] = {0, 0, 0}, sumt[3] = {0, 0, 0}, absf = 0, abst = 0;
        double ctr[3] = {0, 0, 0};
        /* from the rest grid: squeeze toward the middle column along u
         * (trial 0 not squeezed) and add noise */
        {
            double squeeze = trial == 0 ? 1.0 : rng_range(&r, 0.6, 0.95);
            for (int i = 0; i < R; i++)
                for (int j = 0; j < C; j++) {
                    int k = i * C + j;
                    double cu = (j - 0.5 * (C - 1)) * spacing * (squeeze - 1.0);
                    for (int a = 0; a < 3; a++)
                        x[3 * k + a] = rest[3 * k + a] + cu * u[a] + rng_range(&r, -0.25, 0.25) * spacing;
                }
        }
        CHECK(cloth_set_positions(c, x) == CLOTH_OK, "%s: set_positions: %s", name, cloth_last_error(c));
        nplastic = cloth_update_plastic(c);
        for (int k = 0; k < 3 * n; k++) x[k] += rng_range(&r, -0.05, 0.05) * spacing;
        for (int k = 0; k < 3 * n; k++) v[k] = rng_range(&r, -2, 2);
        CHECK(cloth_set_positions(c, x) == CLOTH_OK, "%s: set_positions: %s", name, cloth_last_error(c));
        CHECK(cloth_set_velocities(c, v) == CLOTH_OK, "%s: set_velocities: %s", name, cloth_last_error(c));
        if (!CHECK(cloth_internal_forces(c, f) == CLOTH_OK, "%s: internal_forces: %s", name, cloth_last_error(c)))
            continue;

        for (int i = 0; i < n; i++) {
            double t[3];
            cross3(x + 3 * i, f + 3 * i, t);
            for (int a = 0; a < 3; a++) {
                sumf[a] += f[3 * i + a];
                sumt[a] += t[a];
            }
            absf += norm3(f + 3 * i);
            abst += norm3(x + 3 * i) * norm3(f + 3 * i);
            for (int a = 0; a < 3; a++) ctr[a] += x[3 * i + a] / n;
        }
        CHECK(absf > 0, "%s: all internal forces zero on a random state", name);
        CHECK(norm3(sumf) <= 1e-10 * absf, "%s trial %d: sum of internal forces (%g %g %g), |.| %.3g > 1e-10 * %.3g",
              name, trial, sumf[0], sumf[1], sumf[2], norm3(sumf), absf);
        CHECK(norm3(sumt) <= 1e-10 * abst, "%s trial %d: sum of torques x_i x f_i (%g %g %g), |.| %.3g > 1e-10 * %.3g",
              name, trial, sumt[0], sumt[1], sumt[2], norm3(sumt), abst);
        if (absf > 0 && norm3(sumf) / absf > worst_f) worst_f = norm3(sumf) / absf;
        if (abst > 0 && norm3(sumt) / abst > worst_t) worst_t = norm3(sumt) / abst;

        /* translation of positions: forces unchanged */
        {
            double T[3] = {rng_range(&r, -3, 3), rng_range(&r, -3, 3), rng_range(&r, -3, 3)}, e;
            for (int i = 0; i < n; i++)
                for (int a = 0; a < 3; a++) x2[3 * i + a] = x[3 * i + a] + T[a];
            cloth_set_positions(c, x2);
            cloth_internal_forces(c, f2);
            e = rel_diff(f, f2, 3 * n);
            CHECK(e <= 1e-9, "%s trial %d: translating the cloth changed internal forces by %.3g (relative)", name,
                  trial, e);
            cloth_set_positions(c, x);
        }
        /* rigid-body velocity added: forces unchanged */
        {
            double V[3], w[3], e;
            for (int a = 0; a < 3; a++) V[a] = rng_range(&r, -2, 2), w[a] = rng_range(&r, -3, 3);
            for (int i = 0; i < n; i++) {
                double rel[3], wx[3];
                for (int a = 0; a < 3; a++) rel[a] = x[3 * i + a] - ctr[a];
                cross3(w, rel, wx);
                for (int a = 0; a < 3; a++) v2[3 * i + a] = v[3 * i + a] + V[a] + wx[a];
            }
            cloth_set_velocities(c, v2);
            cloth_internal_forces(c, f2);
            e = rel_diff(f, f2, 3 * n);
            CHECK(e <= 1e-9, "%s trial %d: adding a rigid-body velocity changed internal forces by %.3g", name, trial,
                  e);
            cloth_set_velocities(c, v);
        }
        /* rotation about the centre: forces rotate */
        {
            double axis[3], ang = rng_range(&r, 0.3, 3.0), Rm[9], e = 0, s = 0;
            rng_unit_vector(&r, axis);
            {
                double cs = cos(ang), sn = sin(ang), t = 1 - cs, X = axis[0], Y = axis[1], Z = axis[2];
                double M[9] = {t * X * X + cs,     t * X * Y - sn * Z, t * X * Z + sn * Y,
                               t * X * Y + sn * Z, t * Y * Y + cs,     t * Y * Z - sn * X,
                               t * X * Z - sn * Y, t * Y * Z + sn * X, t * Z * Z + cs};
                memcpy(Rm, M, sizeof M);
            }
            for (int i = 0; i < n; i++)
                for (int a = 0; a < 3; a++) {
                    x2[3 * i + a] = ctr[a];
                    v2[3 * i + a] = 0;
                    for (int b = 0; b < 3; b++) {
                        x2[3 * i + a] += Rm[3 * a + b] * (x[3 * i + b] - ctr[b]);
                        v2[3 * i + a] += Rm[3 * a + b] * v[3 * i + b];
                    }
                }
            cloth_set_positions(c, x2);
            cloth_set_velocities(c, v2);
            cloth_internal_forces(c, f2);
            for (int i = 0; i < n; i++)
                for (int a = 0; a < 3; a++) {
                    double rf = 0;
                    for (int b = 0; b < 3; b++) rf += Rm[3 * a + b] * f[3 * i + b];
                    if (fabs(rf - f2[3 * i + a]) > e) e = fabs(rf - f2[3 * i + a]);
                    if (fabs(rf) > s) s = fabs(rf);
                }
            CHECK(e <= 1e-9 * s, "%s trial %d: rotating the state does not rotate the forces (err %.3g of %.3g)", name,
                  trial, e, s);
            cloth_set_positions(c, x);
            cloth_set_velocities(c, v);
        }
    }
    printf("%-26s %2dx%-2d: %4d plastic links (last trial); worst |sum f|/sum|f| %.2e, |sum x x f|/sum|x||f| %.2e%s\n",
           name, R, C, nplastic, worst_f, worst_t, check_failures() > failed_before ? "  (FAILURES)" : "");
    if (mat.alpha > 0.5)
        CHECK(nplastic > 0, "%s: the squeezed states made no link plastic (alpha %g)", name, mat.alpha);
    free(x);
    free(v);
    free(f);
    free(f2);
    free(x2);
    free(v2);
    free(rest);
    cloth_destroy(c);
}

int main(void)
{
    const double here[3] = {0, 0, 0}, far[3] = {120.0, -75.0, 33.0};
    cloth_material cotton = cloth_material_preset(CLOTH_COTTON);
    cloth_material wool = cloth_material_preset(CLOTH_WOOL);
    cloth_material elastic = cloth_material_preset(CLOTH_ELASTIC);
    cloth_material yieldy = cotton;
    yieldy.alpha = 1.0;
    /* make sure damping is on, so the damper's part is tested too */
    if (cotton.c_t <= 0) cotton.c_t = 0.5;
    if (cotton.c_b <= 0) cotton.c_b = 0.05;
    if (wool.c_t <= 0) wool.c_t = 0.5;
    if (wool.c_b <= 0) wool.c_b = 0.05;
    if (yieldy.c_t <= 0) yieldy.c_t = 0.5;
    if (yieldy.c_b <= 0) yieldy.c_b = 0.05;
    if (elastic.c_t <= 0) elastic.c_t = 0.5;
    if (elastic.c_b <= 0) elastic.c_b = 0.05;

    run_case("cotton", 9, 11, cotton, here, 0x5EED0201u);
    run_case("wool", 6, 5, wool, here, 0x5EED0202u);
    run_case("alpha = 1", 21, 21, yieldy, here, 0x5EED0203u);
    run_case("elastic", 7, 8, elastic, here, 0x5EED0204u);
    run_case("cotton, far from origin", 10, 9, cotton, far, 0x5EED0205u);
    return check_summary();
}
