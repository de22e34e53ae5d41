/* Plugin: a fabric in physical units drapes alike at every grid.
 *
 * A 1 m cotton cloth (cloth_fabric_preset(CLOTH_FABRIC_COTTON), its springs
 * derived for each spacing by cloth_fabric_apply) falls flat from z = 0.35 m
 * onto a static sphere of radius 0.25 m at the origin, 2 s at 60 steps/s,
 * at 21x21 and 41x41 nodes. The shape is read off the boundary: its
 * vertices' mean distance from the vertical axis and mean height.
 *   1. every step is taken;
 *   2. both grids drape (the boundary hangs below the sphere's equator and
 *      well inside the flat sheet's reach);
 *   3. the two grids' boundary distances agree within 5%, and their heights
 *      within 5% of the drop; the control, the same per-link springs at both
 *      grids (cloth_material_preset(CLOTH_COTTON)), differs by more than 5%.
 */
#include <math.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "odecloth/fabric.h"
#include "check.h"

#define H (1.0 / 60)
#define STEPS 120
#define SPHERE_R 0.25
#define DROP_Z 0.35

typedef struct shape {
    double r, z; /* m: the boundary's mean distance from the z axis, mean height */
    int ok;      /* every step taken */
} shape;

static void boundary(const cloth *c, shape *s)
{
    int R = cloth_rows(c), C = cloth_cols(c), m = 0;
    const double *x = cloth_positions(c);
    s->r = s->z = 0.0;
    for (int i = 0; i < R; i++)
        for (int j = 0; j < C; j++) {
            if (i > 0 && i < R - 1 && j > 0 && j < C - 1) continue;
            const double *p = x + 3 * ((size_t)i * C + j);
            s->r += sqrt(p[0] * p[0] + p[1] * p[1]);
            s->z += p[2];
            m++;
        }
    s->r /= m;
    s->z /= m;
}

/* fabric: springs derived from the cotton fabric for the grid, else the per-link preset */
static shape drape(int n, int fabric)
{
    shape s = {NAN, NAN, 0};
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dCreateSphere(sp, SPHERE_R);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = n;
    d.cloth.width = d.cloth.height = 1.0;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.5;
    d.cloth.origin[2] = DROP_Z;
    cloth_fabric f = cloth_fabric_preset(CLOTH_FABRIC_COTTON);
    cloth_error err = {0};
    dClothID c = NULL;
    if (!fabric) d.cloth.material = cloth_material_preset(CLOTH_COTTON);
    if (CHECK(!fabric || cloth_fabric_apply(&f, &d.cloth, &err) == CLOTH_OK, "cloth_fabric_apply %d: %s", n,
              err.message) &&
        CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "dClothCreate %d: %s", n, err.message)) {
        dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
        int k = 0;
        while (k < STEPS && dClothStep(c, H) == CLOTH_OK) k++;
        s.ok = CHECK(k == STEPS, "%dx%d: step %d failed: %s", n, n, k, dClothGetLastError(c));
        boundary(dClothGetCore(c), &s);
        printf("%dx%d cotton %s: boundary %.4f m from the axis, at z = %.4f m\n", n, n,
               fabric ? "fabric" : "per-link preset", s.r, s.z);
        dClothDestroy(c);
    }
    dSpaceDestroy(sp);
    dWorldDestroy(w);
    return s;
}

int main(void)
{
    dInitODE();
    shape a = drape(21, 1), b = drape(41, 1), pa = drape(21, 0), pb = drape(41, 0);
    /* a flat 1 m square's boundary lies 0.574 m from its centre on average */
    for (int k = 0; k < 2; k++) {
        const shape *s = k ? &b : &a;
        CHECK(s->z < 0.0 && s->r < 0.45, "%s grid does not drape: boundary r %.3f m, z %.3f m", k ? "41" : "21", s->r,
              s->z);
    }
    CHECK(fabs(b.r / a.r - 1.0) <= 0.05, "boundary distance 21x21 %.4f vs 41x41 %.4f m: differ by %.1f%% > 5%%", a.r,
          b.r, 100 * fabs(b.r / a.r - 1.0));
    CHECK(fabs(b.z - a.z) <= 0.05 * DROP_Z, "boundary height 21x21 %.4f vs 41x41 %.4f m: differ by more than %.4f m",
          a.z, b.z, 0.05 * DROP_Z);
    CHECK(fabs(pb.r / pa.r - 1.0) > 0.05,
          "control: the per-link preset's boundary 21x21 %.4f vs 41x41 %.4f m "
          "within 5%%: the comparison cannot tell grids apart",
          pa.r, pb.r);
    dCloseODE();
    return check_summary();
}
