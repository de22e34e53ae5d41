/* Unit: the elongation-limit projection (strain_limit.c) with a rigid body
 * solved with the cloth holding two vertices in full, called directly
 * through internal.h as in unit_strain_limit.c (oc_bodies_prepare as the step
 * calls it).
 *
 * A 3 x 3 cloth (1 m, l0 0.5 m, delta 0.03) lies flat at the step's start;
 * a 3 kg body holds vertices 0 and 1 (the first row's first link). The
 * positions handed to the projection (the step's end) differ from the
 * start: vertex 1 is 1.05 l0 from vertex 0, tilted 30 degrees out of the
 * plane (a pair held by one body that the step turned and stretched: no
 * move of the body changes its length), and the centre vertex is 0.2 m up
 * (its links 4-8 % over). Closed forms and conservation:
 *   - the held pair moves with the body: its length changes only by the
 *     second-order term of the body's linearised turn theta, at most
 *     l theta^2 / 2 (the body turns about levers from the positions the
 *     projection works on; with levers from the step's start the turn
 *     changed the length at first order: 0.525 -> 0.515 m);
 *   - every other link ends within lmax (1 + 1e-8);
 *   - momentum, cloth + body, unchanged to 1e-10 of sum m |dv| (the
 *     projection's impulses are internal);
 *   - v changes by dx / cfac at the free vertices (1e-12).
 */
#include <math.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "mpcg.h"
#include "check.h"

static double dist3(const double *a, const double *b)
{
    double w[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    return sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
}

int main(void)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 3;
    d.width = d.height = 1.0;
    d.gravity[2] = 0.0;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return check_summary();
    const int n = 9;
    const double l0 = 0.5, lim = 1.0 + d.material.delta, cfac = 0.01, h = 0.01, BODY = 3.0;
    const double *xs = cloth_positions(c), *m = cloth_masses(c);
    /* the body: centre of mass 0.1 m above the middle of the held pair */
    cloth_body b = {.mass = BODY, .inertia = {0.05, 0, 0, 0, 0.05, 0, 0, 0, 0.05}};
    for (int a = 0; a < 3; a++) b.com[a] = 0.5 * (xs[a] + xs[3 + a]) + (a == 2 ? 0.1 : 0.0);
    CHECK(cloth_set_bodies(c, &b, 1) == CLOTH_OK, "set_bodies: %s", cloth_last_error(c));
    for (int i = 0; i < 2; i++) {
        CHECK(cloth_pin(c, i, xs + 3 * i) == CLOTH_OK, "pin: %s", cloth_last_error(c));
        CHECK(cloth_hold_by_body(c, i, 0) == CLOTH_OK, "hold: %s", cloth_last_error(c));
    }
    /* S as build_constraints makes it: the held vertices have none free */
    for (int i = 0; i < n; i++) {
        double *Si = c->S + 9 * (size_t)i;
        memset(Si, 0, 9 * sizeof *Si);
        if (i >= 2) Si[0] = Si[4] = Si[8] = 1.0;
    }
    mpcg_bodies B;
    CHECK(oc_bodies_prepare(c, h, cfac, &B) != NULL, "oc_bodies_prepare: no held vertex");
    /* the step's end: vertex 1 at 1.05 l0 from vertex 0, 30 degrees up;
     * the centre 0.2 m up */
    double x[27], v[27], x0[27], v0[27], row[3], up[3] = {0, 0, 1};
    memcpy(x, xs, sizeof x);
    for (int a = 0; a < 3; a++) row[a] = (xs[3 + a] - xs[a]) / l0;
    for (int a = 0; a < 3; a++) x[3 + a] = x[a] + 1.05 * l0 * (cos(M_PI / 6) * row[a] + sin(M_PI / 6) * up[a]);
    x[3 * 4 + 2] += 0.2;
    for (int k = 0; k < 27; k++) v[k] = 0.01 * (k % 5) - 0.02;
    memcpy(x0, x, sizeof x);
    memcpy(v0, v, sizeof v);
    double pair0 = dist3(x, x + 3);
    int over = oc_strain_limit(c, x, v, c->S, cfac, 100);
    double pair1 = dist3(x, x + 3), du[6];
    cloth_body_velocity_change(c, 0, du);
    /* the body turned by theta = |dw| cfac; its held points move by the
     * linearised turn theta x r, which keeps their distance l to first
     * order: it changes by at most l theta^2 / 2 */
    double theta = cfac * sqrt(du[3] * du[3] + du[4] * du[4] + du[5] * du[5]);
    printf("%d links over; the body turned %.4f rad; the held pair %.15f -> %.15f m (l theta^2 / 2 = %.3g m)\n", over,
           theta, pair0, pair1, 0.5 * pair0 * theta * theta);
    CHECK(over >= 5, "only %d links over: the case does not test the projection", over);
    CHECK(theta > 1e-3, "the body did not turn (%.3g rad): the levers are not tested", theta);
    CHECK(fabs(pair1 - pair0) <= 0.5 * pair0 * theta * theta * (1.0 + 1e-6),
          "the held pair's length changed by %.3g m, more than l theta^2 / 2 = %.3g m", pair1 - pair0,
          0.5 * pair0 * theta * theta);
    CHECK(dist3(x0, x) > 0.0, "the held vertices did not move");
    double worst = 0.0;
    for (int e = 0; e < cloth_link_count(c, CLOTH_SEQUENTIAL); e++) {
        cloth_link L;
        cloth_get_link(c, CLOTH_SEQUENTIAL, e, &L);
        if ((L.i == 0 && L.j == 1) || (L.i == 1 && L.j == 0)) continue;
        double s = dist3(x + 3 * L.i, x + 3 * L.j) / (lim * L.rest) - 1.0;
        if (s > worst) worst = s;
    }
    printf("largest excess over lmax of the other links: %.3g\n", worst);
    CHECK(worst <= 1e-8, "a link ends %.3g over its limit", worst);
    double P[3] = {0, 0, 0}, scale = 0.0, dverr = 0.0, dvmax = 0.0;
    for (int a = 0; a < 3; a++) P[a] = BODY * du[a];
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) {
            double dv = v[3 * i + a] - v0[3 * i + a], dx = x[3 * i + a] - x0[3 * i + a];
            P[a] += m[i] * dv;
            scale += m[i] * fabs(dv);
            if (i >= 2) {
                if (fabs(dv - dx / cfac) > dverr) dverr = fabs(dv - dx / cfac);
                if (fabs(dv) > dvmax) dvmax = fabs(dv);
            }
        }
    scale += BODY * sqrt(du[0] * du[0] + du[1] * du[1] + du[2] * du[2]);
    double Pn = sqrt(P[0] * P[0] + P[1] * P[1] + P[2] * P[2]);
    printf("momentum change %.3g of sum m |dv| %.3g\n", Pn / scale, scale);
    CHECK(Pn <= 1e-10 * scale, "momentum changed by %.3g (sum m |dv| %.3g)", Pn, scale);
    CHECK(dverr <= 1e-12 * dvmax, "dv differs from dx / cfac by %.3g", dverr);
    cloth_destroy(c);
    return check_summary();
}
