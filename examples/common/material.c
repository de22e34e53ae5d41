/* The material a demo's options choose: demo_material in demo.h. */
#include "demo.h"
#include "odecloth/fabric.h"

int demo_fabric_chosen(const demo_opts *o, int fabric_default)
{
    return o->fabric ? o->fabric : o->material_set ? 0 : fabric_default;
}

int demo_material(const demo_opts *o, double size, int fabric_default, cloth_material *out)
{
    int fabric = demo_fabric_chosen(o, fabric_default);
    cloth_material m = cloth_material_preset(o->material);
    if (fabric) {
        /* the fabric's springs for this grid's spacing: the same cloth at every grid */
        cloth_fabric f = cloth_fabric_preset((cloth_fabric_kind)(fabric - 1));
        double h = size / (o->grid - 1);
        cloth_error err;
        if (cloth_fabric_material(&f, h, h, &m, &err) != CLOTH_OK) {
            fprintf(stderr, "%s: fabric at grid %d: %s\n", o->prog, o->grid, err.message);
            return -1;
        }
    }
    if (o->k_b > 0.0) m.k_b = o->k_b;
    if (o->memory >= 0) m.plastic_memory = o->memory;
    /* a crease's moment per length: the link stiffness for this spacing (cloth_fabric's crease_stiffness) */
    if (o->crease_law > 0.0) m.k_crease = 4.0 * o->crease_law * (o->grid - 1) / size;
    *out = m;
    return 0;
}
