/* Physics: a fabric's derived springs store, in the library's own energy
 * (cloth_energies), what the fabric's physical parameters say, at every
 * grid resolution (derivation: docs/materials.md).
 *
 * Bending. A sheet is set on a cylinder of curvature kappa as the
 * inscribed polygon whose sequential links keep their rest lengths (nodes
 * at angle steps theta, 2 R sin(theta / 2) = spacing): only the interlaced
 * links store energy. The energy per unit area of the interior is taken as
 * the difference of two sheets that differ by n rows (or columns) along the
 * bend divided by the area those rows add, so the edges, where interlaced
 * links are missing, cancel. Expected: B kappa_ref^2 / 2 (kappa /
 * kappa_ref)^4, the quartic law of the chord shortening matched at
 * kappa_ref. Leading order in kappa h: the exact chord differs by
 * (kappa h)^2 / 8 relative at most, so 3% holds down to kappa h = 0.4;
 * spacings c/4, c/8, c/16 (kappa_ref h = 0.28, 0.14, 0.07).
 * Non-square cells (dx = 1.5 dy): the mean of the two thread directions
 * is B kappa^2 / 2 (the derivation's choice).
 *
 * Tension. The sheet stretched by a uniform strain eps = 1e-5 along one
 * thread direction, the other held: energy per area (again the difference
 * of two sheets) = tensile eps^2 / 2 within 1e-3 (the lattice is exact for
 * uniform strain; what is left is O(eps) nonlinearity).
 *
 * Mass: the masses add up to density times the area.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "odecloth/fabric.h"
#include "check.h"

static cloth *sheet(const cloth_fabric *f, int rows, int cols, double dx, double dy)
{
    cloth_desc d = cloth_default_desc();
    d.rows = rows;
    d.cols = cols;
    d.width = (cols - 1) * dx;
    d.height = (rows - 1) * dy;
    d.origin[0] = d.origin[1] = d.origin[2] = 0.0;
    cloth_error err;
    if (cloth_fabric_apply(f, &d, &err) != CLOTH_OK) {
        CHECK(0, "cloth_fabric_apply: %s", err.message);
        return NULL;
    }
    cloth *c = NULL;
    if (cloth_create(&d, &c, &err) != CLOTH_OK) {
        CHECK(0, "cloth_create: %s", err.message);
        return NULL;
    }
    return c;
}

/* Elastic energy of the sheet bent to curvature kappa along u (along = 0:
 * the columns' direction) or v (along = 1), or, with kappa = 0, stretched
 * by eps along that direction. */
static double deformed_energy(const cloth_fabric *f, int rows, int cols, double dx, double dy, int along,
                              double kappa, double eps)
{
    cloth *c = sheet(f, rows, cols, dx, dy);
    if (!c) return NAN;
    double h = along ? dy : dx, R = kappa > 0.0 ? 1.0 / kappa : 0.0;
    double theta = kappa > 0.0 ? 2.0 * asin(0.5 * h * kappa) : 0.0;
    double *x = malloc(3 * (size_t)rows * cols * sizeof *x);
    for (int r = 0; r < rows; r++)
        for (int k = 0; k < cols; k++) {
            double *p = x + 3 * (r * cols + k);
            int i = along ? r : k;           /* index along the bend   */
            double across = along ? k * dx : r * dy;
            double s = kappa > 0.0 ? R * sin(i * theta) : i * h * (1.0 + eps);
            double z = kappa > 0.0 ? R * (1.0 - cos(i * theta)) : 0.0;
            p[0] = along ? across : s;
            p[1] = along ? s : across;
            p[2] = z;
        }
    CHECK(cloth_set_positions(c, x) == CLOTH_OK, "set positions");
    double e = cloth_energies(c).elastic;
    free(x);
    cloth_destroy(c);
    return e;
}

/* Energy per unit area of the interior: the energy of a block of n x n
 * cells inside a sheet, by double differences of sheets of n0 and n0 + n
 * nodes each way, so every edge (where interlaced links are missing) cancels. */
static double energy_density(const cloth_fabric *f, double dx, double dy, int along, double kappa, double eps)
{
    const int n0 = 7, n = 6;
    double e00 = deformed_energy(f, n0, n0, dx, dy, along, kappa, eps);
    double e01 = deformed_energy(f, n0, n0 + n, dx, dy, along, kappa, eps);
    double e10 = deformed_energy(f, n0 + n, n0, dx, dy, along, kappa, eps);
    double e11 = deformed_energy(f, n0 + n, n0 + n, dx, dy, along, kappa, eps);
    return (e11 - e10 - e01 + e00) / (n * dx * n * dy);
}

/* Spacings at which kappa_ref h is 0.4, 0.28, 0.2, 0.14, 0.1 (the leading
 * order holds to 2% at 0.4), those the fabric allows: the interlaced links,
 * k_b growing as h^-4, stretch like a membrane too, and below some spacing
 * they alone are stiffer than `tensile` (docs/materials.md). */
static int spacings(const cloth_fabric *f, double h[5])
{
    static const double kh[5] = {0.4, 0.28, 0.2, 0.14, 0.1};
    double kref = cloth_fabric_reference_curvature(f);
    int n = 0;
    for (int k = 0; k < 5; k++) {
        cloth_material m;
        if (cloth_fabric_material(f, kh[k] / kref, kh[k] / kref, &m, NULL) == CLOTH_OK) h[n++] = kh[k] / kref;
        else printf("  kappa_ref h = %.2f: spacing %.3g m refused (finer than the fabric allows)\n", kh[k],
                    kh[k] / kref);
    }
    return n;
}

static void check_bending(const char *name, const cloth_fabric *f)
{
    double c = cloth_fabric_bending_length(f), kref = cloth_fabric_reference_curvature(f);
    double B = f->bending, want = 0.5 * B * kref * kref;
    printf("%s: B %.4g N m, bending length %.4g m, kappa_ref %.4g 1/m\n", name, B, c, kref);
    double first = NAN, h[5];
    int nh = spacings(f, h);
    CHECK(nh >= 2, "%s: %d spacings", name, nh);
    for (int level = 0; level < nh; level++) {
        for (int along = 0; along < 2; along++) {
            double w = energy_density(f, h[level], h[level], along, kref, 0.0);
            double w2 = energy_density(f, h[level], h[level], along, 0.5 * kref, 0.0);
            printf("  h %.3g m (kappa_ref h %.2f), along %c: W(kappa_ref) / (B kappa_ref^2 / 2) = %.5f, "
                   "W(kappa_ref / 2) / (B kappa_ref^2 / 32) = %.5f\n",
                   h[level], kref * h[level], along ? 'v' : 'u', w / want, w2 / (want / 16.0));
            CHECK_REL(w, want, 0.03, 0.0);
            CHECK_REL(w2, want / 16.0, 0.03, 0.0);
            if (level == 0 && along == 0) first = w;
            CHECK_REL(w, first, 0.03, 0.0); /* the same sheet at every resolution */
        }
    }
    /* cells 1.5 : 1, the two thread directions' mean */
    double dy = h[nh - 1], dx = 1.5 * dy;
    double wu = energy_density(f, dx, dy, 0, kref, 0.0), wv = energy_density(f, dx, dy, 1, kref, 0.0);
    printf("  cells %.3g x %.3g m: along u %.5f, along v %.5f, mean %.5f of B kappa_ref^2 / 2\n", dx, dy,
           wu / want, wv / want, 0.5 * (wu + wv) / want);
    CHECK_REL(0.5 * (wu + wv), want, 0.03, 0.0);
}

static void check_tension(const char *name, const cloth_fabric *f)
{
    const double eps = 1e-5;
    double want = 0.5 * f->tensile * eps * eps, h[5];
    int nh = spacings(f, h);
    for (int k = 0; k <= nh; k++) {
        double dy = h[k < nh ? k : nh - 1], dx = k < nh ? dy : 1.5 * dy; /* last: cells 1.5 : 1 */
        double wu = energy_density(f, dx, dy, 0, 0.0, eps), wv = energy_density(f, dx, dy, 1, 0.0, eps);
        printf("%s tension, cells %.3g x %.3g m: W / (tensile eps^2 / 2) along u %.6f, along v %.6f\n", name, dx,
               dy, wu / want, wv / want);
        if (k < nh) {
            CHECK_REL(wu, want, 1e-3, 0.0);
            CHECK_REL(wv, want, 1e-3, 0.0);
        } else {
            CHECK_REL(0.5 * (wu + wv), want, 1e-3, 0.0);
        }
    }
}

static void check_mass(const cloth_fabric *f)
{
    double dx = 0.01, dy = 0.015;
    cloth *c = sheet(f, 11, 7, dx, dy);
    if (!c) return;
    double m = 0.0;
    for (int i = 0; i < cloth_vertex_count(c); i++) m += cloth_masses(c)[i];
    CHECK_REL(m, f->density * 10 * dy * 6 * dx, 1e-12, 0.0);
    cloth_destroy(c);
}

int main(void)
{
    const struct { const char *name; cloth_fabric_kind k; } fabrics[] = {
        {"cotton", CLOTH_FABRIC_COTTON}, {"denim", CLOTH_FABRIC_DENIM}, {"silk", CLOTH_FABRIC_SILK}};
    for (size_t i = 0; i < sizeof fabrics / sizeof fabrics[0]; i++) {
        cloth_fabric f = cloth_fabric_preset(fabrics[i].k);
        check_bending(fabrics[i].name, &f);
        check_tension(fabrics[i].name, &f);
        check_mass(&f);
    }
    /* a reference curvature set by hand */
    cloth_fabric f = cloth_fabric_preset(CLOTH_FABRIC_WOOL);
    f.bend_curvature = 20.0;
    CHECK_NEAR(cloth_fabric_reference_curvature(&f), 20.0, 0.0);
    check_bending("wool, kappa_ref 20 1/m", &f);
    return check_summary();
}
