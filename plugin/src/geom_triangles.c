/* An ODE geom as triangles, in the world frame: a box's faces or a
 * trimesh's triangles, for the triangle and link tests. */
#include <string.h>
#include "dcloth_internal.h"
#include "geom_triangles.h"

int dcloth_geom_triangle_count(dGeomID g, int cls) { return cls == dBoxClass ? 12 : dGeomTriMeshGetTriangleCount(g); }

void dcloth_geom_triangles(dGeomID g, int cls, int nt, double *tb)
{
    if (cls == dBoxClass) {
        dVector3 L;
        dGeomBoxGetLengths(g, L);
        const dReal *o = dGeomGetPosition(g), *R = dGeomGetRotation(g);
        double corner[8][3];
        for (int k = 0; k < 8; k++) {
            double l[3] = {(k & 1 ? 0.5 : -0.5) * L[0], (k & 2 ? 0.5 : -0.5) * L[1], (k & 4 ? 0.5 : -0.5) * L[2]};
            for (int r = 0; r < 3; r++)
                corner[k][r] = o[r] + R[4 * r] * l[0] + R[4 * r + 1] * l[1] + R[4 * r + 2] * l[2];
        }
        /* face (axis a, side s): its corners in turn around it, two triangles */
        for (int a = 0; a < 3; a++)
            for (int s = 0; s < 2; s++) {
                int u = 1 << ((a + 1) % 3), v = 1 << ((a + 2) % 3), base = s << a;
                int q[4] = {base, base | u, base | u | v, base | v};
                int f = 2 * (2 * a + s), tri[2][3] = {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}};
                for (int m = 0; m < 2; m++)
                    for (int e = 0; e < 3; e++) memcpy(tb + 9 * (f + m) + 3 * e, corner[tri[m][e]], sizeof corner[0]);
            }
    } else {
        for (int j = 0; j < nt; j++) {
            dVector3 a, b, e;
            dGeomTriMeshGetTriangle(g, j, &a, &b, &e);
            for (int r = 0; r < 3; r++) tb[9 * j + r] = a[r], tb[9 * j + 3 + r] = b[r], tb[9 * j + 6 + r] = e[r];
        }
    }
}
