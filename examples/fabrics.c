/* fabrics: cotton against wool (paper Table 1), each with its own alpha,
 * delta and k_s, through two experiments: the table drape and removal of
 * drape_table (with its bending k_b and plastic memory, common/drape.h),
 * and the press and release of crumple (the presets). Sheets
 * fabrics_table.png and fabrics_press.png in --out (columns: the fabrics).
 * What it measures: docs/demos.md.
 *
 * --check: penetration < thickness and strain <= each fabric's delta in
 * every run; wool (alpha 0.1, k_s 0.1: "gentle folds, spreads back out")
 * leaves less residual crease than cotton (alpha 0.8, k_s 10: "creases
 * stay") where cotton's links yielded, and no more where they did not.
 * --alpha A overrides both fabrics' alpha.
 *
 * Test demo_fabrics in test/CMakeLists.txt.
 */
#include <string.h>
#include "common/drape.h"

static const char usage[] = "usage: fabrics [options]\n"
                            "Cotton against wool (Table 1 presets) on the table (drape, lift off, lay\n"
                            "flat) and in the press (squeeze, release, hang). Writes <out>/cotton_*.png,\n"
                            "wool_*.png and the sheets fabrics_table.png, fabrics_press.png; prints the\n"
                            "metrics of each run.\n";

enum { COTTON, WOOL };

/* Wool against cotton in one experiment; returns the number of failed checks. */
static int check_fabrics(const char *what, const drape_result *r)
{
    const demo_metrics *c = &r[COTTON].after, *w = &r[WOOL].after;
    double bend = fmin(r[COTTON].draped.min_bend, r[COTTON].after.min_bend);
    if (c->plastic_links == 0 && bend > 0.8)
        return demo_claim(w->crease_deg <= c->crease_deg + DRAPE_FLAT_DEG,
                          "%s: cotton never yielded (deepest bend %.3f): wool's residual crease %.3f deg no more "
                          "than cotton's %.3f + %.1f deg",
                          what, bend, w->crease_deg, c->crease_deg, DRAPE_FLAT_DEG);
    return demo_claim(w->crease_deg < c->crease_deg,
                      "%s: wool's residual crease %.3f deg (%d plastic links) < cotton's %.3f deg (%d)", what,
                      w->crease_deg, w->plastic_links, c->crease_deg, c->plastic_links);
}

int main(int argc, char **argv)
{
    demo_opts o;
    int p = demo_begin(&o, "fabrics", usage, argc, argv);
    if (p) return p == 1 ? 0 : 2;
    if (o.nalpha > 1) {
        fprintf(stderr, "fabrics: give one --alpha at most\n");
        return 2;
    }
    if (o.fabric || o.crease_grip > 0.0 || o.crease_law > 0.0) {
        fprintf(stderr, "fabrics: --fabric, --crease-grip and --crease-law are drape_table's, drape_sphere's and "
                        "crumple's\n");
        return 2;
    }
    /* the table as drape_table runs it (its bending and plastic memory,
     * examples/common/drape.h), the press as crumple does (the presets);
     * --bending and --memory override both */
    drape_variant v[2], vt[2];
    const char *names[2] = {"cotton", "wool"};
    memset(v, 0, sizeof v);
    for (int i = 0; i < 2; i++) {
        v[i].material = cloth_material_preset(i == COTTON ? CLOTH_COTTON : CLOTH_WOOL);
        if (o.nalpha) v[i].material.alpha = o.alphas[0];
        if (o.k_b > 0.0) v[i].material.k_b = o.k_b;
        if (o.memory >= 0) v[i].material.plastic_memory = o.memory;
        snprintf(v[i].label, sizeof v[i].label, "%s (alpha %g)", names[i], v[i].material.alpha);
        snprintf(v[i].tag, sizeof v[i].tag, "%s", names[i]);
        vt[i] = v[i];
        vt[i].material.k_b = o.k_b > 0.0 ? o.k_b : drape_table_scene.k_b;
        vt[i].material.plastic_memory = o.memory >= 0 ? o.memory : drape_table_scene.memory;
        vt[i].removal = drape_removal_chosen(&o);
    }
    drape_result table[2], press[2];
    const char *out = o.out;
    char dir[2][1024];
    /* each experiment's pictures in its own folder (the tags repeat) */
    snprintf(dir[0], sizeof dir[0], "%s/table", out);
    snprintf(dir[1], sizeof dir[1], "%s/press", out);
    o.out = dir[0];
    if (drape_run_all(&o, &drape_table_scene, vt, 2, table, "fabrics_table", "cotton and wool over a table")) return 1;
    o.out = dir[1];
    if (drape_run_all(&o, &press_scene, v, 2, press, "fabrics_press", "cotton and wool pressed")) return 1;
    if (!o.check) return 0;
    int failed = 0;
    for (int i = 0; i < 2; i++) {
        failed += drape_check_common(&o, &vt[i], &table[i]);
        failed += drape_check_common(&o, &v[i], &press[i]);
    }
    failed += check_fabrics("table", table);
    failed += check_fabrics("press", press);
    printf("fabrics: %d check(s) failed\n", failed);
    return failed ? 1 : 0;
}
