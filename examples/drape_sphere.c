/* drape_sphere: the paper's Fig. 8 and 9. A 1 m cloth is dropped over a
 * sphere (radius 0.25 m on a thin post, its top 0.8 m above a floor plane),
 * settles, is lifted off by its four corners, carried clear, laid on the
 * floor spread out and released (examples/common/drape.h has the timeline).
 * Run for each plastic yield ratio alpha (default 0, 0.5, 0.8 and 1; cotton
 * otherwise, with the drapes' softer bending k_b 0.05 N/m and plastic memory,
 * examples/common/drape.h); pictures "draped" and "after removal" for each and a contact
 * sheet drape_sphere.png in --out.
 *
 * --check asserts that the residual crease grows with alpha (0 near flat,
 * each larger alpha clearly more) and that no vertex went past the
 * thickness into a body nor stretched past delta.
 *
 * Test demo_drape_sphere in test/CMakeLists.txt.
 * Test demo_drape_sphere_linearized in test/CMakeLists.txt.
 */
#include "common/drape.h"

static const char usage[] = "usage: drape_sphere [options]\n"
                            "The paper's Fig. 8 and 9: a cloth dropped over a sphere, lifted off by its\n"
                            "corners, laid on the floor and released; once per --alpha (default 0,0.5,0.8,1).\n"
                            "Writes <out>/alpha<A>_draped.png, alpha<A>_after.png and the sheet\n"
                            "drape_sphere.png; prints crease, height, plastic links, wrinkles,\n"
                            "penetration, strain, wall time.\n";

int main(int argc, char **argv)
{
    static const double defaults[] = {0.0, 0.5, 0.8, 1.0};
    return drape_alpha_main(argc, argv, "drape_sphere", usage, &drape_sphere_scene, defaults, 4,
                            "cloth over a sphere, then taken off");
}
