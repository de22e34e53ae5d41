/* Fabric presets (paper Table 1: delta, alpha, k_s) and parameter validation; the other values are
 * ours, in SI units, for a cloth of about 1 m at 21 x 21 nodes. Why each value: docs/materials.md,
 * "Design notes from the code". */
#include <math.h>
#include "internal.h"

cloth_material cloth_material_preset(cloth_preset p)
{
    cloth_material cotton = {
        .k_t = 2000.0,
        .k_c = 50.0,
        .k_b = 20.0,
        .k_s = 10.0,
        .alpha = 0.8,
        .delta = 0.03,
        .k_delta = 100.0,
        .c_t = 0.02,
        .c_b = 0.002,
        .density = 0.2,
    };
    switch (p) {
    case CLOTH_WOOL: {
        cloth_material wool = {
            .k_t = 500.0,
            .k_c = 12.5,
            .k_b = 10.0,
            .k_s = 0.1,
            .alpha = 0.1,
            .delta = 0.1,
            .k_delta = 100.0,
            .c_t = 0.01,
            .c_b = 0.001,
            .density = 0.3,
        };
        return wool;
    }
    case CLOTH_ELASTIC: cotton.alpha = 0.0; return cotton;
    case CLOTH_COTTON:
    default: return cotton;
    }
}

static int bad(double x) { return !isfinite(x); }

cloth_status cloth_material_validate(const cloth_material *m, cloth_error *err)
{
    if (!m) return oc_error_set(err, CLOTH_EINVAL, "material is NULL");
    const struct {
        const char *name;
        double v;
        int positive;
    } f[] = {
        {"k_t", m->k_t, 1},
        {"k_c", m->k_c, 0},
        {"k_b", m->k_b, 0},
        {"k_s", m->k_s, 0},
        {"alpha", m->alpha, 0},
        {"delta", m->delta, 1},
        {"k_delta", m->k_delta, 0},
        {"c_t", m->c_t, 0},
        {"c_b", m->c_b, 0},
        {"density", m->density, 1},
        {"tau_set", m->tau_set, 0},
        {"tau_recover", m->tau_recover, 0},
        {"set_hardening", m->set_hardening, 0},
        {"tension_yield", m->tension_yield, 0},
        {"tension_set", m->tension_set, 0},
        {"k_crease", m->k_crease, 0},
    };
    for (size_t k = 0; k < sizeof f / sizeof f[0]; k++) {
        if (bad(f[k].v)) return oc_error_set(err, CLOTH_EINVAL, "material.%s is not finite", f[k].name);
        if (f[k].positive ? !(f[k].v > 0.0) : f[k].v < 0.0)
            return oc_error_set(err, CLOTH_EINVAL, "material.%s = %g must be %s", f[k].name, f[k].v,
                                f[k].positive ? "> 0" : ">= 0");
    }
    if (m->alpha > 1.0) return oc_error_set(err, CLOTH_EINVAL, "material.alpha = %g must be in [0, 1]", m->alpha);
    if (m->set_hardening > 1.0)
        return oc_error_set(err, CLOTH_EINVAL, "material.set_hardening = %g must be in [0, 1]", m->set_hardening);
    if (m->tension_yield > m->delta)
        return oc_error_set(err, CLOTH_EINVAL, "material.tension_yield = %g must be in [0, delta = %g]",
                            m->tension_yield, m->delta);
    if (m->tension_set > 1.0)
        return oc_error_set(err, CLOTH_EINVAL, "material.tension_set = %g must be in [0, 1]", m->tension_set);
    if (m->k_crease > 0.0 && oc_plastic_time_on(m))
        return oc_error_set(err, CLOTH_EINVAL,
                            "material.k_crease = %g takes the crease law: tau_set, tau_recover and "
                            "set_hardening must be 0",
                            m->k_crease);
    if (m->plastic_memory != 0 && m->plastic_memory != 1)
        return oc_error_set(err, CLOTH_EINVAL, "material.plastic_memory = %d must be 0 or 1", m->plastic_memory);
    return CLOTH_OK;
}

cloth_status cloth_solver_validate(const cloth_solver *s, cloth_error *err)
{
    if (!s) return oc_error_set(err, CLOTH_EINVAL, "solver is NULL");
    if ((int)s->method < CLOTH_BACKWARD_EULER || (int)s->method > CLOTH_BDF2)
        return oc_error_set(err, CLOTH_EINVAL, "solver.method = %d is not a cloth_method", (int)s->method);
    if ((int)s->precond < CLOTH_PRECOND_BLOCK_JACOBI || (int)s->precond > CLOTH_PRECOND_AUTO)
        return oc_error_set(err, CLOTH_EINVAL, "solver.precond = %d is not a cloth_precond", (int)s->precond);
    if (!(s->cg_tolerance > 0.0 && s->cg_tolerance < 1.0))
        return oc_error_set(err, CLOTH_EINVAL, "solver.cg_tolerance = %g must be in (0, 1)", s->cg_tolerance);
    if (s->cg_max_iterations < 1)
        return oc_error_set(err, CLOTH_EINVAL, "solver.cg_max_iterations = %d must be >= 1", s->cg_max_iterations);
    if (s->strain_limit_iterations < 0)
        return oc_error_set(err, CLOTH_EINVAL, "solver.strain_limit_iterations = %d must be >= 0",
                            s->strain_limit_iterations);
    if (!(s->strain_fail > 0.0) || bad(s->strain_fail))
        return oc_error_set(err, CLOTH_EINVAL, "solver.strain_fail = %g must be finite and > 0", s->strain_fail);
    if (s->max_substep_halvings < 0 || s->max_substep_halvings > 16)
        return oc_error_set(err, CLOTH_EINVAL, "solver.max_substep_halvings = %d must be in [0, 16]",
                            s->max_substep_halvings);
    if ((int)s->nonlinear < CLOTH_LINEARIZED || (int)s->nonlinear > CLOTH_NEWTON)
        return oc_error_set(err, CLOTH_EINVAL, "solver.nonlinear = %d is not a cloth_nonlinear", (int)s->nonlinear);
    if (s->newton_iterations < 0 || s->newton_iterations > 256)
        return oc_error_set(err, CLOTH_EINVAL, "solver.newton_iterations = %d must be in [0, 256]",
                            s->newton_iterations);
    if (s->nonlinear == CLOTH_NEWTON && s->newton_iterations < 1)
        return oc_error_set(err, CLOTH_EINVAL, "solver.newton_iterations = %d must be >= 1 with CLOTH_NEWTON",
                            s->newton_iterations);
    if (!(s->newton_tolerance > 0.0) || bad(s->newton_tolerance))
        return oc_error_set(err, CLOTH_EINVAL, "solver.newton_tolerance = %g must be finite and > 0",
                            s->newton_tolerance);
    if (!(s->newton_rtol >= 0.0 && s->newton_rtol < 1.0))
        return oc_error_set(err, CLOTH_EINVAL, "solver.newton_rtol = %g must be in [0, 1)", s->newton_rtol);
    if (!(s->limit_tolerance > 0.0 && s->limit_tolerance < 1.0))
        return oc_error_set(err, CLOTH_EINVAL, "solver.limit_tolerance = %g must be in (0, 1)", s->limit_tolerance);
    if (!(s->newton_cg_tolerance > 0.0 && s->newton_cg_tolerance < 1.0))
        return oc_error_set(err, CLOTH_EINVAL, "solver.newton_cg_tolerance = %g must be in (0, 1)",
                            s->newton_cg_tolerance);
    if (!(s->newton_cg_share >= 0.0 && s->newton_cg_share < 1.0))
        return oc_error_set(err, CLOTH_EINVAL, "solver.newton_cg_share = %g must be in [0, 1)", s->newton_cg_share);
    if (s->keep_unconverged != 0 && s->keep_unconverged != 1)
        return oc_error_set(err, CLOTH_EINVAL, "solver.keep_unconverged = %d must be 0 or 1", s->keep_unconverged);
    return CLOTH_OK;
}
