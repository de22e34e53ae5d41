/* Cloth triangles against a trimesh (mesh_contacts.c). */
#ifndef ODECLOTH_MESH_CONTACTS_H
#define ODECLOTH_MESH_CONTACTS_H

#include <ccd/ccd.h>
#include "odecloth/dcloth.h"

struct convex_query;

/* The mesh tests' scratch: a trimesh's triangles this step (9 world coordinates and 3 edge flags each:
 * 1 where the surface turns convexly or ends), edges for matching neighbours, and the cloth's triangles
 * in a hash grid */
struct mesh_scratch {
    double *v;
    unsigned char *convex;
    struct mesh_edge {
        double a[3], b[3]; /* the ends, a before b (lexicographic) */
        int tri, e;        /* triangle j, edge e (from corner e to e + 1) */
    } * edges;
    int cap;
    double *grid_box; /* 6 per cloth triangle: its box, grown */
    int *grid_stamp;  /* per cloth triangle: the last mesh triangle + 1 */
    int *grid_head;   /* per bucket: its first entry, -1 if none */
    int *grid_next, *grid_tri;
    long long *grid_key;
    int grid_nbuck, grid_cap;
};

/* Cloth triangle k's box b (6 bounds) for the pairs with a mesh's prisms over the step of h seconds (span:
 * the mesh's diagonal, the most a sweep need cover); 0 leaves the triangle out */
typedef int (*dcloth_tri_bounds)(dClothID c, const struct convex_query *q, int k, double h, double span, double b[6]);
/* One pair: cloth triangle k against q's prism; the vertex contacts it set */
typedef int (*dcloth_pair_test)(dClothID c, struct convex_query *q, int k, double h, ccd_t *ccd, ccd_t *fine);

/* The trimesh q->g's triangles, as prisms, against the cloth triangles near them over the step of h
 * seconds (q: the geom's query, its shape set here; ccd, fine: libccd's loose and tight queries, their
 * first shape set here); the vertex contacts set (none when memory ran out) */
int dcloth_mesh_contacts(dClothID c, struct convex_query *q, double h, ccd_t *ccd, ccd_t *fine);
/* The same pairs for the cloth triangles bounds boxes, each decided by test */
int dcloth_mesh_pairs(dClothID c, struct convex_query *q, double h, ccd_t *ccd, ccd_t *fine, dcloth_tri_bounds bounds,
                      dcloth_pair_test test);

#endif
