/* One link as a spring and a damper: energy, force and Jacobian blocks (paper eq. 6-7, 9-14, sec. 4),
 * every link a piecewise-quadratic spring_law. When d < l the transverse term of K is negative and
 * breaks CG, so the paper's rule keeps only k uu^T there (derivation: docs/model.md, docs/newton.md). */
#include <math.h>
#include "spring_predicted.h"

static inline double link_vec(const double xi[3], const double xj[3], double u[3])
{
    u[0] = xj[0] - xi[0];
    u[1] = xj[1] - xi[1];
    u[2] = xj[2] - xi[2];
    double d = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    if (d > SPRING_MIN_LENGTH) {
        u[0] /= d;
        u[1] /= d;
        u[2] /= d;
    }
    return d;
}

double oc_spring_energy(const double xi[3], const double xj[3], spring_law s)
{
    /* the length as link_vec computes it (the direction is not needed) */
    double u0 = xj[0] - xi[0], u1 = xj[1] - xi[1], u2 = xj[2] - xi[2];
    double d = sqrt(u0 * u0 + u1 * u1 + u2 * u2), e = d - s.rest, el = d > s.lim ? d - s.lim : 0.0;
    return 0.5 * (e >= 0.0 ? s.k_hi : s.k_lo) * e * e + 0.5 * s.k_lim * el * el;
}

void oc_spring_eval(const double xi[3], const double xj[3], spring_law s, int definiteness, double f_i[3], double K[9])
{
    static const double zero[3] = {0.0, 0.0, 0.0};
    double D[9];
    oc_link_eval(xi, xj, zero, zero, s, 0.0, definiteness, f_i, K, D);
}

void oc_damper_eval(const double xi[3], const double xj[3], const double vi[3], const double vj[3], double c,
                    double f_i[3], double D[9])
{
    double u[3];
    double d = link_vec(xi, xj, u);
    if (d <= SPRING_MIN_LENGTH) {
        u[0] = u[1] = u[2] = 0.0;
    }
    double rate = (vj[0] - vi[0]) * u[0] + (vj[1] - vi[1]) * u[1] + (vj[2] - vi[2]) * u[2];
    f_i[0] = c * rate * u[0];
    f_i[1] = c * rate * u[1];
    f_i[2] = c * rate * u[2];
    if (D)
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) D[3 * a + b] = c * u[a] * u[b];
}

void oc_link_eval(const double xi[3], const double xj[3], const double vi[3], const double vj[3], spring_law s,
                  double c, int definiteness, double f_i[3], double K[9], double D[9])
{
    double u[3];
    double d = link_vec(xi, xj, u);
    if (d <= SPRING_MIN_LENGTH) {
        f_i[0] = f_i[1] = f_i[2] = 0.0;
        if (K)
            for (int k = 0; k < 9; k++) K[k] = D[k] = 0.0;
        return;
    }
    double k = d >= s.rest ? s.k_hi : s.k_lo;
    double rate = (vj[0] - vi[0]) * u[0] + (vj[1] - vi[1]) * u[1] + (vj[2] - vi[2]) * u[2];
    double fe = k * (d - s.rest);
    if (d > s.lim) {
        fe += s.k_lim * (d - s.lim);
        k += s.k_lim;
    }
    double fm = fe + c * rate;
    f_i[0] = fm * u[0];
    f_i[1] = fm * u[1];
    f_i[2] = fm * u[2];
    if (!K) return;
    double kt = (definiteness && d < s.rest) ? 0.0 : fe / d;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double uu = u[a] * u[b];
            K[3 * a + b] = (k - kt) * uu + (a == b ? kt : 0.0);
            D[3 * a + b] = c * uu;
        }
}

double oc_spring_eval_predicted(const double xi[3], const double xj[3], const double u0[3], spring_law s, double w,
                                double f_i[3], double K[9], int *slack)
{
    return spring_predicted(xi, xj, u0, s, w, f_i, K, slack);
}
