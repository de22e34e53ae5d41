/* drape_table: the paper's Fig. 7. A 1 m cloth is dropped over a table (a box
 * on a floor plane), settles, is lifted off by its four corners, carried
 * clear, laid on the floor spread out and released (examples/common/drape.h
 * has the timeline). Run for each plastic yield ratio alpha (default 0, 0.5
 * and 0.8; cotton otherwise, with the drapes' softer bending k_b 0.05 N/m and
 * plastic memory, examples/common/drape.h); pictures "draped" and "after removal" for each
 * and a contact sheet drape_table.png in --out.
 *
 * --check asserts the paper's claim on the metrics: the residual crease
 * (mean |dihedral angle| of the settled, spread cloth) grows with alpha
 * (0 near flat, 0.5 clearly more, 0.8 more still), that the draped cloth's
 * mean crease grows with alpha too, and no vertex went past the thickness
 * into a body nor stretched past delta.
 *
 * Test demo_drape_table in test/CMakeLists.txt.
 *
 * The same with ODE's box geom as the table (vertex and libccd triangle
 * contacts), lifted off over its edges, at cotton's own bending and the
 * paper's rule (at the drapes' defaults alpha 1 goes past the strain bound
 * in the short run, docs/demos.md):
 * Test demo_drape_table_box in test/CMakeLists.txt.
 *
 * The fabric cotton in physical units (--fabric), taken off by two corners
 * and laid down as a person does (--removal two), with the paper's rule: the
 * elastic cloth lies flat, within the thickness and the elongation limit:
 * Test demo_drape_table_two_corners in test/CMakeLists.txt.
 *
 * The same with the crease law (--crease-law) at alpha 0.8: its hinges keep the cloth within the thickness
 * and the elongation limit, every step taken:
 * Test demo_drape_table_crease in test/CMakeLists.txt.
 *
 * The metrics themselves, against closed forms on a folded cloth:
 * Test demo_metrics in test/CMakeLists.txt.
 */
#include "common/drape.h"

static const char usage[] = "usage: drape_table [options]\n"
                            "The paper's Fig. 7: a cloth dropped over a table, lifted off by its corners,\n"
                            "laid on the floor and released; once per --alpha (default 0,0.5,0.8). Writes\n"
                            "<out>/alpha<A>_draped.png, alpha<A>_after.png and the sheet drape_table.png;\n"
                            "prints crease, height, plastic links, wrinkles, penetration, strain, wall time.\n";

int main(int argc, char **argv)
{
    static const double defaults[] = {0.0, 0.5, 0.8};
    return drape_alpha_main(argc, argv, "drape_table", usage, &drape_table_scene, defaults, 3,
                            "cloth over a table, then taken off");
}
