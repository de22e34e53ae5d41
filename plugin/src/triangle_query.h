/* One cloth triangle against one convex shape of a geom (triangle_query.c). */
#ifndef ODECLOTH_TRIANGLE_QUERY_H
#define ODECLOTH_TRIANGLE_QUERY_H

#include <ccd/ccd.h>
#include "dcloth_internal.h"
#include "polytope.h"

/* What one convex shape of geom g (the geom itself, or one triangle of a
 * mesh) offers the cloth's triangles. */
typedef struct convex_query {
    const void *shape;
    ccd_support_fn support;
    ccd_center_fn center;
    const double *face;          /* a mesh triangle's outward unit normal, or NULL */
    double out[3][3];            /* its edges' outward normals in its plane          */
    const unsigned char *convex; /* its edges' flags (mesh_convex)         */
    double aabb[6];              /* the shape's, world frame */
    double span;                 /* its diagonal */
    dGeomID g;
    dBodyID body;
    const struct dcloth_surf *surf; /* the geom's mu and thickness this step */
    double travel;                  /* m: the most any point of the geom moves in the step */
    int moving;                     /* the geom moves more than SWEEP_NEGLIGIBLE per step */
    int cls;                        /* the geom's class (dTriMeshClass: face is set) */
    const dcloth_polytope *poly;    /* the shape as a polytope (an exact box), or NULL */
    const double *x, *v;            /* the cloth's positions and velocities tested; NULL: its own */
    double reach_min;               /* m: the least sweep a triangle is tested over */
} convex_query;

/* libccd's support and centre of a cloth triangle grown by a radius (the query's second shape) */
void dcloth_tri_support(const void *obj, const ccd_vec3_t *dir, ccd_vec3_t *out);
void dcloth_tri_center(const void *obj, ccd_vec3_t *out);
/* libccd set up for a geom (obj1, a dcloth_geom_shape) against a grown triangle (obj2) at thickness t:
 * the loose query's and the tight one's */
void dcloth_triangle_ccd(double t, ccd_t *loose, ccd_t *fine);
/* Cloth triangle k against q's shape over the step of h seconds (ccd: libccd's loose query, fine: its tight
 * one): sets its vertices' contacts where deeper than what they have; returns how many it set. */
int dcloth_triangle_query(dClothID c, const convex_query *q, int k, double h, ccd_t *ccd, ccd_t *fine);
/* Triangle v[] grown by radius into q's shape, as the triangle queries see it (ccd: libccd's settings
 * where EPA answers): 0 when they overlap, with the depth, the unit direction from the shape toward the
 * triangle and a point between them; -1 apart */
int dcloth_triangle_penetration(const convex_query *q, const double *const v[3], double radius, const ccd_t *ccd,
                                double *depth, double dir[3], double pos[3]);
/* Merges the contact along n with gap (point pt, the body's velocity vb there, weight w on the vertex) from cloth
 * triangle k into vc where it ties with vc's, from another triangle on q's geom (exact tests): 1 if merged */
int dcloth_merge_tie(dClothID c, const convex_query *q, vcontact *vc, int k, const double n[3], double gap,
                     const double pt[3], const double vb[3], double w);
/* the diagonal of a box (6 bounds: x lo, x hi, y lo, ...) */
double dcloth_diagonal(const double aabb[6]);

#endif
