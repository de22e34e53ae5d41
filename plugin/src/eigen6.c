/* The eigen decomposition of a symmetric 6x6 matrix (momentum.c's rigid
 * turns: their momenta and constraints). */
#include <math.h>
#include "dcloth_internal.h"
#include "eigen6.h"

void dcloth_eigen6(double A[6][6], double d[6], double V[6][6])
{
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) V[i][j] = i == j;
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = 0.0, diag = 0.0;
        for (int i = 0; i < 6; i++) {
            diag += A[i][i] * A[i][i];
            for (int j = i + 1; j < 6; j++) off += A[i][j] * A[i][j];
        }
        if (!(off > 1e-32 * diag)) break;
        for (int p = 0; p < 6; p++)
            for (int q = p + 1; q < 6; q++) {
                if (A[p][q] == 0.0) continue;
                double th = 0.5 * (A[q][q] - A[p][p]) / A[p][q];
                double t = (th >= 0.0 ? 1.0 : -1.0) / (fabs(th) + sqrt(th * th + 1.0));
                double cs = 1.0 / sqrt(t * t + 1.0), sn = t * cs;
                for (int k = 0; k < 6; k++) { /* A <- A J, then J^T A */
                    double a = A[k][p], b = A[k][q];
                    A[k][p] = cs * a - sn * b;
                    A[k][q] = sn * a + cs * b;
                }
                for (int k = 0; k < 6; k++) {
                    double a = A[p][k], b = A[q][k];
                    A[p][k] = cs * a - sn * b;
                    A[q][k] = sn * a + cs * b;
                }
                for (int k = 0; k < 6; k++) {
                    double a = V[k][p], b = V[k][q];
                    V[k][p] = cs * a - sn * b;
                    V[k][q] = sn * a + cs * b;
                }
            }
    }
    for (int i = 0; i < 6; i++) d[i] = A[i][i];
}
