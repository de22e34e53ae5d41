/* The plugin's tuning constants, each with its unit and reason: the contact pipeline's own choices
 * (users set dClothDesc and the surface callback). Measurements behind them: docs/contacts.md, "Why
 * the plugin's constants have their values". */
#ifndef DCLOTH_TUNING_H
#define DCLOTH_TUNING_H

/* ------------------------------------------------------------------ contacts (all stages) */

/* Vertices and triangles are seen DCLOTH_CONTACT_MARGIN of the thickness beyond it (1): one held
 * exactly at the thickness is still seen (a shape that only touches reports no contact). */
#define DCLOTH_CONTACT_MARGIN 0.25

/* Distances below DCLOTH_TOUCH of the thickness are rounding (1): a vertex the last step put on
 * its shell reads a gap of about -1e-17 m. */
#define DCLOTH_TOUCH 1e-6

/* A vertex within DCLOTH_CONTACT_SLOP of the thickness of touching at the step's predicted end is
 * held on the surface (1), so a resting vertex stays in contact instead of falling free every
 * other step. */
#define DCLOTH_CONTACT_SLOP 0.1

/* Two contacts' normals oppose (a pinch) below DCLOTH_PINCH_COS (the cosine, 60 degrees), and two
 * planes lie too near parallel to be a second surface above DCLOTH_SECOND_COS (8 degrees). */
#define DCLOTH_PINCH_COS 0.5
#define DCLOTH_SECOND_COS 0.99

/* ------------------------------------------------------------ the active set (active_set.c) */

/* A step is solved at most DCLOTH_RESOLVE_PASSES times, its active set changing between solves:
 * lifting a cloth off a box over its edges, contacts let go in waves, one pass after another. */
#define DCLOTH_RESOLVE_PASSES 8

/* A free vertex ending a step deeper than RESOLVE_DEPTH of the thickness inside its shell (1) has
 * the step solved again with it held; a let-go spreads along the links from the PEEL_AFTER-th
 * solve of a step. */
#define RESOLVE_DEPTH 0.1
#define PEEL_AFTER 3

/* A triangle's contact not judged by its own force lets go of a vertex it pulls harder than LETGO_PULL
 * of a limit link's tension (1), and the step is solved again: held for ever, a lifted cloth tears;
 * let go at any pull, one bent over an edge loses its rim. */
#define LETGO_PULL 0.15

/* A link is past the elongation limit, for sliding its sticking vertices, beyond
 * (1 + delta)(1 + SLIP_STRAIN) of its rest length (1: the projection's rounding). */
#define SLIP_STRAIN 1e-4

/* ------------------------------------------------------------ the contact rule (contact_rule.c) */

/* A triangle's contact held over from the last step sticks only on vertices carrying at least
 * STICK_WEIGHT of its point's barycentric weight (1); the others slide: a far vertex held on a
 * plank-like triangle's plane otherwise reads the cloth's pull as a huge normal force and locks. */
#define STICK_WEIGHT 0.1

/* ------------------------------------------ triangle and mesh contacts (triangles.c and below) */

/* EPA's tolerance for a triangle within its shell, of the thickness (1): the loose one (1e-3)
 * finds moving triangles; a body resting on a cloth needs the fine one to stay at rest. */
#define EPA_FINE 1e-6

/* Gaps within TRI_TIE of the thickness tie (1: rounding, far below EPA's fine tolerance); within
 * MERGE_TIE (1) mirror-image contacts merge: far above the rounding a symmetric scene's solves
 * accumulate, far below a contact's own scale. */
#define TRI_TIE 1e-9
#define MERGE_TIE 1e-6

/* A prism's contact directions lie within acos(MESH_FACE_COS) (8 degrees) of its face normal, beyond
 * only across a convex or open edge; a triangle ahead of a geom takes its facing face's plane within
 * acos(AHEAD_PARALLEL) (8 degrees) of the contact direction. */
#define MESH_FACE_COS 0.99
#define AHEAD_PARALLEL 0.99

/* A trimesh triangle's prism is at most MESH_PRISM_DEPTH thicknesses deep (1): deeper than a cloth
 * is pushed in, shallower than a plate, so a prism does not poke out of the mesh's far side. */
#define MESH_PRISM_DEPTH 10.0

/* A triangle moving less than SWEEP_NEGLIGIBLE of the thickness per step is at rest (1). */
#define SWEEP_NEGLIGIBLE 1e-3

/* ------------------------------------------------------------------ link tests (edges.c) */

/* A link's middle counts as nearer than an end below (1 - EDGE_TIE) of their squared distance and
 * ties within EDGE_TIE (1); EPA's tolerance for a link against a convex, of the thickness (1); the
 * fetched triangles' grid has at most EDGE_GRID_DIM cells a side. */
#define EDGE_TIE 1e-6
#define EDGE_EPA 1e-6
#define EDGE_GRID_DIM 64

/* ---------------------------------------------------------- exact box tests (polytope.c) */

/* Heights within FEATURE_TIE of the radius tie (1: far above the rounding a symmetric scene's
 * solves accumulate, so mirror images pick mirror features); edges whose directions' cross
 * product is shorter than EDGE_PARALLEL are parallel (1). */
#define FEATURE_TIE 1e-6
#define EDGE_PARALLEL 1e-6

/* ------------------------------------------------------------------------ sleep (sleep.c) */

/* A sleeping cloth watches DCLOTH_WAKE_REACH m around it: a body moving toward it faster than
 * this per step may reach it before it wakes. */
#define DCLOTH_WAKE_REACH 0.25

#endif
