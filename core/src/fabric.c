/* A fabric in physical units turned into the links' material for one grid
 * spacing. The derivation of every factor is in docs/materials.md. */
#include <math.h>
#include "odecloth/fabric.h"
#include "internal.h"

/* eta = kappa_ref c: with the interlaced links' quartic bending energy
 * matched to B kappa^2 / 2 at eta / c, a cantilever of overhang 2 c droops
 * to 41.5 degrees (docs/materials.md, "The cantilever's curvature"). */
#define FABRIC_CANTILEVER_ETA 1.1349

cloth_status cloth_fabric_validate(const cloth_fabric *f, cloth_error *err)
{
    if (!f) return oc_error_set(err, CLOTH_EINVAL, "fabric is NULL");
    const struct {
        const char *name;
        double v;
        int positive;
    } q[] = {
        {"tensile", f->tensile, 1},
        {"bending", f->bending, 1},
        {"density", f->density, 1},
        {"compression", f->compression, 1},
        {"alpha", f->alpha, 0},
        {"spreading", f->spreading, 0},
        {"delta", f->delta, 1},
        {"k_delta", f->k_delta, 0},
        {"tau_tension", f->tau_tension, 0},
        {"tau_bending", f->tau_bending, 0},
        {"bend_curvature", f->bend_curvature, 0},
        {"tau_set", f->tau_set, 0},
        {"tau_recover", f->tau_recover, 0},
        {"set_hardening", f->set_hardening, 0},
        {"tension_yield", f->tension_yield, 0},
        {"tension_set", f->tension_set, 0},
        {"crease_stiffness", f->crease_stiffness, 0},
    };
    for (size_t k = 0; k < sizeof q / sizeof q[0]; k++) {
        if (!isfinite(q[k].v)) return oc_error_set(err, CLOTH_EINVAL, "fabric.%s is not finite", q[k].name);
        if (q[k].positive ? !(q[k].v > 0.0) : q[k].v < 0.0)
            return oc_error_set(err, CLOTH_EINVAL, "fabric.%s = %g must be %s", q[k].name, q[k].v,
                                q[k].positive ? "> 0" : ">= 0");
    }
    if (f->alpha > 1.0) return oc_error_set(err, CLOTH_EINVAL, "fabric.alpha = %g must be in [0, 1]", f->alpha);
    if (f->set_hardening > 1.0)
        return oc_error_set(err, CLOTH_EINVAL, "fabric.set_hardening = %g must be in [0, 1]", f->set_hardening);
    if (f->tension_yield > f->delta)
        return oc_error_set(err, CLOTH_EINVAL, "fabric.tension_yield = %g must be in [0, delta = %g]", f->tension_yield,
                            f->delta);
    if (f->tension_set > 1.0)
        return oc_error_set(err, CLOTH_EINVAL, "fabric.tension_set = %g must be in [0, 1]", f->tension_set);
    if (f->crease_stiffness > 0.0 && (f->tau_set > 0.0 || f->tau_recover > 0.0 || f->set_hardening > 0.0))
        return oc_error_set(err, CLOTH_EINVAL,
                            "fabric.crease_stiffness = %g takes the crease law: tau_set, "
                            "tau_recover and set_hardening must be 0",
                            f->crease_stiffness);
    return CLOTH_OK;
}

double cloth_fabric_bending_length(const cloth_fabric *f)
{
    if (cloth_fabric_validate(f, NULL) != CLOTH_OK) return NAN;
    return cbrt(f->bending / (f->density * CLOTH_FABRIC_GRAVITY));
}

double cloth_fabric_reference_curvature(const cloth_fabric *f)
{
    if (cloth_fabric_validate(f, NULL) != CLOTH_OK) return NAN;
    if (f->bend_curvature > 0.0) return f->bend_curvature;
    return FABRIC_CANTILEVER_ETA / cloth_fabric_bending_length(f);
}

/* Membrane stiffness per unit k_t along the cells' a side (b across it),
 * uniaxial strain: the a-links give a / b, the two diagonals 2 a^3 / (b L^2). */
static double tension_per_k(double a, double b) { return a / b + 2.0 * a * a * a / (b * (a * a + b * b)); }

/* Bending energy per area per unit k_b kappa^4, bent along side a: the
 * a-links shorten by a^3 kappa^2 / 4, the diagonals by a^4 kappa^2 / (4 L). */
static double bending_per_k(double a, double b)
{
    return pow(a, 5) / (32.0 * b) * (1.0 + 2.0 * a * a / (a * a + b * b));
}

static cloth_status spacing_check(double v, const char *name, cloth_error *err)
{
    if (!isfinite(v) || !(v > 0.0))
        return oc_error_set(err, CLOTH_EINVAL, "fabric spacing %s = %g m must be finite and > 0", name, v);
    return CLOTH_OK;
}

/* k_t and k_b for dx x dy cells: membrane k_t + 4 k_b = S = tensile / t (the interlaced lattice as
 * the sequential one with double links); bending matches B kappa^2 / 2 at kappa_ref, the quadratic's
 * root that tends to Q / q for a stiff membrane (derivation: docs/materials.md, "Design notes"). */
static cloth_status link_stiffnesses(const cloth_fabric *f, double dx, double dy, double *k_t, double *k_b,
                                     cloth_error *err)
{
    double kref = cloth_fabric_reference_curvature(f);
    double t = 0.5 * (tension_per_k(dx, dy) + tension_per_k(dy, dx));
    double q = 0.5 * (bending_per_k(dx, dy) + bending_per_k(dy, dx));
    double S = f->tensile / t, Q = f->bending / (2.0 * kref * kref), r = 16.0 * Q / (q * S);
    if (!(r <= 1.0) && isfinite(r)) {
        double grow = pow(r, 0.25); /* q S grows as the spacing^4 */
        return oc_error_set(err, CLOTH_EINVAL,
                            "fabric material at spacing %g x %g m: the interlaced links cannot give the fabric's "
                            "bending (B %g N m at kappa_ref %g 1/m) within its tensile stiffness %g N/m; use cells of "
                            "at least %g x %g m (or a larger bend_curvature)",
                            dx, dy, f->bending, kref, f->tensile, dx * grow, dy * grow);
    }
    *k_b = 2.0 * Q / (q * (1.0 + sqrt(1.0 - r)));
    *k_t = S - 4.0 * *k_b;
    return CLOTH_OK;
}

/* The crease law's hinge stiffness for a moment S per length and radian near flat: a hinge of a link with
 * halves dx turns its middle node with k dx^2 / 4 per radian, one per dy of crease, so k = 4 S dy / dx^2;
 * the mean of the two thread directions. */
static double crease_per_link(double S, double dx, double dy) { return 2.0 * S * (dy / (dx * dx) + dx / (dy * dy)); }

cloth_status cloth_fabric_material(const cloth_fabric *f, double dx, double dy, cloth_material *out, cloth_error *err)
{
    cloth_status s = cloth_fabric_validate(f, err);
    if (s != CLOTH_OK) return s;
    if ((s = spacing_check(dx, "dx", err)) != CLOTH_OK || (s = spacing_check(dy, "dy", err)) != CLOTH_OK) return s;
    if (!out) return oc_error_set(err, CLOTH_EINVAL, "fabric material: out is NULL");
    cloth_material m = {0};
    if ((s = link_stiffnesses(f, dx, dy, &m.k_t, &m.k_b, err)) != CLOTH_OK) return s;
    m.k_c = f->compression * m.k_t;
    m.k_s = f->spreading * m.k_b;
    m.alpha = f->alpha;
    m.delta = f->delta;
    m.k_delta = f->k_delta;
    m.c_t = f->tau_tension * m.k_t;
    m.c_b = f->tau_bending * m.k_b;
    m.density = f->density;
    m.plastic_memory = 0;
    m.tau_set = f->tau_set;
    m.tau_recover = f->tau_recover;
    m.set_hardening = f->set_hardening;
    m.tension_yield = f->tension_yield;
    m.tension_set = f->tension_set;
    m.k_crease = crease_per_link(f->crease_stiffness, dx, dy);
    /* a fabric and spacing of extreme scales can overflow or underflow */
    const struct {
        const char *name;
        double v;
        int positive;
    } r[] = {{"k_t", m.k_t, 1}, {"k_c", m.k_c, 1}, {"k_b", m.k_b, 1},          {"k_s", m.k_s, 0},
             {"c_t", m.c_t, 0}, {"c_b", m.c_b, 0}, {"k_crease", m.k_crease, 0}};
    for (size_t k = 0; k < sizeof r / sizeof r[0]; k++)
        if (!isfinite(r[k].v) || (r[k].positive && !(r[k].v > 0.0)))
            return oc_error_set(err, CLOTH_EINVAL, "fabric material at spacing %g x %g m: %s = %g is out of range", dx,
                                dy, r[k].name, r[k].v);
    if ((s = cloth_material_validate(&m, err)) != CLOTH_OK) return s;
    *out = m;
    return CLOTH_OK;
}

cloth_status cloth_fabric_apply(const cloth_fabric *f, cloth_desc *d, cloth_error *err)
{
    if (!d) return oc_error_set(err, CLOTH_EINVAL, "fabric apply: descriptor is NULL");
    if (d->rows < 2 || d->cols < 2)
        return oc_error_set(err, CLOTH_EINVAL, "fabric apply: grid %d x %d has no cells", d->rows, d->cols);
    if (!isfinite(d->width) || !(d->width > 0.0) || !isfinite(d->height) || !(d->height > 0.0))
        return oc_error_set(err, CLOTH_EINVAL, "fabric apply: size %g x %g m: width and height must be finite and > 0",
                            d->width, d->height);
    return cloth_fabric_material(f, d->width / (d->cols - 1), d->height / (d->rows - 1), &d->material, err);
}
