/* Demo: the pictures' shadows and contact darkening (examples/common:
 * render.c, shadow.c, contact.c), against where they must fall, computed
 * here from the geometry alone.
 *
 * A flat square cloth (0.4 m) held level over a floor plane, seen from
 * straight above (1 m up, a 60 degree pinhole; +x to the right, +y up in
 * the picture). Each scene is rendered with the cloth and without it (the
 * bare floor), and the two pictures compared pixel by pixel, so the
 * floor's checks cancel:
 *   1. cloth 0.3 m up: floor points whose ray toward the key light
 *      (demo_key_light) meets the cloth, and that the cloth does not hide,
 *      are at most half as bright as the bare floor (the key light gives
 *      about two thirds of the floor's light there); floor points well clear
 *      of the cloth and of its shadow are unchanged (within 2 of 255);
 *   2. cloth lying on the floor (5 mm up): a ring 1-2 cm outside its edge
 *      is darker than the bare floor (below 0.93 of it), floor beyond 8 cm
 *      unchanged.
 * 2 px margins (10 mm) keep the edges out of each class. Skipped (said) in
 * a build without OSMesa.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "demo.h"
#include "sanitizer.h"

/* Under LeakSanitizer: OSMesa keeps a few hundred bytes of its context
 * after OSMesaDestroyContext (its own frames only); ours are still checked. */
#ifdef ODECLOTH_ASAN
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libOSMesa.so\n"; }
#endif

#define W 240
#define EYE_Z 1.0
#define FOV 60.0
#define HALF 0.2    /* the cloth's half side, m */
#define MARGIN 0.01 /* m on the floor, about 2 px */

/* The floor point (x, y) a pixel's centre sees. */
static void floor_point(int col, int row, double *x, double *y)
{
    double t = tan(FOV * M_PI / 360.0) * EYE_Z;
    *x = ((col + 0.5) - W / 2.0) / (W / 2.0) * t;
    *y = (W / 2.0 - (row + 0.5)) / (W / 2.0) * t;
}

/* Distance outside the square |x|, |y| <= h (negative inside). */
static double outside(double x, double y, double h) { return fmax(fabs(x), fabs(y)) - h; }

static double luma(const demo_image *im, int col, int row)
{
    const unsigned char *p = im->rgb + 3 * ((size_t)row * W + col);
    return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
}

static demo_image *render(dSpaceID space, dClothID c)
{
    demo_camera cam = {{0, -1e-4, EYE_Z}, {0, 0, 0}, FOV};
    return demo_render(&cam, space, c ? &c : NULL, c ? 1 : 0, 0, W, W);
}

static dClothID level_cloth(dWorldID world, double z)
{
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = 9;
    d.cloth.width = d.cloth.height = 2 * HALF;
    d.cloth.origin[0] = d.cloth.origin[1] = -HALF;
    d.cloth.origin[2] = z;
    d.cloth.axis_u[0] = 1, d.cloth.axis_u[1] = 0, d.cloth.axis_u[2] = 0;
    d.cloth.axis_v[0] = 0, d.cloth.axis_v[1] = 1, d.cloth.axis_v[2] = 0;
    dClothID c = NULL;
    cloth_error err;
    CHECK(dClothCreate(world, 0, &d, &c, &err) == CLOTH_OK, "cloth created (%s)", c ? "" : err.message);
    return c;
}

/* Scene 1: the cast shadow of a cloth z up. */
static void cast_shadow(dWorldID world, dSpaceID space, const demo_image *bare)
{
    const double z = 0.3, *L = demo_key_light;
    dClothID c = level_cloth(world, z);
    demo_image *im = c ? render(space, c) : NULL;
    CHECK(im != NULL, "scene 1 rendered");
    long shadowed = 0, dark = 0, clear = 0, same = 0;
    for (int row = 0; im && row < W; row++)
        for (int col = 0; col < W; col++) {
            double x, y;
            floor_point(col, row, &x, &y);
            /* the cloth, seen from the eye, covers the floor point scaled to its height */
            double hidden = outside(x * (EYE_Z - z) / EYE_Z, y * (EYE_Z - z) / EYE_Z, HALF);
            /* the point's ray toward the light, at the cloth's height */
            double lit = outside(x + z / L[2] * L[0], y + z / L[2] * L[1], HALF);
            double a = luma(im, col, row), b = luma(bare, col, row);
            if (hidden > MARGIN && lit < -MARGIN) {
                shadowed++;
                dark += a <= 0.5 * b;
            } else if (hidden > MARGIN && lit > MARGIN) {
                clear++;
                same += fabs(a - b) <= 2.0;
            }
        }
    printf("scene 1: %ld shadowed floor pixels, %ld at most half as bright; %ld clear, %ld unchanged\n", shadowed, dark,
           clear, same);
    CHECK(shadowed > 300, "scene 1: the shadow shows beside the cloth (%ld pixels > 300)", shadowed);
    CHECK(dark == shadowed, "scene 1: every shadowed pixel at most half the bare floor (%ld of %ld)", dark, shadowed);
    CHECK(clear > 10000 && same == clear, "scene 1: the floor clear of it unchanged (%ld of %ld)", same, clear);
    demo_image_destroy(im);
    dClothDestroy(c);
}

/* Scene 2: a cloth lying on the floor darkens a rim around it. */
static void contact_rim(dWorldID world, dSpaceID space, const demo_image *bare)
{
    dClothID c = level_cloth(world, 0.005);
    demo_image *im = c ? render(space, c) : NULL;
    CHECK(im != NULL, "scene 2 rendered");
    long ring = 0, darker = 0, far = 0, same = 0;
    double worst = 0.0;
    for (int row = 0; im && row < W; row++)
        for (int col = 0; col < W; col++) {
            double x, y;
            floor_point(col, row, &x, &y);
            double out = outside(x, y, HALF), a = luma(im, col, row), b = luma(bare, col, row);
            if (out > 0.01 && out < 0.02) {
                ring++;
                darker += a < 0.93 * b;
                worst = fmax(worst, a / b);
            } else if (out > 0.08) {
                far++;
                same += fabs(a - b) <= 2.0;
            }
        }
    printf("scene 2: ring of %ld pixels, %ld darker than 0.93 of the bare floor (brightest %.2f); %ld far, %ld "
           "unchanged\n",
           ring, darker, worst, far, same);
    CHECK(ring > 300 && darker == ring, "scene 2: the rim 1-2 cm out darker (%ld of %ld)", darker, ring);
    CHECK(far > 10000 && same == far, "scene 2: floor beyond 8 cm unchanged (%ld of %ld)", same, far);
    demo_image_destroy(im);
    dClothDestroy(c);
}

int main(void)
{
    if (!demo_render_available()) {
        printf("demo_shadow: %s: skipped\n", demo_render_unavailable_reason());
        return 0;
    }
    dInitODE2(0);
    dWorldID world = dWorldCreate();
    dSpaceID space = dSimpleSpaceCreate(0);
    dCreatePlane(space, 0, 0, 1, 0);
    demo_image *bare = render(space, NULL);
    CHECK(bare != NULL, "bare floor rendered");
    if (bare) {
        cast_shadow(world, space, bare);
        contact_rim(world, space, bare);
    }
    demo_image_destroy(bare);
    demo_render_shutdown();
    dSpaceDestroy(space);
    dWorldDestroy(world);
    dCloseODE();
    return check_summary();
}
