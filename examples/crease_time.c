/* crease_time: plasticity that depends on duration and repetition (the
 * paper's future work; material.tau_set, tau_recover, set_hardening in
 * odecloth/cloth.h). The same cloth as drape_table (cotton, the drapes'
 * bending k_b 0.05 N/m, alpha 0.8) with the time-dependent plastic law, in
 * three runs of drape_table's experiment (examples/common/drape.h):
 *   - left on the table 0.5 s, then taken off and laid on the floor;
 *   - left on the table 10 s, then the same;
 *   - left 0.5 s five times: after each of the first four drapes lifted off
 *     by its corners, laid back flat over the table and let go.
 * Pictures "draped" (the end of the last drape) and "after removal" per
 * run, the sheet crease_time.png; the residual crease (mean |dihedral| of
 * the settled cloth) printed for each.
 *
 * --check asserts the law's claims on the residual crease: the 0.5 s drape
 * mostly recovers (under drape_table's flat bound, DRAPE_FLAT_DEG), the
 * 10 s drape leaves more, five drapes more than one; and the
 * drapes' common claims (penetration within the thickness, strain within
 * delta). Full size: `crease_time --check` (21 x 21, 60 steps/s).
 *
 * Test demo_crease_time in test/CMakeLists.txt.
 */
#include <string.h>
#include "common/drape.h"

/* The law's time constants for this demo: illustrative (docs/materials.md),
 * a set reached in seconds and recovering over tens of seconds, a third of
 * each fold's set kept for good. */
#define CREASE_TAU_SET 2.0
#define CREASE_TAU_RECOVER 20.0
#define CREASE_HARDENING 0.3
#define CREASE_ALPHA 0.8

static const char usage[] = "usage: crease_time [options]\n"
                            "A cloth left on a table 0.5 s, 10 s, and 0.5 s five times, then taken off\n"
                            "and laid on the floor, with the time-dependent plastic law (tau_set 2 s,\n"
                            "tau_recover 20 s, set_hardening 0.3; --alpha A sets the yield ratio, default\n"
                            "0.8). Writes <out>/<run>_draped.png, <run>_after.png and the sheet\n"
                            "crease_time.png; prints crease, height, plastic links, penetration, strain.\n";

typedef struct run_spec {
    const char *label, *tag;
    double hold;
    int folds;
} run_spec;

enum { BRIEF, LONG, REPEATED, NRUNS };

static const run_spec runs[NRUNS] = {
    {"0.5 s on the table", "hold0.5", 0.5, 1},
    {"10 s on the table", "hold10", 10.0, 1},
    {"0.5 s, five times", "hold0.5x5", 0.5, 5},
};

int main(int argc, char **argv)
{
    demo_opts o;
    int p = demo_begin(&o, "crease_time", usage, argc, argv);
    if (p) return p == 1 ? 0 : 2;
    if (o.nalpha > 1) {
        fprintf(stderr, "crease_time: give one --alpha at most\n");
        return 2;
    }
    drape_variant v[NRUNS];
    drape_result r[NRUNS];
    memset(v, 0, sizeof v);
    for (int i = 0; i < NRUNS; i++) {
        cloth_material *m = &v[i].material;
        *m = cloth_material_preset(o.material);
        m->alpha = o.nalpha ? o.alphas[0] : CREASE_ALPHA;
        m->k_b = o.k_b > 0.0 ? o.k_b : DRAPE_BENDING;
        m->plastic_memory = 0; /* the recovery law decides what a released link keeps */
        m->tau_set = CREASE_TAU_SET;
        m->tau_recover = CREASE_TAU_RECOVER;
        m->set_hardening = CREASE_HARDENING;
        snprintf(v[i].label, sizeof v[i].label, "%s", runs[i].label);
        snprintf(v[i].tag, sizeof v[i].tag, "%s", runs[i].tag);
        v[i].hold = runs[i].hold;
        v[i].folds = runs[i].folds;
    }
    if (drape_run_all(&o, &drape_table_scene, v, NRUNS, r, "crease_time",
                      "a crease that depends on how long and how often"))
        return 1;
    for (int i = 0; i < NRUNS; i++)
        printf("%-20s residual crease %.3f deg (max %.2f), %d plastic links\n", runs[i].label, r[i].after.crease_deg,
               r[i].after.crease_max_deg, r[i].after.plastic_links);
    if (!o.check) return 0;
    int failed = 0;
    for (int i = 0; i < NRUNS; i++) failed += drape_check_common(&o, &v[i], &r[i]);
    failed += demo_claim(r[BRIEF].after.crease_deg < DRAPE_FLAT_DEG,
                         "a brief drape mostly recovers: residual crease %.3f deg after 0.5 s < %.1f deg",
                         r[BRIEF].after.crease_deg, DRAPE_FLAT_DEG);
    failed += demo_claim(r[LONG].after.crease_deg > r[BRIEF].after.crease_deg,
                         "held longer sets deeper: residual crease %.3f deg after 10 s > %.3f deg after 0.5 s",
                         r[LONG].after.crease_deg, r[BRIEF].after.crease_deg);
    failed += demo_claim(r[REPEATED].after.crease_deg > r[BRIEF].after.crease_deg,
                         "repeated folds accumulate: residual crease %.3f deg after five > %.3f deg after one",
                         r[REPEATED].after.crease_deg, r[BRIEF].after.crease_deg);
    printf("crease_time: %d check(s) failed\n", failed);
    return failed ? 1 : 0;
}
