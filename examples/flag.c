/* flag: a flag on a pole in a gusting wind. A 1 m x 0.6 m cotton flag is
 * pinned along its edge to a vertical pole (a static ODE cylinder), its fly
 * end free; the wind (core air drag, cloth_set_air) blows along the flag at
 * 6 m/s, with a gust of 0.4 of that at 1.3 Hz and a crosswind of 0.3 of it
 * at 0.9 Hz, so the flag streams out and flutters. Pictures at the widest
 * flap sideways ("flap") and at the end ("end"); sheet flag.png in --out.
 * 4 s (--short: 2 s) at 60 steps/s, the rate an ODE scene runs at.
 *
 * --check: no failed step; strain <= delta + the step's allowance; the fly end rises from
 * hanging (the wind holds it out: its mean height over the run's second
 * half is above the pin's lowest point) and flaps both ways sideways by
 * more than 5 cm.
 *
 * Test demo_flag in test/CMakeLists.txt.
 */
#include <math.h>
#include <string.h>
#include "common/drape.h"
#include "common/view.h"

#define POLE_Z 2.2
#define POLE_R 0.02
#define FLAG_W 1.0
#define FLAG_H 0.6
#define WIND 6.0

static const char usage[] = "usage: flag [options]\n"
                            "A flag on a pole in a gusting wind (air drag on the cloth's triangles,\n"
                            "cloth_set_air); pictures at the widest sideways flap and at the end, the\n"
                            "metrics. 60 steps/s unless --steps-per-second says otherwise.\n";

static const float pole_rgb[3] = {0.45f, 0.45f, 0.45f};

static double flap_pos, flap_neg, fly_z_mean, pin_z_low;

/* the wind at time t: along the flag (+x), gusting, and a crosswind (y) */
static void wind_at(double t, double w[3])
{
    w[0] = WIND * (1.0 + 0.4 * sin(2.0 * M_PI * 1.3 * t));
    w[1] = 0.3 * WIND * sin(2.0 * M_PI * 0.9 * t);
    w[2] = 0.0;
}

static int run(const demo_opts *o, const demo_scene *sc, const drape_variant *v, drape_result *r)
{
    memset(r, 0, sizeof *r);
    const double h = 1.0 / o->hz;
    int steps = (int)lround((o->short_run ? 2.0 : 4.0) * o->hz);
    demo_contacts w = {dWorldCreate(), dJointGroupCreate(0), 0.8, 0.0};
    dWorldSetGravity(w.world, 0, 0, -9.81);
    dSpaceID space = dHashSpaceCreate(0);
    dCreatePlane(space, 0, 0, 1, 0);
    dGeomID pole = dCreateCylinder(space, POLE_R, POLE_Z);
    dGeomSetPosition(pole, -POLE_R, 0, POLE_Z / 2);
    dGeomSetData(pole, (void *)pole_rgb);
    dClothDesc d = demo_desc(o);
    d.cloth.rows = (int)lround((o->grid - 1) * FLAG_H / FLAG_W) + 1;
    d.cloth.cols = o->grid;
    d.cloth.width = FLAG_W;
    d.cloth.height = FLAG_H;
    d.cloth.origin[0] = 0.0;
    d.cloth.origin[1] = 0.0;
    d.cloth.origin[2] = POLE_Z - 0.05;
    demo_moment widest = {0};
    int rc = -1;
    dClothID c = demo_hang_cloth(o, v, &w, space, &d, r);
    if (!c) goto done;
    const int R = d.cloth.rows, C = d.cloth.cols;
    const dReal *x = dClothGetPositions(c);
    for (int row = 0; row < R; row++) dClothPinToWorld(c, row * C, x + 3 * (size_t)(row * C));
    pin_z_low = x[3 * (size_t)((R - 1) * C) + 2];
    const int fly = (R / 2) * C + C - 1; /* the fly end's middle */
    if (demo_moment_init(&widest, c)) goto done;
    const demo_camera cam = {{0.9, -2.4, 1.9}, {0.5, 0, 1.8}, 42};
    demo_metrics metrics = {0};
    double t0 = demo_now(), zsum = 0.0;
    int next_frame = 1, zn = 0;
    flap_pos = flap_neg = 0.0;
    for (int s = 0; s < steps; s++) {
        cloth_air air = {{0, 0, 0}, 2.0, 0.1};
        wind_at(s * h, air.wind);
        if (cloth_set_air(dClothGetCore(c), &air) != CLOTH_OK) {
            fprintf(stderr, "%s: %s\n", o->prog, cloth_last_error(dClothGetCore(c)));
            goto done;
        }
        if (demo_scene_step(o, v, &w, space, &c, &cam, h, s, steps, &next_frame, &metrics)) goto done;
        double y = x[3 * (size_t)fly + 1];
        flap_pos = fmax(flap_pos, y);
        flap_neg = fmin(flap_neg, y);
        if (2 * s >= steps) {
            zsum += x[3 * (size_t)fly + 2];
            zn++;
        }
        demo_moment_offer(&widest, fabs(y), c, NULL, &metrics, t0, &r->draped);
    }
    fly_z_mean = zn ? zsum / zn : NAN;
    demo_moment_finish(o, sc, v, &widest, c, NULL, space, &cam, &metrics, t0, r);
    rc = 0;
done:
    demo_scene_free(&widest, c, &w, space);
    return rc;
}

static const demo_scene scene = {"flag", {"flap", "end"}, {"flap", "end"}, DRAPE_TABLE, run, 0.0, 0, 0, 0, 0.0, 0};

static int report(const demo_opts *o, const drape_variant *v, const drape_result *r)
{
    (void)r;
    printf("fly end: sideways %.3f to %.3f m; mean height over the second half %.3f m (lowest pin %.3f m)\n", flap_neg,
           flap_pos, fly_z_mean, pin_z_low);
    if (!o->check) return 0;
    return demo_claim(flap_pos > 0.05 && flap_neg < -0.05, "%s: the fly end flaps both ways by > 5 cm", v->tag) +
           demo_claim(fly_z_mean > pin_z_low, "%s: the wind holds the fly end out, above the lowest pin", v->tag);
}

int main(int argc, char **argv)
{
    demo_opts o;
    int p = demo_begin(&o, "flag", usage, argc, argv);
    if (p) return p == 1 ? 0 : 2;
    return drape_material_main(&o, &scene, "a flag in a gusting wind", report);
}
