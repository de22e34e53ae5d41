/* crumple: a cloth pressed together between two moving plates, then released.
 *
 * A 1 m cloth hangs in the xz plane between two horizontal bars (kinematic
 * ODE bodies, box-shaped triangle meshes: see examples/common/drape.h;
 * --box-table: ODE boxes), its top row pinned under the top bar, its bottom
 * row on the bottom bar, with a 1 cm ripple so that it buckles out of its
 * plane. The script (each step a smoothstep in time): the bottom bar rises
 * until the bars are GAP apart (2 s: the cloth bulges into a loop), two
 * upright side plates close to 3 cm either side of the cloth's plane (2 s:
 * the loop is squashed into folds), hold (0.5 s; "pressed"), open (0.8 s),
 * the bottom bar goes back down to 0.9 m (2.5 s), lets go of the cloth and
 * slides away (1 s), and the cloth hangs from the top bar (4 s; "released").
 * Friction 0 (smooth plates). An elastic cloth hangs flat again; a plastic
 * one keeps what yielded. The near side plate is not drawn. Once per
 * --alpha (default 0, 0.5, 0.8); pictures and a contact sheet crumple.png
 * in --out.
 *
 * --check: penetration < thickness, strain <= delta, and the alpha claims of
 * examples/common/drape.h (alpha 0 hangs flat again, a run whose links
 * yielded keeps clearly more crease, growing with alpha).
 *
 * Test demo_crumple in test/CMakeLists.txt.
 * Test demo_crumple_linearized in test/CMakeLists.txt.
 */
#include "common/drape.h"

static const char usage[] = "usage: crumple [options]\n"
                            "A hanging cloth squeezed between a rising bottom bar and two closing side\n"
                            "plates (kinematic bodies), released, left hanging; once per --alpha\n"
                            "(default 0,0.5,0.8). Writes\n"
                            "<out>/alpha<A>_pressed.png, alpha<A>_released.png and the sheet crumple.png;\n"
                            "prints crease, height, plastic links, wrinkles, penetration, strain, wall time.\n";

int main(int argc, char **argv)
{
    static const double defaults[] = {0.0, 0.5, 0.8};
    return drape_alpha_main(argc, argv, "crumple", usage, &press_scene, defaults, 3, "cloth pressed between plates");
}
