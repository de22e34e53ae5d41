/*
 * odecloth ODE plugin: cloth in an ODE world.
 *
 * The plugin is the glue between the pure C cloth core (odecloth/cloth.h) and
 * the Open Dynamics Engine: ODE rigid bodies become colliders and attachment
 * points of a cloth, and contact reactions go back to the bodies. It follows
 * ODE's own style: dCloth prefix, dClothID handles, dReal at the boundary
 * (double: the plugin needs ODE built with dDOUBLE, as Debian's is).
 *
 * A step, in order (dClothStep):
 *   1. broadphase: one box proxy around the cloth (not in any of your spaces,
 *      so it never reaches your own dSpaceCollide callback) against the space
 *      you gave, nested spaces included, through ODE's dSpaceCollide2 and its
 *      category / collide bits;
 *   2. each vertex inside a candidate geom's AABB gets its distance and
 *      normal to the geom (closed forms for sphere, box, capsule, cylinder
 *      and plane, a ray for heightfields, a sphere proxy through dCollide
 *      for the other classes), and cloth triangles near a box (by its
 *      geometry), capsule or cylinder (libccd) are tested against it; a vertex that is, or
 *      would end the step, closer than the thickness gets a velocity
 *      constraint (paper eq. 22): its normal velocity is the body's point
 *      velocity (dBodyGetPointVel) plus what closes the gap within the step;
 *      Coulomb friction: sticking (the tangential velocity follows the body)
 *      while the force that would hold it is within mu N, sliding (a force
 *      of mu N against the slip) beyond; a contact that pulled in the last
 *      step is released, and a free vertex that ends the step inside its
 *      shell makes the step be solved again with it held;
 *   3. pins, to the world or to a point of a body, become constraints too;
 *   4. the core's implicit step (cloth_step) holds every constraint exactly;
 *   5. each constraint's force (from the solve's residual) and each sliding
 *      friction force is applied, opposite, to its body with
 *      dBodyAddForceAtPos, together with a share of whatever else changed
 *      the cloth's momentum, so cloth and bodies exchange momentum exactly;
 *      ODE's next dWorldStep carries it.
 * So step the cloth first, then the world, with the same h (dClothWorldStep
 * does both).
 *
 * Errors are values: functions return CLOTH_OK or an error code, and
 * dClothGetLastError says why; nothing prints, aborts or changes on error.
 */
#ifndef ODECLOTH_DCLOTH_H
#define ODECLOTH_DCLOTH_H

#include <ode/ode.h>

/* The cloth core: the plugin steps a core cloth, whose types it shares. */
#include "odecloth/cloth.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The odecloth version, "major.minor.patch" (the core's cloth_version()).
 * Never NULL; the string is static. */
ODECLOTH_API const char *dClothGetVersion(void);

typedef struct dxCloth *dClothID;

typedef struct dClothDesc {
    cloth_desc cloth;            /* grid, placement, material, solver (cloth.h) */
    dReal thickness;             /* m, 1e-6 .. 10: vertices keep this far from surfaces */
    dReal mu;                    /* Coulomb friction coefficient, >= 0 (0: none) */
    unsigned long category_bits; /* ODE's collision bits: the cloth and a geom  */
    unsigned long collide_bits;  /* meet if (collide & theirs.category) or
                                    (theirs.collide & category); default all   */
} dClothDesc;

/* Defaults: the core's cloth_default_desc(), thickness 5 mm, mu 0.3, all
 * bits set. */
ODECLOTH_API dClothDesc dClothDefaultDesc(void);

/* Create a cloth in `world` that collides with the geoms of `space` (may be
 * 0: no collisions; a geom that is not a space is refused). On error *out
 * is NULL and err (may be NULL) says why. The cloth keeps the space: before
 * destroying the space, give the cloth another (dClothSetSpace(c, 0)). */
ODECLOTH_API cloth_status dClothCreate(dWorldID world, dSpaceID space, const dClothDesc *desc, dClothID *out,
                                       cloth_error *err);
ODECLOTH_API void dClothDestroy(dClothID c);

/* The core cloth, for everything the plugin does not wrap: material, solver,
 * state save / restore, energies, links. Its constraints are rewritten by
 * every dClothStep (contacts and pins); set pins through the plugin. */
ODECLOTH_API cloth *dClothGetCore(dClothID c);

/* Why the last call on c failed. Never NULL. */
ODECLOTH_API const char *dClothGetLastError(dClothID c);

/* --------------------------------------------------------------- stepping */

/* One cloth step of h seconds (contacts, pins, implicit solve, reactions to
 * the bodies). Call before dWorldStep(world, h). On failure (CLOTH_EINVAL for
 * a bad h, CLOTH_ESTEP when the solve fails) the cloth and the bodies are as
 * they were. A failed solve is not an error under DCLOTH_FAILURE_HOLD, the
 * default: see dClothSetFailureMode. */
ODECLOTH_API cloth_status dClothStep(dClothID c, dReal h);

/* A step whose solve fails even in the core's substeps:
 *  DCLOTH_FAILURE_HOLD (default): the cloth stops where it was (velocities
 *    zeroed: no energy added, no force on bodies); CLOTH_OK, with stats
 *    held set and dClothGetLastError saying why; the world steps on. Each
 *    step held in a row retries the next in one more substep halving than
 *    solver.max_substep_halvings allows (up to 16), so a failure that
 *    smaller steps pass does not repeat for ever.
 *  DCLOTH_FAILURE_STOP: CLOTH_ESTEP, and dClothWorldStep steps nothing. */
typedef enum dClothFailureMode { DCLOTH_FAILURE_HOLD = 0, DCLOTH_FAILURE_STOP } dClothFailureMode;
ODECLOTH_API cloth_status dClothSetFailureMode(dClothID c, dClothFailureMode mode);

/* Step n cloths (at most 64, each once, all of this world), then the world
 * (dWorldQuickStep if quick, else dWorldStep), by h. All or nothing: when a
 * cloth's step returns an error, the cloths before it are put back as they
 * were, and so are the force and torque accumulators and velocities of the
 * bodies they pushed, and the world is not stepped. */
ODECLOTH_API cloth_status dClothWorldStep(dWorldID world, dClothID *cloths, int n, dReal h, int quick);

typedef struct dClothStepStats {
    cloth_step_stats core;           /* iterations, residual, energy, strain, failure */
    int contacts;                    /* vertices with a contact constraint            */
    int sticking;                    /* of which sticking (friction within mu N)      */
    int released;                    /* contacts released because they pulled         */
    int pins;                        /* pinned vertices                               */
    int resolves;                    /* extra solves: free vertices that ended inside
                                their shell were held and the step redone     */
    int late_contacts;               /* vertices the contact search had not reached at
                                the step's start that ended inside a shell, or
                                whose triangle did: contacts from then on
                                (each such solve is one of the resolves)      */
    int candidates;                  /* geoms whose AABB met the cloth's              */
    int triangle_contacts;           /* vertex contacts set by cloth-triangle tests
                                (box by its geometry; capsule, cylinder, libccd) */
    dReal max_penetration;           /* m, deepest vertex inside its thickness shell,
                                by its own distance, before the step (0 if
                                none)                                         */
    double seconds_contacts;         /* s, wall time finding contacts (broad + narrow) */
    double seconds_total;            /* s, wall time of the whole dClothStep           */
    int sleeping;                    /* 1: the cloth slept through this step (no solve;
                                see dClothSetAutoSleep); the other fields are
                                then those of the last step it was solved,
                                but the timings                               */
    int held;                        /* 1: the solve failed and the cloth was stopped
                                where it was (DCLOTH_FAILURE_HOLD)            */
    int newton_all;                  /* Newton iterations of all the step's solves
                                (core.newton is the last solve's)             */
    int cg_all;                      /* CG iterations of all the step's solves        */
    int edge_contacts;               /* vertex contacts set by the links' tests against
                                the edges of boxes, trimeshes and convexes
                                whose triangle tests are off                  */
    double turned[3];                /* N m s: the angular momentum the rigid turn took
                                out of the cloth and its moving holders (the
                                part no force explains: docs/contacts.md)     */
    double couple[3];                /* N m: the couple the moving holders got for
                                what that turn could not take, each its
                                constraints' share of it                      */
    double self_contact_seconds_all; /* s, wall time of the cloth's self-contact
                                barrier in all the step's solves (core's is
                                the last solve's)                             */
    dReal max_penetration_all;       /* m, the deepest point of the cloth inside a
                                geom's thickness shell before the step (0 if
                                none): a vertex by its own distance (every
                                geom), a triangle or a link by its deepest
                                point, as its test measured it (the vertices
                                the step moves: pinned ones not)              */
} dClothStepStats;

/* Stats of the last dClothStep. */
ODECLOTH_API const dClothStepStats *dClothGetStats(dClothID c);

/* ---------------------------------------------------------- for drawing */

ODECLOTH_API int dClothGetVertexCount(dClothID c);
/* 3 * vertex count, m; valid until the next step. */
ODECLOTH_API const dReal *dClothGetPositions(dClothID c);
/* Unit vertex normals (area-weighted over the vertex's triangles), 3 * count. */
ODECLOTH_API cloth_status dClothGetNormals(dClothID c, dReal *normals);
/* Two triangles per grid cell, counter-clockwise seen from +axis_u x axis_v. */
ODECLOTH_API int dClothGetTriangleCount(dClothID c);
/* 3 vertex indices per triangle; static for the cloth's lifetime. */
ODECLOTH_API const int *dClothGetTriangles(dClothID c);

/* ------------------------------------------------------------------ pins */

/* Pin a vertex to a fixed world point. */
ODECLOTH_API cloth_status dClothPinToWorld(dClothID c, int vertex, const dReal point[3]);
/* Pin a vertex to a point given in the body's frame: the vertex follows the
 * point, and the body feels the pull. b must be a body of the cloth's world. */
ODECLOTH_API cloth_status dClothPinToBody(dClothID c, int vertex, dBodyID b, const dReal local_point[3]);
ODECLOTH_API cloth_status dClothReleasePin(dClothID c, int vertex);
/* Release every pin to b (call before destroying a pinned body). */
ODECLOTH_API cloth_status dClothReleaseBody(dClothID c, dBodyID b);
/* Force (N) the pin applied to the vertex over the last step (the body got
 * the opposite). Zero if not pinned. */
ODECLOTH_API cloth_status dClothGetPinForce(dClothID c, int vertex, dReal force[3]);

/* Force (N) a contact applied to the vertex over the last step, constraint
 * and sliding friction together (zero if none). */
ODECLOTH_API cloth_status dClothGetContactForce(dClothID c, int vertex, dReal force[3]);
/* Which geom the vertex's contact was with in the last step (*geom 0: none)
 * and, where point and normal are not NULL, the surface point under the
 * vertex and the unit normal out of the geom (zeros without a contact). */
ODECLOTH_API cloth_status dClothGetVertexContact(dClothID c, int vertex, dGeomID *geom, dReal point[3],
                                                 dReal normal[3]);

/* Add a force (N) on a vertex for the next step, as dBodyAddForce does for
 * a body: forces add up until the step that applies them, then clear.
 * Forces that stay (wind) can be set on the core instead,
 * cloth_set_external_forces(dClothGetCore(c), f): the plugin adds its
 * friction to them and never overwrites them. Wakes the cloth. */
ODECLOTH_API cloth_status dClothAddVertexForce(dClothID c, int vertex, dReal fx, dReal fy, dReal fz);

/* ------------------------------------------------------------ parameters */

ODECLOTH_API cloth_status dClothSetFriction(dClothID c, dReal mu);
/* Contact parameters per geom, as an ODE near callback fills dSurfaceParameters
 * per pair: fn(data, c, g, &s) is called once a step for each geom the
 * cloth's broadphase finds, s holding dClothGetFriction(c) and
 * dClothGetThickness(c); change either field for that geom (its contacts'
 * friction, and how far vertices and triangles keep from it). A value
 * dClothSetFriction or dClothSetThickness would refuse is ignored (that
 * field keeps the cloth's). fn NULL: the cloth's values for all geoms.
 * The broadphase reaches the largest thickness fn has given since it was
 * set: a geom thicker than any before is seen from when it comes within
 * that reach (a vertex then inside its shell is pushed out). */
typedef struct dClothSurface {
    dReal mu;        /* Coulomb friction coefficient, >= 0      */
    dReal thickness; /* m, 1e-6 .. 10, the contact distance      */
} dClothSurface;
typedef void dClothSurfaceFn(void *data, dClothID c, dGeomID g, dClothSurface *s);
ODECLOTH_API cloth_status dClothSetSurfaceCallback(dClothID c, dClothSurfaceFn *fn, void *data);
/* Friction alone per geom: fn(data, c, g, &mu), mu holding
 * dClothGetFriction(c), called as the surface callback is. Setting either
 * callback (even to NULL) clears the other. */
typedef void dClothFrictionFn(void *data, dClothID c, dGeomID g, dReal *mu);
ODECLOTH_API cloth_status dClothSetFrictionCallback(dClothID c, dClothFrictionFn *fn, void *data);
ODECLOTH_API dReal dClothGetFriction(dClothID c);
ODECLOTH_API cloth_status dClothSetThickness(dClothID c, dReal thickness);
ODECLOTH_API dReal dClothGetThickness(dClothID c);
ODECLOTH_API void dClothSetCategoryBits(dClothID c, unsigned long bits);
ODECLOTH_API void dClothSetCollideBits(dClothID c, unsigned long bits);
ODECLOTH_API unsigned long dClothGetCategoryBits(dClothID c);
ODECLOTH_API unsigned long dClothGetCollideBits(dClothID c);
/* Change the space the cloth collides with (0: none). A geom that is not
 * a space is refused (CLOTH_EINVAL, the space unchanged). */
ODECLOTH_API cloth_status dClothSetSpace(dClothID c, dSpaceID space);

/* Hand the cloth a convex geom's points (the array given to
 * dGeomSetConvex, `count` points of 3 dReals in the geom's frame), copied,
 * so that its triangles are tested against the geom (libccd's EPA):
 * ODE 0.16 gives no access to a convex's points. Without it a convex gets
 * vertex contacts only. points NULL (or count 0) forgets the geom: do so
 * before destroying it. */
ODECLOTH_API cloth_status dClothSetConvexPoints(dClothID c, dGeomID g, const dReal *points, int count);

/* Triangle tests (a box's by its geometry, the others' by libccd) for geom g on (enable nonzero, the default) or
 * off. They keep a box's, capsule's, cylinder's, convex's or trimesh's edges
 * and corners from passing between the cloth's vertices; off, g gets vertex
 * contacts, and a box, trimesh or convex the link tests below, cheaper (a
 * 1000-triangle trimesh under an 81x81 cloth: docs/benchmarks.md) and enough where no
 * edge pokes into a triangle. Other classes have vertex contacts only either
 * way. Forget a geom (enable it) before destroying it. */
ODECLOTH_API cloth_status dClothSetTriangleTests(dClothID c, dGeomID g, int enable);
ODECLOTH_API int dClothGetTriangleTests(dClothID c, dGeomID g);

/* A box g's triangle tests decided by its geometry (enable nonzero, the default) or by libccd's EPA (0): the
 * contact's plane and point from the box's or the triangle's face where one decides them, the nearest points
 * elsewhere, and contacts that tie at a vertex merged, so a scene that is its own mirror image stays one to
 * rounding (docs/contacts.md). Other classes are refused. Off, the box is listed (CLOTH_ENOMEM if the list
 * cannot grow): enable it again before destroying g, or a geom later made at its address gets EPA. */
ODECLOTH_API cloth_status dClothSetExactTriangleTests(dClothID c, dGeomID g, int enable);
ODECLOTH_API int dClothGetExactTriangleTests(dClothID c, dGeomID g);

/* Link tests for a box, trimesh or convex (points handed over) g whose triangle tests are off, on (the
 * default) or off (vertex contacts only): a link nearing an edge holds its ends on the plane through it
 * (docs/contacts.md). Forget a geom (enable it) before destroying it. */
ODECLOTH_API cloth_status dClothSetEdgeTests(dClothID c, dGeomID g, int enable);
ODECLOTH_API int dClothGetEdgeTests(dClothID c, dGeomID g);

/* ---------------------------------------------------------- save/restore */

/* All a cloth carries from one step to the next: the core's state
 * (cloth_save) and the plugin's own, each vertex's contact history (in
 * contact, sticking, last force, slip: they decide release and the friction
 * cone), the pins and their forces, the sleep state, the steps held in a row
 * (DCLOTH_FAILURE_HOLD) and the forces dClothAddVertexForce added for the
 * next step. Restoring it (and your bodies) continues bitwise as the
 * uninterrupted run; restoring the core alone does not. Geoms and bodies
 * are referred to, not copied: they must still exist. */
typedef struct dClothState dClothState;
ODECLOTH_API dClothState *dClothStateCreate(dClothID c); /* for c's vertex count; NULL on no memory */
ODECLOTH_API void dClothStateDestroy(dClothState *s);    /* NULL is fine */
ODECLOTH_API cloth_status dClothSave(dClothID c, dClothState *s);
ODECLOTH_API cloth_status dClothRestore(dClothID c, const dClothState *s);

/* The same to a file, to continue a run in another process or on another
 * machine (versioned, little-endian, checksummed; the layout is in
 * plugin/src/statefile.c). Geoms and bodies cannot go to a file: you name
 * those the cloth may refer to in geoms[] and bodies[] (NULL with a count of
 * 0 for none), and the file keeps indices into them, so pass the same
 * arrays, in the same order, of the scene you rebuilt. Writing refuses
 * (file untouched) a pin, contact or sleep snapshot whose geom or body is
 * not in the arrays, naming it: dropping it would silently change the run.
 * Reading checks every field (magic, version, vertex count, indices,
 * finite numbers, checksum) and changes the cloth only if all pass. The last
 * step's stats are not kept; your bodies' own state is yours to save. For a
 * bitwise continuation put a body's quaternion and rotation back bit for bit:
 * dBodySetQuaternion normalises again, moving the last bits of a turned body. */
ODECLOTH_API cloth_status dClothWriteState(dClothID c, const char *path, const dGeomID *geoms, int ngeoms,
                                           const dBodyID *bodies, int nbodies);
ODECLOTH_API cloth_status dClothReadState(dClothID c, const char *path, const dGeomID *geoms, int ngeoms,
                                          const dBodyID *bodies, int nbodies);

/* -------------------------------------------------------------- sleeping */

/* A cloth at rest costs nothing (off by default, as ODE's auto-disable).
 * With on != 0, a cloth whose RMS vertex speed, sqrt(2 KE / M), has stayed
 * below `speed` (m/s, > 0; ODE's own auto-disable uses 0.01) for `steps`
 * (>= 1) steps in a row, while every body near it or
 * holding it is static, disabled or slower than `speed` too, falls asleep:
 * its velocities are zeroed and dClothStep only checks whether to wake it
 * (the broadphase: no narrowphase, no solve). A free body (no joints) it
 * alone holds comes to rest with it and is held as by a rigid support (what
 * ODE holds for it, gravity and your forces, is cancelled each step); a
 * body in joints keeps feeling the cloth's last forces. It wakes when a body within
 * 0.25 m of it or holding it moves faster than `speed` (at its geom's far
 * edge; a body faster than 0.25 m per step may reach it first), when a geom
 * comes that near, leaves, or moves, when the world's gravity changes, and
 * on any dCloth call that changes it (pins, friction, thickness, bits,
 * space). After changing the core (dClothGetCore) call dClothWake. */
ODECLOTH_API cloth_status dClothSetAutoSleep(dClothID c, int on, dReal speed, int steps);
ODECLOTH_API int dClothIsSleeping(dClothID c);
ODECLOTH_API void dClothWake(dClothID c);

#ifdef __cplusplus
}
#endif

#endif /* ODECLOTH_DCLOTH_H */
