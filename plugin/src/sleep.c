/* Sleeping (dClothSetAutoSleep): a cloth at rest with nothing moving near it is not solved. It keeps,
 * on falling asleep, the geoms near it, their positions and the world's gravity, and compares each
 * step with them to decide whether to wake. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "dcloth_internal.h"
#include "broadphase.h"
#include "journal.h"
#include "sleep.h"

/* Does geom g's body move faster than the threshold anywhere on the geom?
 * (linear speed plus angular speed times the AABB's half diagonal) */
static int body_moves(dClothID c, dBodyID b, dGeomID g)
{
    if (!b || !dBodyIsEnabled(b)) return 0;
    const dReal *v = dBodyGetLinearVel(b), *w = dBodyGetAngularVel(b);
    double r = 0.0;
    if (g) {
        dReal a[6];
        dGeomGetAABB(g, a);
        double dx = a[1] - a[0], dy = a[3] - a[2], dz = a[5] - a[4];
        r = 0.5 * sqrt(dx * dx + dy * dy + dz * dz);
        if (!isfinite(r)) r = 0.0; /* planes: unbounded; their bodies, if any, count by velocity */
    }
    double sv = sqrt(dcloth_dot3(v, v)) + r * sqrt(dcloth_dot3(w, w));
    return !(sv <= c->sleep.state.speed);
}

/* Anything moving near the cloth or holding it (candidates of c->broad.cand and
 * the pins' bodies)? */
static int anything_moves(dClothID c)
{
    for (int a = 0; a < c->broad.ncand; a++)
        if (body_moves(c, dGeomGetBody(c->broad.cand[a]), c->broad.cand[a])) return 1;
    for (int i = 0; i < c->n; i++)
        if (c->pin[i].active && body_moves(c, c->pin[i].body, 0)) return 1;
    return 0;
}

/* The candidates and gravity now, against the ones it fell asleep with. */
static int scene_changed(dClothID c)
{
    dVector3 g;
    dWorldGetGravity(c->world, g);
    if (g[0] != c->sleep.state.gravity[0] || g[1] != c->sleep.state.gravity[1] || g[2] != c->sleep.state.gravity[2])
        return 1;
    if (c->broad.ncand != c->sleep.state.n) return 1;
    for (int a = 0; a < c->broad.ncand; a++) {
        dGeomID gg = c->broad.cand[a];
        int k = 0;
        while (k < c->sleep.state.n && c->sleep.ids[k] != gg) k++;
        if (k == c->sleep.state.n) return 1;
        /* a static geom moved by hand (a body's motion is judged by its
         * velocity: a resting body's position drifts by rounding) */
        const dReal *p = dGeomGetClass(gg) == dPlaneClass || dGeomGetBody(gg) ? NULL : dGeomGetPosition(gg);
        if (p &&
            (p[0] != c->sleep.geoms[3 * k] || p[1] != c->sleep.geoms[3 * k + 1] || p[2] != c->sleep.geoms[3 * k + 2]))
            return 1;
    }
    return 0;
}

/* Was b solved with the cloth in its last step (and still free of joints)? */
static int held_coupled(dClothID c, dBodyID b)
{
    for (int k = 0; k < c->coupled.n; k++)
        if (c->coupled.bodies[k] == b) return dBodyGetNumJoints(b) == 0;
    return 0;
}

static double wall(void)
{
    struct timespec t;
    timespec_get(&t, TIME_UTC);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int dcloth_sleep_before(dClothID c, double h, double t0)
{
    if (!c->sleep.state.asleep) return 0;
    if (dcloth_find_candidates(c, h, DCLOTH_WAKE_REACH) < 0) return -1;
    if (!c->sleep.state.on || anything_moves(c) || scene_changed(c)) {
        dClothWake(c);
        return 0;
    }
    /* The bodies it holds stay held: one solved with the cloth alone (no joints) as by a rigid support,
     * ODE's forces on it cancelled and its velocity waking the cloth if something else moves it; a body
     * in joints keeps the cloth's last forces at their points. */
    for (int k = 0; k < c->coupled.n; k++) {
        dBodyID b = c->coupled.bodies[k];
        if (!dBodyIsEnabled(b) || dBodyGetNumJoints(b) > 0) continue;
        dVector3 g = {0, 0, 0};
        if (dBodyGetGravityMode(b)) dWorldGetGravity(c->world, g);
        dMass m;
        dBodyGetMass(b, &m);
        const dReal *F = dBodyGetForce(b), *T = dBodyGetTorque(b);
        dcloth_touch(c, b);
        dBodyAddForce(b, -(F[0] + m.mass * g[0]), -(F[1] + m.mass * g[1]), -(F[2] + m.mass * g[2]));
        dBodyAddTorque(b, -T[0], -T[1], -T[2]);
    }
    for (int i = 0; i < c->n; i++) {
        const vpin *p = &c->pin[i];
        const vcontact *k = &c->vc[i];
        dBodyID b = p->active ? p->body : k->geom ? k->body : 0;
        if (!b || dBodyIsKinematic(b) || !dBodyIsEnabled(b) || held_coupled(c, b)) continue;
        const double *f = p->active ? p->force : k->force, *at = p->active ? p->world : k->point;
        dcloth_touch(c, b);
        dBodyAddForceAtPos(b, -f[0], -f[1], -f[2], at[0], at[1], at[2]);
    }
    c->stats.sleeping = 1;
    c->stats.seconds_contacts = 0.0;
    c->stats.seconds_total = wall() - t0;
    return 1;
}

void dcloth_sleep_after(dClothID c)
{
    if (!c->sleep.state.on) return;
    /* at rest judged by the RMS speed sqrt(2 KE / M), not the fastest vertex: a single flap or corner
     * may sway for seconds while the cloth as a whole is settled (docs/contacts.md) */
    const double *v = cloth_velocities(c->core), *m = cloth_masses(c->core);
    double e = 0.0, M = 0.0;
    for (int i = 0; i < c->n; i++) {
        e += m[i] * dcloth_dot3(v + 3 * i, v + 3 * i);
        M += m[i];
    }
    int slow = e <= c->sleep.state.speed * c->sleep.state.speed * M;
    if (!slow || anything_moves(c)) {
        c->sleep.state.still = 0;
        return;
    }
    if (++c->sleep.state.still < c->sleep.state.steps) return;
    /* fall asleep: remember the scene as far as a sleeping cloth watches */
    if (dcloth_find_candidates(c, 0.0, DCLOTH_WAKE_REACH) < 0 || anything_moves(c)) return;
    if (c->broad.ncand > c->sleep.cap) {
        double *gp = realloc(c->sleep.geoms, 3 * (size_t)c->broad.ncand * sizeof *gp);
        if (gp) c->sleep.geoms = gp;
        dGeomID *id = gp ? realloc(c->sleep.ids, (size_t)c->broad.ncand * sizeof *id) : NULL;
        if (id) c->sleep.ids = id;
        if (!gp || !id) return; /* no memory: stay awake */
        c->sleep.cap = c->broad.ncand;
    }
    for (int a = 0; a < c->broad.ncand; a++) {
        c->sleep.ids[a] = c->broad.cand[a];
        const dReal *p = dGeomGetClass(c->broad.cand[a]) == dPlaneClass ? NULL : dGeomGetPosition(c->broad.cand[a]);
        for (int k = 0; k < 3; k++) c->sleep.geoms[3 * a + k] = p ? p[k] : 0.0;
    }
    c->sleep.state.n = c->broad.ncand;
    dVector3 g;
    dWorldGetGravity(c->world, g);
    for (int k = 0; k < 3; k++) c->sleep.state.gravity[k] = g[k];
    memset(c->step.v0, 0, 3 * (size_t)c->n * sizeof *c->step.v0); /* the step is over: scratch */
    cloth_set_velocities(c->core, c->step.v0);
    /* the bodies it alone holds come to rest with it (they are slower than
     * the threshold: else it would not sleep) */
    for (int k = 0; k < c->coupled.n; k++)
        if (held_coupled(c, c->coupled.bodies[k]) && dBodyIsEnabled(c->coupled.bodies[k])) {
            dBodyID b = c->coupled.bodies[k];
            dVector3 g = {0, 0, 0};
            if (dBodyGetGravityMode(b)) dWorldGetGravity(c->world, g);
            dMass m;
            dBodyGetMass(b, &m);
            dcloth_touch(c, b);
            dBodySetLinearVel(b, 0, 0, 0);
            dBodySetAngularVel(b, 0, 0, 0);
            /* and this step's forces on it (the user's, the cloth's) become
             * the support that holds it: net zero with gravity */
            dBodySetForce(b, -m.mass * g[0], -m.mass * g[1], -m.mass * g[2]);
            dBodySetTorque(b, 0, 0, 0);
        }
    c->sleep.state.asleep = 1;
}
