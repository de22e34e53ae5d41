/* A flat square plugin cloth for the plugin tests (header-only, static). */
#ifndef ODECLOTH_TEST_PLUGIN_CLOTH_H
#define ODECLOTH_TEST_PLUGIN_CLOTH_H

#include <math.h>

#include "odecloth/dcloth.h"
#include "check.h"

/* o = a x b, and |a| (plain 3-vectors) */
static inline void cross(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double norm3(const double *a) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/* n x n nodes, side L, centred at `centre`, columns along u and rows along
 * v, friction mu and the given thickness; a failed step is an error
 * (DCLOTH_FAILURE_STOP). NULL (and a failed check) on error. */
static inline dClothID flat_cloth(dWorldID w, dSpaceID s, int n, double L, const double centre[3], const double u[3],
                                  const double v[3], double mu, double thickness)
{
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = n;
    d.cloth.width = d.cloth.height = L;
    for (int k = 0; k < 3; k++) {
        d.cloth.axis_u[k] = u[k];
        d.cloth.axis_v[k] = v[k];
        d.cloth.origin[k] = centre[k] - 0.5 * L * (u[k] + v[k]);
    }
    d.mu = mu;
    d.thickness = thickness;
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, s, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) return NULL;
    dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
    return c;
}

/* A box as 12 triangles, counter-clockwise from outside, half sides e:
 * vertices v and indices t for dGeomTriMeshDataBuildDouble. */
static inline void box_mesh(const double e[3], dReal v[24], dTriIndex t[36])
{
    static const int q[24] = {1, 3, 7, 5, 0, 4, 6, 2, 2, 6, 7, 3, 0, 1, 5, 4, 4, 5, 7, 6, 0, 2, 3, 1};
    for (int i = 0; i < 8; i++)
        for (int k = 0; k < 3; k++) v[3 * i + k] = (i >> k & 1) ? e[k] : -e[k];
    for (int f = 0; f < 6; f++) {
        const int *a = q + 4 * f;
        dTriIndex *o = t + 6 * f;
        o[0] = a[0], o[1] = a[1], o[2] = a[2];
        o[3] = a[0], o[4] = a[2], o[5] = a[3];
    }
}

/* A box of half sides e in space s: ODE's box geom, or (mesh nonzero) the
 * same box as 12 triangles built from v and t into *td (0 for a box geom). */
static inline dGeomID box_geom(dSpaceID s, const double e[3], int mesh, dReal v[24], dTriIndex t[36],
                               dTriMeshDataID *td)
{
    *td = 0;
    if (!mesh) return dCreateBox(s, 2 * e[0], 2 * e[1], 2 * e[2]);
    box_mesh(e, v, t);
    *td = dGeomTriMeshDataCreate();
    dGeomTriMeshDataBuildDouble(*td, v, 3 * sizeof(dReal), 8, t, 36, 3 * sizeof(dTriIndex));
    return dCreateTriMesh(s, *td, 0, 0, 0);
}

/* A sphere of mass m (radius 5 cm) in world w holding cloth c by its
 * vertices 0 and 1, its centre halfway between them. */
static inline dBodyID sphere_holding(dWorldID w, dClothID c, double m)
{
    const dReal *x = dClothGetPositions(c);
    dBodyID b = dBodyCreate(w);
    dMass ms;
    dMassSetSphereTotal(&ms, m, 0.05);
    dBodySetMass(b, &ms);
    double p0[3] = {0.5 * (x[0] + x[3]), 0.5 * (x[1] + x[4]), 0.5 * (x[2] + x[5])};
    dBodySetPosition(b, p0[0], p0[1], p0[2]);
    for (int k = 0; k < 2; k++) {
        dReal lp[3] = {x[3 * k] - p0[0], x[3 * k + 1] - p0[1], x[3 * k + 2] - p0[2]};
        CHECK(dClothPinToBody(c, k, b, lp) == CLOTH_OK, "dClothPinToBody: %s", dClothGetLastError(c));
    }
    return b;
}

#endif
