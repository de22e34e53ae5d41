/* Plugin: the crumple demo's press with ODE boxes (examples/common/press.c: a 21x21 cloth between a
 * rising bottom bar, a top bar and two closing side plates; alpha 0, Newton, the demo's defaults).
 *
 * Its deepest point in any geom's shell (dClothStepStats.max_penetration_all, over every step of the
 * press and the release) stays within the thickness and no step fails. Where a solve leaves a cloth
 * triangle deeper in a bar's shell than its vertices (the bar's edge between them), its contact is taken
 * again where the solve ended (late_triangles.c); with the start's contact point alone, which weighs a
 * vertex the step slides under the top bar not at all, the bar's edge ends past the thickness.
 */
#include <stdio.h>
#include <string.h>
#include "check.h"
#include "drape.h"

int main(void)
{
    char *argv[] = {"plugin_press_depth", "--box-table", "--no-images", "--alpha", "0", NULL};
    demo_opts o;
    if (demo_begin(&o, "plugin_press_depth", "", 5, argv)) return 2;
    drape_variant v;
    memset(&v, 0, sizeof v);
    CHECK(drape_scene_material(&o, &press_scene, &v.material) == 0, "the press's material");
    v.material.alpha = 0.0;
    v.removal = drape_removal_chosen(&o);
    snprintf(v.label, sizeof v.label, "alpha 0");
    snprintf(v.tag, sizeof v.tag, "alpha0");
    drape_result r;
    memset(&r, 0, sizeof r);
    int rc = press_scene.run(&o, &press_scene, &v, &r);
    double deepest = r.draped.deepest_point > r.after.deepest_point ? r.draped.deepest_point : r.after.deepest_point;
    printf("press, 21x21, alpha 0: deepest point %.2f mm (thickness %.1f mm), strain %.4f\n", 1e3 * deepest,
           1e3 * r.thickness, r.after.max_strain > r.draped.max_strain ? r.after.max_strain : r.draped.max_strain);
    CHECK(rc == 0, "a step of the press failed");
    CHECK(r.thickness > 0.0, "the press reported no thickness");
    CHECK(deepest <= r.thickness, "the cloth's deepest point %.2f mm is past the thickness %.1f mm", 1e3 * deepest,
          1e3 * r.thickness);
    return check_summary();
}
