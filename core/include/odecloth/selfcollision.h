/*
 * odecloth core: cloth against itself (self-collision), an optional pass
 * after each step.
 *
 * The paper's cloth meets bodies only (vertex against triangle mesh); with
 * soft bending a cloth folds onto itself and, without this pass, through
 * itself. The pass keeps every vertex at least `thickness` from each of the
 * cloth's triangles it is not a corner of, on the side of the triangle it
 * was on after the previous pass (so a vertex that crossed a triangle within
 * one step is put back, not pushed through). Each vertex-triangle pair
 * closer than that is separated along the triangle's normal by moving the
 * vertex and the triangle's corners in inverse proportion to their masses
 * (the corners weighted by the barycentric coordinates of the closest
 * point; Bridson, Fedkiw, Anderson 2002, sec. 7), and their relative
 * velocity along the normal, if approaching, is cancelled the same way (an
 * inelastic contact). Vertices held by a constraint (pins, body contacts)
 * are not moved. Edge-against-edge crossings are not detected.
 *
 *   cloth_self_collision *sc;
 *   cloth_self_collision_create(c, 0.005, &sc, &err);
 *   for (;;) { cloth_step(c, h, NULL); cloth_self_collision_apply(sc, c, NULL); }
 *   cloth_self_collision_destroy(sc);
 *
 * An apply also binds the pass to c: from then on each CLOTH_NEWTON step of
 * c keeps its vertices from passing through its triangles and its edges
 * through its edges (a barrier within the thickness in the step's
 * potential, every Newton update stopped short of a touch), until the pass
 * or c is destroyed or the pass is applied to another cloth. A smallest
 * substep the barrier cannot take is taken without it (cloth_step_stats'
 * self_contact_dropped), its pairs left to the pass.
 *
 * The first apply only records the positions (the sides). Workspaces are
 * sized at creation; apply allocates nothing. An apply that moves vertices
 * writes them with cloth_set_positions / cloth_set_velocities, so BDF2
 * restarts from backward Euler after it (as after any such call); the
 * layers slide on each other without friction.
 */
#ifndef ODECLOTH_SELFCOLLISION_H
#define ODECLOTH_SELFCOLLISION_H

#include "cloth.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct cloth_self_collision cloth_self_collision;

typedef struct cloth_self_collision_stats {
    int pairs;      /* vertex-triangle pairs separated, over all passes  */
    int crossings;  /* of which the vertex had crossed the triangle      */
    double closest; /* m, smallest vertex-triangle distance found before
                       separation (negative: crossed), HUGE_VAL if none   */
} cloth_self_collision_stats;

/* thickness: m, in (0, 1] and under du dv / sqrt(du^2 + dv^2) for cells du x dv (0.707 of a square
 * cell's side: the flat grid's cell diagonals lie that far apart); the cloth c fixes the sizes (its grid). */
ODECLOTH_API cloth_status cloth_self_collision_create(const cloth *c, double thickness, cloth_self_collision **out,
                                                      cloth_error *err);
ODECLOTH_API void cloth_self_collision_destroy(cloth_self_collision *s); /* NULL is fine */
/* After a step: separate c's vertices from its triangles (passes: 3). c
 * must be the cloth (or one of the same grid) given to create. stats may
 * be NULL. */
ODECLOTH_API cloth_status cloth_self_collision_apply(cloth_self_collision *s, cloth *c,
                                                     cloth_self_collision_stats *stats);

#ifdef __cplusplus
}
#endif

#endif
