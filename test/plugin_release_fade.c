/* Plugin, Newton: a triangle's contact lets go after its own force has
 * faded through zero, not at a pull threshold.
 *
 * A 3 x 3 cloth (0.1 m, cells of 5 cm) rests, no gravity, on four thin
 * posts (1 cm square, static boxes) under its cells' centres: only its
 * triangles touch them (every vertex is 2.5 cm or more from a post's
 * side), so every contact is a triangle's, on points inside the
 * triangles. Each vertex is pushed by m_i a(t) along z, a rising from
 * -A to +A over T (down onto the posts, then up), applied before each
 * step (backward Euler takes it at the step's end). Held, the posts carry
 * the load: the contacts' force sums to -M a within the cloth's own
 * momentum change. A contact judged by its own force lets go the step
 * after it pulled: in the last step the cloth is held the contacts carry
 * at most one step's change of the load the wrong way, M 2 A h / T, and
 * the first step it moves it leaves at under two steps' change, h 4 A h /
 * T. */
#include <math.h>
#include <stdio.h>

#include "odecloth/dcloth.h"
#include "check.h"

#define A 2.0
#define T 1.05

int main(void)
{
    dInitODE2(0);
    dWorldID w = dWorldCreate();
    dSpaceID sp = dHashSpaceCreate(0);
    for (int k = 0; k < 4; k++) {
        dGeomID post = dCreateBox(sp, 0.01, 0.01, 0.2);
        dGeomSetPosition(post, k % 2 ? 0.025 : -0.025, k / 2 ? 0.025 : -0.025, -0.1);
    }
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = 3;
    d.cloth.width = d.cloth.height = 0.1;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.05;
    d.cloth.origin[2] = d.thickness;
    d.cloth.gravity[2] = 0.0;
    d.cloth.solver.nonlinear = CLOTH_NEWTON;
    d.mu = 0.0;
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) return check_summary();
    dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
    const cloth *core = dClothGetCore(c);
    const double *m = cloth_masses(core), h = 1.0 / 60.0, change = 2.0 * A * h / T;
    int n = dClothGetVertexCount(c), left = -1, tri = 0;
    double M = 0.0, last_f = NAN, last_a = NAN, v_first = NAN;
    for (int i = 0; i < n; i++) M += m[i];
    for (int s = 0; s < 120 && left < 0; s++) {
        double a = -A + 2.0 * A * fmin((s + 1) * h / T, 1.0);
        for (int i = 0; i < n; i++) dClothAddVertexForce(c, i, 0, 0, m[i] * a);
        if (!CHECK(dClothWorldStep(w, &c, 1, h, 0) == CLOTH_OK, "step %d: %s", s, dClothGetLastError(c))) break;
        const double *vel = cloth_velocities(core);
        double vz = 0.0, fz = 0.0;
        for (int i = 0; i < n; i++) {
            vz += m[i] * vel[3 * i + 2] / M;
            dReal f[3];
            dClothGetContactForce(c, i, f);
            fz += f[2];
        }
        tri = tri > dClothGetStats(c)->triangle_contacts ? tri : dClothGetStats(c)->triangle_contacts;
        if (vz > 1e-9) {
            left = s;
            v_first = vz;
            break;
        }
        last_f = fz;
        last_a = a;
    }
    printf("triangle contacts up to %d; left the posts in step %d (load %+.4f m/s^2 the step before): v %.3g m/s "
           "(bound %.3g); the contacts carried %+.4f M A the step before (-M a: %+.4f, bound %+.4f)\n",
           tri, left, last_a, v_first, 2.0 * h * change, last_f / (M * A), -last_a / A, -change / A);
    CHECK(tri > 0, "no triangle contacts: the test tests nothing");
    CHECK(left > 0, "the cloth never left the posts");
    CHECK(v_first > 0.0 && v_first <= 2.0 * h * change * (1.0 + 1e-3), "it left at %g m/s, over two steps' change",
          v_first);
    CHECK(last_f >= -change * M * (1.0 + 1e-3), "the contacts pulled %g N the step before they let go (bound %g)",
          -last_f, change * M);
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
    dCloseODE();
    return check_summary();
}
