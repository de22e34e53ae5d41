/* Unit: cloth_fabric validation and the derivation's closed forms.
 *
 * Refusals: every field NaN, infinite, negative, and zero where zero means
 * nothing (tensile, bending, density, compression, delta), alpha above 1,
 * spacings NaN, infinite, zero or negative, NULL arguments, a spacing finer
 * than the fabric allows, and values that overflow: each refused with
 * CLOTH_EINVAL and a message naming the field, the output left as it was
 * (byte for byte).
 *
 * Closed forms (square cells h, docs/materials.md): k_t + 4 k_b = tensile / 2;
 * k_b solves 4 q k_b^2 - q S k_b + Q S = 0 with q = h^4 / 16, S = tensile / 2,
 * Q = B / (2 kappa_ref^2), and tends to Q / q = 8 B / (h^4 kappa_ref^2) for a
 * stiff membrane; the finest spacing the refusal names is accepted and 0.1%
 * finer refused; the ratios and pass-through fields; presets all valid, an
 * unknown kind is cotton.
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "odecloth/fabric.h"
#include "check.h"

static cloth_material sentinel(void)
{
    cloth_material m;
    memset(&m, 0xA5, sizeof m);
    return m;
}

/* The material derivation refuses: EINVAL, a message containing `name`,
 * the output untouched. */
static void refused(const cloth_fabric *f, double dx, double dy, const char *name, const char *what)
{
    cloth_material out = sentinel(), before = out;
    cloth_error err = {CLOTH_OK, ""};
    cloth_status s = cloth_fabric_material(f, dx, dy, &out, &err);
    CHECK(s == CLOTH_EINVAL, "%s: status %d", what, (int)s);
    CHECK(err.code == CLOTH_EINVAL, "%s: err.code %d", what, (int)err.code);
    CHECK(strstr(err.message, name) != NULL, "%s: message \"%s\" does not name %s", what, err.message, name);
    CHECK(memcmp(&out, &before, sizeof out) == 0, "%s: output changed", what);
}

static void check_fields(void)
{
    static const char *names[] = {"tensile",        "bending",         "density",     "compression",   "alpha",
                                  "spreading",      "delta",           "k_delta",     "tau_tension",   "tau_bending",
                                  "bend_curvature", "tau_set",         "tau_recover", "set_hardening", "tension_yield",
                                  "tension_set",    "crease_stiffness"};
    static const int positive[] = {1, 1, 1, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    const cloth_fabric base = cloth_fabric_preset(CLOTH_FABRIC_COTTON);
    for (int k = 0; k < 17; k++) {
        const double bad[] = {NAN, INFINITY, -INFINITY, -1.0, -1e-300, 0.0};
        for (int b = 0; b < 6; b++) {
            if (bad[b] == 0.0 && !positive[k]) continue;
            cloth_fabric f = base;
            ((double *)&f)[k] = bad[b];
            char full[64], what[96];
            snprintf(full, sizeof full, "fabric.%s", names[k]);
            snprintf(what, sizeof what, "%s = %g", full, bad[b]);
            refused(&f, 0.01, 0.01, full, what);
            CHECK(cloth_fabric_validate(&f, NULL) == CLOTH_EINVAL, "validate %s", what);
            CHECK(isnan(cloth_fabric_bending_length(&f)), "bending length of %s", what);
            CHECK(isnan(cloth_fabric_reference_curvature(&f)), "kappa_ref of %s", what);
        }
    }
    /* the field order the loop above assumes */
    CHECK(offsetof(cloth_fabric, bend_curvature) == 10 * sizeof(double) && sizeof(cloth_fabric) == 17 * sizeof(double),
          "cloth_fabric layout");
    cloth_fabric f = base;
    f.alpha = 1.0 + 1e-12;
    refused(&f, 0.01, 0.01, "fabric.alpha", "alpha above 1");
    f = base;
    f.set_hardening = 1.0 + 1e-12;
    refused(&f, 0.01, 0.01, "fabric.set_hardening", "set_hardening above 1");
    f = base;
    f.tension_yield = f.delta * (1.0 + 1e-12);
    refused(&f, 0.01, 0.01, "fabric.tension_yield", "tension_yield above delta");
    f = base;
    f.tension_set = 1.0 + 1e-12;
    refused(&f, 0.01, 0.01, "fabric.tension_set", "tension_set above 1");
    /* the tension plasticity passes through, the yield at delta included */
    f = base;
    f.tension_yield = f.delta, f.tension_set = 1.0;
    cloth_material mtp;
    CHECK(cloth_fabric_material(&f, 0.01, 0.01, &mtp, NULL) == CLOTH_OK && mtp.tension_yield == f.delta &&
              mtp.tension_set == 1.0,
          "tension_yield, tension_set pass through");
    /* the crease law: a moment per length, the hinge 4 S dy / dx^2 (mean of both directions); not with the
     * time-dependent law */
    f = base;
    f.crease_stiffness = 0.02;
    cloth_material mc, mr;
    CHECK(cloth_fabric_material(&f, 0.05, 0.05, &mc, NULL) == CLOTH_OK &&
              fabs(mc.k_crease - 4.0 * 0.02 / 0.05) <= 1e-15 * mc.k_crease,
          "k_crease %g at 5 cm cells, want 4 S / h = 1.6", mc.k_crease);
    CHECK(cloth_fabric_material(&f, 0.06, 0.04, &mr, NULL) == CLOTH_OK &&
              fabs(mr.k_crease - 0.5 * (4.0 * 0.02 * 0.04 / 0.0036 + 4.0 * 0.02 * 0.06 / 0.0016)) <=
                  1e-14 * mr.k_crease,
          "k_crease %g at 6 x 4 cm cells, want the mean of both directions", mr.k_crease);
    CHECK(base.crease_stiffness == 0.0 && cloth_fabric_material(&base, 0.05, 0.05, &mc, NULL) == CLOTH_OK &&
              mc.k_crease == 0.0,
          "the preset leaves the crease law off");
    f.tau_set = 2.0;
    refused(&f, 0.05, 0.05, "fabric.crease_stiffness", "crease_stiffness with tau_set");
    /* the time-dependent plastic law passes through */
    f = base;
    f.tau_set = 2.0, f.tau_recover = 20.0, f.set_hardening = 1.0;
    cloth_material mt;
    CHECK(cloth_fabric_material(&f, 0.01, 0.01, &mt, NULL) == CLOTH_OK && mt.tau_set == 2.0 && mt.tau_recover == 20.0 &&
              mt.set_hardening == 1.0,
          "tau_set, tau_recover, set_hardening pass through");
    /* zero where zero has a meaning */
    f = base;
    f.alpha = f.spreading = f.k_delta = f.tau_tension = f.tau_bending = f.bend_curvature = 0.0;
    f.tau_set = f.tau_recover = f.set_hardening = f.tension_yield = f.tension_set = 0.0;
    cloth_material m;
    CHECK(cloth_fabric_material(&f, 0.01, 0.01, &m, NULL) == CLOTH_OK, "zeros that mean something");
}

static void check_spacings(void)
{
    const cloth_fabric f = cloth_fabric_preset(CLOTH_FABRIC_COTTON);
    const double bad[] = {NAN, INFINITY, -INFINITY, 0.0, -0.01};
    for (int b = 0; b < 5; b++) {
        char what[64];
        snprintf(what, sizeof what, "dx = %g", bad[b]);
        refused(&f, bad[b], 0.01, "dx", what);
        snprintf(what, sizeof what, "dy = %g", bad[b]);
        refused(&f, 0.01, bad[b], "dy", what);
    }
    cloth_error err;
    CHECK(cloth_fabric_material(NULL, 0.01, 0.01, NULL, &err) == CLOTH_EINVAL && strstr(err.message, "fabric"),
          "NULL fabric: %s", err.message);
    CHECK(cloth_fabric_material(&f, 0.01, 0.01, NULL, &err) == CLOTH_EINVAL && strstr(err.message, "out"),
          "NULL out: %s", err.message);
    /* values past the doubles' range */
    cloth_fabric g = f;
    g.tensile = 1e308;
    g.bend_curvature = 1e-300;
    refused(&g, 1e-3, 1e-3, "out of range", "k_b overflows");
    g = f;
    g.tau_tension = 1e306;
    refused(&g, 0.01, 0.01, "c_t", "c_t overflows");
}

/* The finest spacing: the refusal names it; it is accepted, 0.1% finer not. */
static void check_finest(cloth_fabric_kind kind, double aspect)
{
    cloth_fabric f = cloth_fabric_preset(kind);
    cloth_material out;
    cloth_error err;
    double dx = 1e-4 * aspect, dy = 1e-4, mx = 0.0, my = 0.0;
    CHECK(cloth_fabric_material(&f, dx, dy, &out, &err) == CLOTH_EINVAL, "0.1 mm cells refused");
    const char *at = strstr(err.message, "at least ");
    CHECK(at && sscanf(at, "at least %lg x %lg", &mx, &my) == 2, "finest spacing in \"%s\"", err.message);
    CHECK_REL(mx / my, aspect, 1e-5, 0.0);
    mx *= 1.0 + 1e-4;
    my *= 1.0 + 1e-4;
    CHECK(cloth_fabric_material(&f, mx, my, &out, &err) == CLOTH_OK, "at the finest: %s", err.message);
    /* at the limit the interlaced links carry half the membrane */
    CHECK_NEAR(out.k_t / (out.k_t + 4.0 * out.k_b), 0.5, 0.02);
    refused(&f, mx / 1.001, my / 1.001, "cells of at least", "finer than the finest");
}

static void check_closed_forms(void)
{
    const cloth_fabric_kind kinds[] = {CLOTH_FABRIC_COTTON, CLOTH_FABRIC_WOOL, CLOTH_FABRIC_SILK, CLOTH_FABRIC_DENIM,
                                       CLOTH_FABRIC_POLYESTER};
    for (int i = 0; i < 5; i++) {
        cloth_fabric f = cloth_fabric_preset(kinds[i]);
        CHECK(cloth_fabric_validate(&f, NULL) == CLOTH_OK, "preset %d", i);
        double c = cloth_fabric_bending_length(&f), kref = cloth_fabric_reference_curvature(&f);
        CHECK_REL(c, cbrt(f.bending / (f.density * 9.81)), 1e-14, 0.0);
        CHECK_REL(kref * c, 1.1349, 1e-12, 0.0);
        const double hs[] = {0.05, 0.025, 0.0125};
        for (int k = 0; k < 3; k++) {
            double h = hs[k], S = 0.5 * f.tensile, q = pow(h, 4) / 16.0, Q = f.bending / (2.0 * kref * kref);
            cloth_material m;
            CHECK(cloth_fabric_material(&f, h, h, &m, NULL) == CLOTH_OK, "preset %d at %g m", i, h);
            CHECK(cloth_material_validate(&m, NULL) == CLOTH_OK, "preset %d material", i);
            CHECK_REL(m.k_t + 4.0 * m.k_b, S, 1e-12, 0.0);
            CHECK_REL(4.0 * q * m.k_b * m.k_b + Q * S, q * S * m.k_b, 1e-9, 0.0);
            CHECK(m.k_b >= Q / q && m.k_b <= 2.0 * Q / q, "the root near Q / q");
            CHECK_REL(m.k_c, f.compression * m.k_t, 1e-15, 0.0);
            CHECK_REL(m.k_s, f.spreading * m.k_b, 1e-15, 0.0);
            CHECK_REL(m.c_t, f.tau_tension * m.k_t, 1e-15, 0.0);
            CHECK_REL(m.c_b, f.tau_bending * m.k_b, 1e-15, 0.0);
            CHECK(m.alpha == f.alpha && m.delta == f.delta && m.k_delta == f.k_delta && m.density == f.density &&
                      m.plastic_memory == 0,
                  "pass-through fields");
        }
        /* a stiff membrane: k_b -> 8 B / (h^4 kappa_ref^2) */
        f.tensile = 1e12;
        cloth_material m;
        CHECK(cloth_fabric_material(&f, 0.01, 0.01, &m, NULL) == CLOTH_OK, "stiff membrane");
        CHECK_REL(m.k_b, 8.0 * f.bending / (1e-8 * kref * kref), 1e-6, 0.0);
        check_finest(kinds[i], 1.0);
    }
    check_finest(CLOTH_FABRIC_DENIM, 1.5);
    cloth_fabric a = cloth_fabric_preset((cloth_fabric_kind)99), b = cloth_fabric_preset(CLOTH_FABRIC_COTTON);
    CHECK(memcmp(&a, &b, sizeof a) == 0, "an unknown kind is cotton");
}

static void check_apply(void)
{
    cloth_fabric f = cloth_fabric_preset(CLOTH_FABRIC_WOOL);
    cloth_desc d = cloth_default_desc(), before;
    cloth_error err;
    d.rows = 21;
    d.cols = 11;
    d.width = 0.5;
    d.height = 1.0;
    CHECK(cloth_fabric_apply(&f, &d, &err) == CLOTH_OK, "apply: %s", err.message);
    cloth_material m;
    CHECK(cloth_fabric_material(&f, 0.05, 0.05, &m, NULL) == CLOTH_OK, "material");
    CHECK(memcmp(&m, &d.material, sizeof m) == 0, "apply = material at width / (cols - 1), height / (rows - 1)");
    CHECK(cloth_desc_validate(&d, &err) == CLOTH_OK, "the descriptor validates: %s", err.message);
    before = d;
    d.width = -1.0;
    before.width = -1.0;
    CHECK(cloth_fabric_apply(&f, &d, &err) == CLOTH_EINVAL && strstr(err.message, "width"), "width: %s", err.message);
    d.width = 0.5;
    before.width = 0.5;
    d.rows = 1;
    before.rows = 1;
    CHECK(cloth_fabric_apply(&f, &d, &err) == CLOTH_EINVAL && strstr(err.message, "grid"), "rows: %s", err.message);
    d.rows = 21;
    before.rows = 21;
    f.density = -1.0;
    CHECK(cloth_fabric_apply(&f, &d, &err) == CLOTH_EINVAL && strstr(err.message, "fabric.density"), "density: %s",
          err.message);
    CHECK(memcmp(&d, &before, sizeof d) == 0, "descriptor untouched by refusals");
    CHECK(cloth_fabric_apply(&f, NULL, &err) == CLOTH_EINVAL, "NULL descriptor");
}

int main(void)
{
    check_fields();
    check_spacings();
    check_closed_forms();
    check_apply();
    return check_summary();
}
