/* Per-geom switches (dClothSetTriangleTests, dClothSetExactTriangleTests,
 * dClothSetEdgeTests): each a list of geoms, read by the contact stages. */
#include <stdlib.h>
#include "dcloth_internal.h"

int dcloth_geom_list_set(dClothID c, dcloth_geom_list *l, dGeomID g, int in, const char *who)
{
    int at = 0;
    while (at < l->n && l->g[at] != g) at++;
    if (!in) {
        if (at < l->n) l->g[at] = l->g[--l->n];
    } else if (at == l->n) {
        if (l->n == l->cap) {
            int cap = l->cap ? 2 * l->cap : 4;
            dGeomID *p = realloc(l->g, (size_t)cap * sizeof *p);
            if (!p) return dcloth_fail(c, CLOTH_ENOMEM, "%s: out of memory", who);
            l->g = p;
            l->cap = cap;
        }
        l->g[l->n++] = g;
    }
    dClothWake(c);
    return CLOTH_OK;
}

int dcloth_geom_list_has(const dcloth_geom_list *l, dGeomID g)
{
    for (int k = 0; k < l->n; k++)
        if (l->g[k] == g) return 1;
    return 0;
}

cloth_status dClothSetTriangleTests(dClothID c, dGeomID g, int enable)
{
    if (!c) return CLOTH_EINVAL;
    if (!g) return dcloth_fail(c, CLOTH_EINVAL, "dClothSetTriangleTests: geom is 0");
    return dcloth_geom_list_set(c, &c->tri_off, g, !enable, "dClothSetTriangleTests");
}

int dClothGetTriangleTests(dClothID c, dGeomID g) { return c && g && !dcloth_geom_list_has(&c->tri_off, g); }

cloth_status dClothSetExactTriangleTests(dClothID c, dGeomID g, int enable)
{
    if (!c) return CLOTH_EINVAL;
    if (!g) return dcloth_fail(c, CLOTH_EINVAL, "dClothSetExactTriangleTests: geom is 0");
    if (dGeomGetClass(g) != dBoxClass)
        return dcloth_fail(c, CLOTH_EINVAL, "dClothSetExactTriangleTests: the geom is not a box (class %d)",
                           dGeomGetClass(g));
    return dcloth_geom_list_set(c, &c->tri_epa, g, enable == 0, "dClothSetExactTriangleTests");
}

int dClothGetExactTriangleTests(dClothID c, dGeomID g)
{
    return c && g && dGeomGetClass(g) == dBoxClass && !dcloth_geom_list_has(&c->tri_epa, g);
}

cloth_status dClothSetEdgeTests(dClothID c, dGeomID g, int enable)
{
    if (!c) return CLOTH_EINVAL;
    if (!g) return dcloth_fail(c, CLOTH_EINVAL, "dClothSetEdgeTests: geom is 0");
    return dcloth_geom_list_set(c, &c->edge_off, g, !enable, "dClothSetEdgeTests");
}

int dClothGetEdgeTests(dClothID c, dGeomID g) { return c && g && !dcloth_geom_list_has(&c->edge_off, g); }
