/* Unit: the air drag's derivatives (air.c) on a random state (5 x 7 grid,
 * positions and velocities perturbed, wind, unequal drags):
 *   - oc_air_eval's force is -grad of its potential wrt the velocities, and
 *     its blocks are -dF/dv (central differences; F is linear in v, so
 *     only rounding remains: 1e-7 relative);
 *   - its blocks are bitwise symmetric (the matvec's fast path needs it);
 *   - in the Newton step (potential.c) with air on and soft links (so the
 *     air's terms are a fair share of Phi's), b = -grad Phi and the matrix
 *     is Phi's Hessian (central differences, 1e-6 relative);
 *   - both drags 0: oc_air_eval adds nothing and oc_air_on is 0.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "potential.h"
#include "check.h"

static cloth *make(rng *g)
{
    cloth_desc d = cloth_default_desc();
    d.rows = 5;
    d.cols = 7;
    d.width = d.height = 0.3;
    /* soft, undamped links: the air's terms dominate Phi's derivatives */
    d.material.k_t = d.material.k_c = d.material.k_b = d.material.k_s = 1e-3;
    d.material.c_t = d.material.c_b = 0.0;
    cloth *c;
    if (!CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK, "create")) return NULL;
    int n3 = 3 * c->n;
    for (int k = 0; k < n3; k++) {
        c->st.x[k] += rng_range(g, -0.01, 0.01);
        c->st.v[k] = rng_range(g, -1.0, 1.0);
    }
    cloth_air air = {{0.7, -0.3, 1.1}, 2.5, 0.4};
    CHECK(cloth_set_air(c, &air) == CLOTH_OK, "set air");
    return c;
}

static double *vec(int n3) { return calloc((size_t)n3, sizeof(double)); }

/* largest |a - b| over n entries, and the largest |b| */
static double maxdiff(const double *a, const double *b, int n, double *scale)
{
    double e = 0.0;
    *scale = 0.0;
    for (int k = 0; k < n; k++) {
        e = fmax(e, fabs(a[k] - b[k]));
        *scale = fmax(*scale, fabs(b[k]));
    }
    return e;
}

static void kernel(cloth *c, rng *g)
{
    int n3 = 3 * c->n;
    double *F = vec(n3), *Fp = vec(n3), *Fm = vec(n3);
    double *v = vec(n3), *w = vec(n3), *fd = vec(n3);
    double *Aw = vec(n3), eps = 1e-4, sc;
    memcpy(v, c->st.v, (size_t)n3 * sizeof *v);
    for (int k = 0; k < n3; k++) w[k] = rng_range(g, -1.0, 1.0);
    oc_bsr_zero(&c->A);
    oc_air_eval(c, c->st.x, NULL, 0.0, v, 1.0, F, &c->A, 1.0);
    unsigned char *flag = malloc((size_t)c->n);
    CHECK(oc_bsr_check_sym(&c->A, c->A.val, flag) == c->n, "every row's blocks bitwise symmetric");
    free(flag);
    for (int k = 0; k < n3; k++) {
        double vk = v[k];
        v[k] = vk + eps;
        double Pp = oc_air_eval(c, c->st.x, NULL, 0.0, v, 0.0, NULL, NULL, 0.0);
        v[k] = vk - eps;
        double Pm = oc_air_eval(c, c->st.x, NULL, 0.0, v, 0.0, NULL, NULL, 0.0);
        v[k] = vk;
        fd[k] = -(Pp - Pm) / (2.0 * eps);
    }
    double e = maxdiff(F, fd, n3, &sc);
    printf("air force vs -dP/dv: %.3g of %.3g\n", e, sc);
    CHECK(e <= 1e-7 * sc, "air force is not -grad of its potential");
    for (int k = 0; k < n3; k++) {
        v[k] = c->st.v[k] + eps * w[k];
        fd[k] = c->st.v[k] - eps * w[k];
    }
    oc_air_eval(c, c->st.x, NULL, 0.0, v, 1.0, Fp, NULL, 0.0);
    oc_air_eval(c, c->st.x, NULL, 0.0, fd, 1.0, Fm, NULL, 0.0);
    for (int k = 0; k < n3; k++) fd[k] = -(Fp[k] - Fm[k]) / (2.0 * eps);
    oc_bsr_mul(&c->A, w, Aw);
    e = maxdiff(Aw, fd, n3, &sc);
    printf("air blocks vs -dF/dv: %.3g of %.3g\n", e, sc);
    CHECK(e <= 1e-7 * sc, "air blocks are not -dF/dv");
    free(F);
    free(Fp);
    free(Fm);
    free(v);
    free(w);
    free(fd);
    free(Aw);
}

/* b and the matrix at dv against Phi's central differences */
static void newton(cloth *c, rng *g)
{
    int n3 = 3 * c->n;
    double *dv = vec(n3), *w = vec(n3);
    double *b = vec(n3), *bp = vec(n3), *bm = vec(n3);
    double *x = vec(n3), *v = vec(n3), *fd = vec(n3);
    double *Aw = vec(n3), eps = 1e-6, sc;
    step_eq q;
    oc_potential_begin(c, 0.01, 0, &q);
    for (int k = 0; k < n3; k++) {
        dv[k] = rng_range(g, -0.05, 0.05);
        w[k] = rng_range(g, -1.0, 1.0);
    }
    for (int k = 0; k < n3; k++) {
        double d = dv[k];
        dv[k] = d + eps;
        double Pp = oc_potential_value(c, &q, dv, x, v);
        dv[k] = d - eps;
        double Pm = oc_potential_value(c, &q, dv, x, v);
        dv[k] = d;
        fd[k] = -(Pp - Pm) / (2.0 * eps);
    }
    oc_potential_state(c, &q, dv);
    oc_potential_assemble(c, &q, dv, b, 0);
    double e = maxdiff(b, fd, n3, &sc);
    printf("Newton: b vs -dPhi/ddv: %.3g of %.3g\n", e, sc);
    CHECK(e <= 1e-6 * sc, "b is not -grad Phi with air");
    oc_bsr_mul(&c->A, w, Aw);
    for (int s = 0; s < 2; s++) {
        for (int k = 0; k < n3; k++) x[k] = dv[k] + (s ? -eps : eps) * w[k];
        oc_potential_state(c, &q, x);
        oc_potential_assemble(c, &q, x, s ? bm : bp, 0);
    }
    for (int k = 0; k < n3; k++) fd[k] = -(bp[k] - bm[k]) / (2.0 * eps);
    e = maxdiff(Aw, fd, n3, &sc);
    printf("Newton: matrix vs Phi's Hessian: %.3g of %.3g\n", e, sc);
    CHECK(e <= 1e-6 * sc, "the Newton matrix is not Phi's Hessian with air");
    free(dv);
    free(w);
    free(b);
    free(bp);
    free(bm);
    free(x);
    free(v);
    free(fd);
    free(Aw);
}

static void off(cloth *c)
{
    cloth_air none = {{1.0, 2.0, 3.0}, 0.0, 0.0};
    cloth_set_air(c, &none);
    int n3 = 3 * c->n;
    double *f = vec(n3), sc;
    oc_air_eval(c, c->st.x, NULL, 0.0, c->st.v, 1.0, f, NULL, 0.0);
    double *z = vec(n3);
    CHECK(!oc_air_on(c) && maxdiff(f, z, n3, &sc) == 0.0, "no drag: no force");
    free(f);
    free(z);
}

int main(void)
{
    rng g = rng_seed(0xa1ada9u);
    cloth *c = make(&g);
    if (c) {
        kernel(c, &g);
        newton(c, &g);
        off(c);
    }
    cloth_destroy(c);
    return check_summary();
}
