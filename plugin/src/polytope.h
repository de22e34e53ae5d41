/* A cloth triangle, grown by a radius, against a convex polytope by separating axes (polytope.c): the
 * contact's depth, direction and point decided by the geometry. */
#ifndef ODECLOTH_POLYTOPE_H
#define ODECLOTH_POLYTOPE_H

/* A convex polytope in the world frame (a box) */
typedef struct dcloth_polytope {
    int nv, nf, ne;
    double v[8][3]; /* vertices                                              */
    double n[6][3]; /* faces' outward unit normals                           */
    int face[6][4]; /* each face's vertices, in order around it              */
    int fv[6];      /* how many (3 or 4)                                     */
    double e[6][3]; /* the distinct directions of its edges, unit            */
} dcloth_polytope;

/* Box of half sides half[3] at o with rotation R (ODE's 3x4, row-major) into P */
void dcloth_polytope_box(dcloth_polytope *P, const double o[3], const double *R, const double half[3]);
/* Triangle t grown by r against P, as libccd's penetration query answers: the depth, the unit direction n
 * to move the triangle by to separate and a point between the two surfaces. 1 when answered (the least axis
 * met by its features, or apart, the nearest points), -1 apart beyond r, 0 for EPA (t inside P, or NaN) */
int dcloth_polytope_query(const dcloth_polytope *P, const double *const t[3], double r, double *depth, double n[3],
                          double pos[3]);

#endif
