/* A count of a triangle mesh's self-intersections: the pairs of triangles
 * that share no vertex where an edge of one crosses the other (passes from
 * one side of its plane to the other inside it).
 *
 * Broadphase: a uniform grid of cubic cells holding each triangle's
 * bounding box; a pair is tested once, in the cell holding the minimum
 * corner of the overlap of its two boxes, however many cells both share.
 *
 * Robustness: a signed volume within INTERSECTIONS_FLAT of the cube of the
 * pair's spread (the largest side of its six points' box) counts as no
 * side, so coplanar or touching triangles never cross, and a flat sheet
 * moved rigidly does not cross itself through rounding.
 *
 * Plain C (no ODE): the test utilities and examples/obj_intersections use it.
 */
#ifndef ODECLOTH_EXAMPLES_INTERSECTIONS_H
#define ODECLOTH_EXAMPLES_INTERSECTIONS_H

#define INTERSECTIONS_FLAT 1e-12

typedef struct intersections {
    long pairs;   /* intersecting pairs of triangles */
    int vertices; /* vertices of their triangles */
} intersections;

/* Counts the intersecting pairs of the nt triangles tri (3 vertex indices
 * each, into the nv points x, 3 doubles each). mark (nv bytes, or NULL) is
 * set to 1 at the vertices of the intersecting pairs' triangles, 0
 * elsewhere. Returns 0; -1 (out and mark zeroed) when an index is out of range, a
 * used coordinate is not finite, or memory ran out. */
int intersections_count(const double *x, int nv, const int *tri, int nt, intersections *out, unsigned char *mark);

/* Whether triangles ta and tb (3 indices each into x) intersect, as
 * intersections_count decides it for one pair; 0 when they share a vertex. */
int intersections_pair(const double *x, const int *ta, const int *tb);

/* The triangles of a rows x cols grid of vertices (row-major), 2 per cell,
 * as the plugin's dClothGetTriangles lists them: cell (r, k) split along
 * its (r, k)-(r + 1, k + 1) diagonal. tri holds 6 (rows - 1) (cols - 1)
 * ints; returns the triangle count. */
int intersections_grid_triangles(int rows, int cols, int *tri);

#endif
