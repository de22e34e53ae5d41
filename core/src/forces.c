/* Forces and energies of the whole cloth (paper eq. 4): springs of both link
 * types in their current regions, damping along links, gravity, external
 * forces and air drag. */
#include <math.h>
#include <string.h>
#include "internal.h"

static void add3(double *a, const double b[3], double s)
{
    a[0] += s * b[0];
    a[1] += s * b[1];
    a[2] += s * b[2];
}

void oc_forces_eval(const cloth *c, const double *x, const double *v, int with_gravity, double *f)
{
    const cloth_material *m = &c->desc.material;
    size_t n3 = 3 * (size_t)c->n;
    memset(f, 0, n3 * sizeof *f);
    double fe[3];
    for (int e = 0; e < c->n_seq; e++) {
        int i = c->seq[e].i, j = c->seq[e].j;
        spring_law s = seq_law(m, c->seq[e].rest, c->st.seq_set[e]);
        oc_link_eval(x + 3 * i, x + 3 * j, v + 3 * i, v + 3 * j, s, m->c_t, 0, fe, NULL, NULL);
        add3(f + 3 * i, fe, 1.0);
        add3(f + 3 * j, fe, -1.0);
    }
    for (int e = 0; e < c->n_int; e++) {
        int i = c->lint[e].i, j = c->lint[e].j;
        spring_law s = int_law(m, c->lint[e].rest, c->st.plastic[e], c->st.l1[e]);
        oc_link_eval(x + 3 * i, x + 3 * j, v + 3 * i, v + 3 * j, s, m->c_b, 0, fe, NULL, NULL);
        add3(f + 3 * i, fe, 1.0);
        add3(f + 3 * j, fe, -1.0);
    }
    if (oc_crease_law_on(m)) oc_crease_forces(c, x, x, 1.0, f); /* the hinges along their own sagittas */
    if (with_gravity)
        for (int i = 0; i < c->n; i++) {
            add3(f + 3 * i, c->desc.gravity, c->mass[i]);
            add3(f + 3 * i, c->f_ext + 3 * i, 1.0);
        }
    if (with_gravity && oc_air_on(c)) oc_air_eval(c, x, NULL, 0.0, v, 1.0, f, NULL, 0.0);
}

/* oc_spring_energy (springs.c), the same arithmetic, inlined: the step's
 * statistics evaluate it for every link of every step */
static inline double link_energy_d(double d, spring_law s)
{
    double e = d - s.rest, el = d > s.lim ? d - s.lim : 0.0;
    return 0.5 * (e >= 0.0 ? s.k_hi : s.k_lo) * e * e + 0.5 * s.k_lim * el * el;
}

/* the length of link (xi, xj), as every pass over the links computes it */
static inline double link_length(const double xi[3], const double xj[3])
{
    double u0 = xj[0] - xi[0], u1 = xj[1] - xi[1], u2 = xj[2] - xi[2];
    return sqrt(u0 * u0 + u1 * u1 + u2 * u2);
}

static inline double link_energy(const double xi[3], const double xj[3], spring_law s)
{
    return link_energy_d(link_length(xi, xj), s);
}

double oc_elastic_energy(const cloth *c, const double *x)
{
    const cloth_material *m = &c->desc.material;
    double E = 0.0;
    for (int e = 0; e < c->n_seq; e++)
        E += link_energy(x + 3 * c->seq[e].i, x + 3 * c->seq[e].j, seq_law(m, c->seq[e].rest, c->st.seq_set[e]));
    for (int e = 0; e < c->n_int; e++)
        E += link_energy(x + 3 * c->lint[e].i, x + 3 * c->lint[e].j,
                         int_law(m, c->lint[e].rest, c->st.plastic[e], c->st.l1[e]));
    return oc_crease_law_on(m) ? E + oc_crease_energy(c, x, x) : E;
}

cloth_energy cloth_energies(const cloth *c)
{
    cloth_energy en = {0.0, 0.0, 0.0};
    if (!c) return en;
    return oc_energies_with_elastic(c, oc_elastic_energy(c, c->st.x));
}

cloth_energy oc_energies_with_elastic(const cloth *c, double elastic)
{
    cloth_energy en = {0.0, 0.0, 0.0};
    en.elastic = elastic;
    const double *x = c->st.x, *v = c->st.v, *g = c->desc.gravity;
    for (int i = 0; i < c->n; i++) {
        const double *vi = v + 3 * i, *xi = x + 3 * i;
        en.kinetic += 0.5 * c->mass[i] * (vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]);
        en.gravitational -= c->mass[i] * (g[0] * xi[0] + g[1] * xi[1] + g[2] * xi[2]);
    }
    return en;
}

cloth_status cloth_internal_forces(const cloth *c, double *f)
{
    if (!c) return CLOTH_EINVAL;
    if (!f) return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_internal_forces: f is NULL");
    oc_forces_eval(c, c->st.x, c->st.v, 0, f);
    return CLOTH_OK;
}

double oc_max_strain_of(const cloth *c, const double *x)
{
    double m = -INFINITY;
    for (int e = 0; e < c->n_seq; e++) {
        const double *a = x + 3 * c->seq[e].i, *b = x + 3 * c->seq[e].j;
        double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
        double s = (sqrt(dx * dx + dy * dy + dz * dz) - c->seq[e].rest) / c->seq[e].rest;
        if (s > m || s != s) m = s;
    }
    return m;
}

/* The passes over the links after a step, each length computed once (step.c): oc_max_strain_of with the
 * sequential links' energy, then on the committed state the plastic update with the interlaced
 * links' energy; bit for bit the separate functions' results, in one pass each. */
double oc_max_strain_seq_energy(const cloth *c, const double *x, double *e_seq)
{
    const cloth_material *m = &c->desc.material;
    double mx = -INFINITY, E = 0.0;
    for (int e = 0; e < c->n_seq; e++) {
        double d = link_length(x + 3 * c->seq[e].i, x + 3 * c->seq[e].j);
        double s = (d - c->seq[e].rest) / c->seq[e].rest;
        if (s > mx || s != s) mx = s;
        E += link_energy_d(d, seq_law(m, c->seq[e].rest, c->st.seq_set[e]));
    }
    *e_seq = E;
    return mx;
}

/* The sequential links' tension sets at the committed positions, and their energy with the sets
 * updated (oc_elastic_energy's first terms, from 0, in its order) */
static double update_tension_energy(cloth *c)
{
    const cloth_material *m = &c->desc.material;
    const double *x = c->st.x;
    double E = 0.0;
    for (int e = 0; e < c->n_seq; e++) {
        double d = link_length(x + 3 * c->seq[e].i, x + 3 * c->seq[e].j), *set = c->st.seq_set + e;
        *set = oc_tension_set_rule(m, c->seq[e].rest, d, *set);
        E += link_energy_d(d, seq_law(m, c->seq[e].rest, *set));
    }
    return E;
}

int oc_update_plastic_energy(cloth *c, double h, double *elastic)
{
    const cloth_material *m = &c->desc.material;
    const double *x = c->st.x;
    double E = oc_tension_plastic_on(m) ? update_tension_energy(c) : *elastic; /* the sets move the energy */
    int count = 0;
    for (int e = 0; e < c->n_int; e++) {
        double d = link_length(x + 3 * c->lint[e].i, x + 3 * c->lint[e].j);
        int p = oc_plastic_update_link(m, &c->st, e, c->lint[e].rest, d, h);
        count += p;
        E += link_energy_d(d, int_law(m, c->lint[e].rest, p, c->st.l1[e]));
    }
    *elastic = oc_crease_law_on(m) ? E + oc_crease_energy(c, x, x) : E;
    return count;
}

double cloth_max_strain(const cloth *c) { return c ? oc_max_strain_of(c, c->st.x) : 0.0; }
