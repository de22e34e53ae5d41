/* The plugin's cloth object (struct dxCloth) and what every stage of its
 * step (step.c) shares: a vertex's contact, a pin, the tolerances. */
#ifndef ODECLOTH_DCLOTH_INTERNAL_H
#define ODECLOTH_DCLOTH_INTERNAL_H

#include "odecloth/dcloth.h"
#include "active_set.h"
#include "body_coupling.h"
#include "broadphase.h"
#include "edges.h"
#include "journal.h"
#include "mesh_contacts.h"
#include "momentum.h"
#include "reactions.h"
#include "sleep.h"
#include "step.h"
#include "triangles.h"
#include "tuning.h"
#include "vertex_contacts.h"

/* dReal is double at the boundary: positions are handed out without copies. */
typedef char dcloth_dreal_must_be_double[sizeof(dReal) == sizeof(double) ? 1 : -1];

/* A vertex's contact in one step. */
typedef struct vcontact {
    dGeomID geom;       /* 0: no contact                                   */
    dBodyID body;       /* 0 for a static geom                             */
    double normal[3];   /* unit, out of the geom toward the vertex         */
    double point[3];    /* m, the surface point under the vertex           */
    double gap;         /* m, distance to the surface minus the thickness  */
    double thickness;   /* m, the geom's contact distance this step        */
    double mu;          /* the geom's friction coefficient this step       */
    double vbody[3];    /* m/s, the body's velocity at the point           */
    int sticking;       /* 1: pinned to the body's motion (static friction) */
    int anchored;       /* 1: sticking to a kinematic body at anchor       */
    double anchor[3];   /* body frame: where the sticking vertex is held    */
    int from_triangle;  /* 1: set by a triangle test (triangles.c)         */
    int tri;            /* that cloth triangle's index (-1: a link's edge
                            contact, edges.c), and the query that            */
    unsigned query;     /* set it (dxCloth's triangles.query): one contact */
    double weight;      /* the contact point's barycentric weight on the
                            vertex (triangle contacts; 1 for a vertex's own)  */
    int ties;           /* the triangles' contacts merged into it (tied)   */
    double tie_sum[3];  /* the sum of their unit normals                   */
    int active;         /* 1: a constraint in this step's solve            */
    int forced;         /* 1: a re-solve found the vertex inside its shell  */
    int candidate;      /* 1: left free, a contact candidate the Newton
                            step decides (cloth_set_contact)                */
    int let_go;         /* 1: a triangle's contact pulled in a solve of this
                            step; free in the next solve. Kept (Newton): the
                            whole contact pulled; the next step lets it go  */
    int slides;         /* 1: held on a link past the elongation limit in a
                            solve of this step; slides in the next          */
    double friction[3]; /* N, sliding friction force applied on the vertex */
    double slip[3];     /* m/s, tangential velocity relative to the body at
                            the step's start                               */
    double force[3];    /* N, total contact force on the vertex (after the step) */
    /* the nearest contact with another geom whose normal opposes this one (dcloth_offer_opposite):
     * where both targets cannot be met (the gap under two thicknesses), contact_rule aims midway */
    dGeomID opp_geom; /* 0: none                                         */
    dBodyID opp_body;
    double opp_normal[3], opp_gap, opp_vbody[3];
    int pinched;        /* 1: this step's target is the midway one         */
    double pinch_shift; /* m, along the normal: the midway target's offset
                            from this contact's own (0 unless pinched)      */
    /* a second surface (dcloth_offer_second): another static or kinematic geom's
     * plane near the vertex, for the Newton step to decide (cloth_set_contact_second);
     * not carried between steps */
    dGeomID sec_geom; /* 0: none                                         */
    dBodyID sec_body;
    double sec_normal[3], sec_point[3], sec_gap, sec_thickness, sec_vbody[3];
} vcontact;

/* A set of geoms (geom_lists.c): g[0..n) */
typedef struct dcloth_geom_list {
    dGeomID *g;
    int n, cap;
} dcloth_geom_list;

typedef struct vpin {
    int active;
    dBodyID body;    /* 0: pinned to the world                          */
    double local[3]; /* body frame (or world point if no body)          */
    double world[3]; /* m, the pin point's position at the step's start */
    double force[3]; /* N, on the vertex, last step                     */
} vpin;

/* The cloth: the user's configuration, the state carried from one step to the next, and one member per
 * stage of the step, that stage's scratch (defined in its own header) */
struct dxCloth {
    cloth *core;
    int n, ntri;
    int *tri; /* 3 ntri                                          */
    /* configuration: what the user set */
    dWorldID world;
    dSpaceID space;
    double thickness, mu;
    unsigned long category, collide;
    int implicit;                  /* 1: couple dynamic bodies implicitly (default)   */
    dClothFailureMode on_failure;  /* what a failed solve gives (dcloth.h)   */
    dClothFrictionFn *friction_fn; /* per-geom friction (NULL: mu for all)  */
    void *friction_data;
    dClothSurfaceFn *surface_fn; /* per-geom mu and thickness (NULL: none) */
    void *surface_data;
    /* convex geoms' points, for triangle tests (dClothSetConvexPoints) */
    struct cvx_points {
        dGeomID g;
        int n;
        double *p; /* 3n, the geom's frame */
    } * cvx;
    int ncvx;
    /* geoms whose triangle tests are off (dClothSetTriangleTests) */
    dcloth_geom_list tri_off;
    /* boxes whose triangle tests are left to EPA (dClothSetExactTriangleTests off) */
    dcloth_geom_list tri_epa;
    dcloth_geom_list edge_off; /* geoms whose link tests are off (dClothSetEdgeTests) */
    /* carried from one step to the next (dClothSave copies all but vc_new, err and undo) */
    vcontact *vc, *vc_new; /* n: committed and candidate contact states */
    vpin *pin;             /* n */
    double *fadd;          /* 3n: dClothAddVertexForce's, for the next step */
    /* steps held in a row: each retries the next in one more substep halving (body_coupling.c) */
    int held_run;
    /* the largest thickness the surface callback has given since it was set: the broadphase's reach */
    double surf_tmax;
    struct dcloth_sleep sleep; /* sleep.c's settings and state */
    dClothStepStats stats;     /* the last step's */
    char err[256];             /* the last failed call's message */
    /* the cloth's whole state before a step, for dClothWorldStep's undo (world_step.c) */
    struct dClothState *undo;
    /* each stage's scratch, in the step's order */
    struct step_scratch step;             /* step.c: the step's start, to solve it again from */
    struct broadphase_scratch broad;      /* broadphase.c */
    struct vertex_proxies vertex;         /* vertex_contacts.c */
    struct triangle_tests triangles;      /* triangles.c, triangle_query.c */
    struct mesh_scratch mesh;             /* mesh_contacts.c */
    struct edge_scratch edge;             /* edges.c */
    struct active_set_scratch active_set; /* active_set.c */
    struct coupled_bodies coupled;        /* body_coupling.c */
    struct reactions_scratch reactions;   /* reactions.c */
    struct turn_scratch turn;             /* momentum.c */
    struct body_journal journal;          /* journal.c: the bodies the step touched */
};

/* save.c: a snapshot of a cloth (dClothSave); statefile.c reads and writes
 * it to a file. */
struct dClothState {
    int n;
    cloth_state *core;
    vcontact *vc;
    vpin *pin;
    dClothStepStats stats;
    struct sleep_state sleep;
    double *sleep_geoms;
    dGeomID *sleep_ids;
    double surf_tmax; /* the broadphase's reach for the surface callback's geoms */
    int held_run;     /* steps held in a row (the next step's extra halvings) */
    double *fadd;     /* 3n: dClothAddVertexForce's, not yet applied          */
};

/* statefile.c: dClothReadState on a file already in memory (name: for the
 * messages), for the fuzzer. */
cloth_status dcloth_read_state(dClothID c, const char *name, const unsigned char *buf, size_t len, const dGeomID *geoms,
                               int ngeoms, const dBodyID *bodies, int nbodies);

static inline double dcloth_dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* body_coupling.c: a held run retries in at most this many substep halvings,
 * so held_run never exceeds it (statefile.c checks it on reading). */
#define DCLOTH_HOLD_MAX_HALVINGS 16

/* geom_lists.c: put g in list l (in nonzero) or take it out, and wake the
 * cloth; CLOTH_ENOMEM (reported for `who`) when memory ran out */
int dcloth_geom_list_set(dClothID c, dcloth_geom_list *l, dGeomID g, int in, const char *who);
int dcloth_geom_list_has(const dcloth_geom_list *l, dGeomID g);

/* fail.c: set c->err and return code (printf-style). */
cloth_status dcloth_fail(dClothID c, cloth_status code, const char *fmt, ...);

/* dcloth.c: geom g's mu and thickness for this step: the cloth's, changed
 * by the surface (or friction) callback where it gives valid values */
void dcloth_surface(dClothID c, dGeomID g, double *mu, double *thickness);

/* Thickness range (m): below a micron libccd's EPA tolerance (1e-3 of it)
 * is lost in rounding and GJK spins; past 10 m its sums overflow (1e300
 * made libccd crash: found by plugin_fuzz_api). */
#define DCLOTH_THICKNESS_MIN 1e-6
#define DCLOTH_THICKNESS_MAX 10.0

#endif
