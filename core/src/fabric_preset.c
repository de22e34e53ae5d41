/* Fabric presets in physical units. Where each value comes from, and which
 * are estimates, is in docs/materials.md ("Presets"). */
#include "odecloth/fabric.h"

/* weight w (kg/m^2), ASTM D1388 bending length c (m), B = w g c^3, and the
 * KES-F tensile secant 500 gf/cm / EMT (N/m) */
static cloth_fabric fabric(double w, double c, double tensile, double delta, double alpha, double spreading)
{
    cloth_fabric f = {
        .tensile = tensile,
        .bending = w * CLOTH_FABRIC_GRAVITY * c * c * c,
        .density = w,
        .compression = 0.025,
        .alpha = alpha,
        .spreading = spreading,
        .delta = delta,
        .k_delta = 100.0,
        .tau_tension = 1e-5,
        .tau_bending = 1e-4,
        .bend_curvature = 0.0,
    };
    return f;
}

#define KES_500GF_PER_CM 490.3325 /* N/m: the load at which KES-F reads EMT */

cloth_fabric cloth_fabric_preset(cloth_fabric_kind k)
{
    switch (k) {
    case CLOTH_FABRIC_WOOL: return fabric(0.28, 0.024, KES_500GF_PER_CM / 0.08, 0.10, 0.1, 0.01);
    case CLOTH_FABRIC_SILK: return fabric(0.06, 0.014, KES_500GF_PER_CM / 0.10, 0.08, 0.5, 0.1);
    case CLOTH_FABRIC_DENIM: return fabric(0.40, 0.035, KES_500GF_PER_CM / 0.055, 0.03, 0.8, 0.5);
    case CLOTH_FABRIC_POLYESTER: return fabric(0.10, 0.020, KES_500GF_PER_CM / 0.03, 0.03, 0.1, 0.01);
    case CLOTH_FABRIC_COTTON:
    default: return fabric(0.13, 0.022, KES_500GF_PER_CM / 0.04, 0.03, 0.8, 0.5);
    }
}
