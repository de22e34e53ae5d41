/* The cloth model: descriptor, creation (topology, rest lengths, masses,
 * workspaces), accessors and setters. Everything allocated here; the step
 * allocates nothing. */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"
#include "self_contact.h"
#include "vec3.h"

/* Largest vertex count: keeps every index (3 per vertex, 16 links per vertex,
 * 2 blocks per link) within int. */
#define CLOTH_MAX_VERTICES (INT_MAX / 64)

cloth_desc cloth_default_desc(void)
{
    cloth_desc d;
    memset(&d, 0, sizeof d);
    d.rows = d.cols = 21;
    d.width = d.height = 1.0;
    d.origin[0] = -0.5;
    d.origin[1] = -0.5;
    d.origin[2] = 1.0;
    d.axis_u[0] = 1.0;
    d.axis_v[1] = 1.0;
    d.gravity[2] = -9.81;
    d.material = cloth_material_preset(CLOTH_COTTON);
    d.solver.method = CLOTH_BACKWARD_EULER;
    d.solver.precond = CLOTH_PRECOND_AUTO;
    d.solver.cg_tolerance = 1e-3;
    d.solver.cg_max_iterations = 2000;
    d.solver.definiteness_rule = 1;
    d.solver.warm_start = 1;
    d.solver.strain_limit_iterations = 20;
    d.solver.strain_fail = 0.5;
    d.solver.max_substep_halvings = 4; /* a failed step is tried again as 2, 4, 8, 16 substeps */
    d.solver.newton_iterations = 16;
    d.solver.newton_tolerance = 1e-2;
    d.solver.newton_rtol = 1e-2;
    d.solver.limit_tolerance = 1e-3;
    d.solver.newton_cg_tolerance = 1e-2;
    d.solver.newton_cg_share = 0.25;
    d.solver.nonlinear = CLOTH_NEWTON;
    return d;
}


/* a divided by its largest component's magnitude (zero stays zero): a
 * direction whose squares neither overflow nor underflow. */
static void unit_scaled(const double a[3], double out[3])
{
    double m = fmax(fabs(a[0]), fmax(fabs(a[1]), fabs(a[2])));
    for (int k = 0; k < 3; k++) out[k] = m > 0.0 ? a[k] / m : 0.0;
}

/* Scales the grid must keep so that positions, rest lengths, their squares and masses stay normal
 * doubles resolved to 1e-7 relative: within 1e100 m of the origin, spacing >= 1e-100 m and >= 1e-9
 * of the extent. */
#define CLOTH_MAX_EXTENT 1e100
#define CLOTH_MIN_SPACING 1e-100
#define CLOTH_MIN_SPACING_REL 1e-9

cloth_status cloth_desc_validate(const cloth_desc *d, cloth_error *err)
{
    if (!d) return oc_error_set(err, CLOTH_EINVAL, "descriptor is NULL");
    if (d->rows < 3 || d->cols < 3)
        return oc_error_set(err, CLOTH_EINVAL, "grid %d x %d: rows and cols must be >= 3", d->rows, d->cols);
    if ((long long)d->rows * d->cols > CLOTH_MAX_VERTICES)
        return oc_error_set(err, CLOTH_EINVAL, "grid %d x %d has more than %d nodes", d->rows, d->cols,
                            CLOTH_MAX_VERTICES);
    if (!isfinite(d->width) || !(d->width > 0.0) || !isfinite(d->height) || !(d->height > 0.0))
        return oc_error_set(err, CLOTH_EINVAL, "size %g x %g m: width and height must be finite and > 0", d->width,
                            d->height);
    const struct {
        const char *name;
        const double *v;
    } vec[] = {{"origin", d->origin}, {"axis_u", d->axis_u}, {"axis_v", d->axis_v}, {"gravity", d->gravity}};
    for (size_t k = 0; k < 4; k++)
        if (!finite3(vec[k].v)) return oc_error_set(err, CLOTH_EINVAL, "%s is not finite", vec[k].name);
    double au[3], av[3];
    unit_scaled(d->axis_u, au);
    unit_scaled(d->axis_v, av);
    double uu = vec3_dot(au, au), vv = vec3_dot(av, av), uv = vec3_dot(au, av);
    if (!(uu > 0.0) || !(vv > 0.0)) return oc_error_set(err, CLOTH_EINVAL, "axis_u and axis_v must be non-zero");
    if (uu * vv - uv * uv <= 1e-12 * uu * vv)
        return oc_error_set(err, CLOTH_EINVAL, "axis_u and axis_v must not be parallel");
    double extent = fmax(fabs(d->origin[0]), fmax(fabs(d->origin[1]), fabs(d->origin[2]))) + d->width + d->height;
    double dx = d->width / (d->cols - 1), dy = d->height / (d->rows - 1), sp = fmin(dx, dy);
    if (!(extent <= CLOTH_MAX_EXTENT))
        return oc_error_set(err, CLOTH_EINVAL, "origin %g, %g, %g with size %g x %g m: the cloth must lie within %g m",
                            d->origin[0], d->origin[1], d->origin[2], d->width, d->height, CLOTH_MAX_EXTENT);
    if (!(sp >= CLOTH_MIN_SPACING) || !(sp >= CLOTH_MIN_SPACING_REL * extent))
        return oc_error_set(err, CLOTH_EINVAL,
                            "node spacing %g m (size %g x %g m, grid %d x %d) must be >= %g m and >= %g times the "
                            "cloth's distance from 0 (%g m) to be resolved",
                            sp, d->width, d->height, d->rows, d->cols, CLOTH_MIN_SPACING, CLOTH_MIN_SPACING_REL,
                            extent);
    cloth_status s = cloth_material_validate(&d->material, err);
    if (s != CLOTH_OK) return s;
    /* a corner node carries a quarter cell, an inner one a whole cell */
    double cell = d->material.density * dx * dy;
    if (!(0.25 * cell >= DBL_MIN) || !isfinite(cell))
        return oc_error_set(err, CLOTH_EINVAL,
                            "node masses from density %g kg/m^2 and cells of %g x %g m are %g kg: "
                            "not a normal positive double",
                            d->material.density, dx, dy, 0.25 * cell);
    return cloth_solver_validate(&d->solver, err);
}

/* Orthonormal frame: u normalised, v made orthogonal to u (Gram-Schmidt). */
static void frame(const cloth_desc *d, double u[3], double v[3])
{
    double au[3], av[3];
    unit_scaled(d->axis_u, au);
    unit_scaled(d->axis_v, av);
    double nu = sqrt(vec3_dot(au, au));
    for (int k = 0; k < 3; k++) u[k] = au[k] / nu;
    double p = vec3_dot(av, u);
    for (int k = 0; k < 3; k++) v[k] = av[k] - p * u[k];
    double nv = sqrt(vec3_dot(v, v));
    for (int k = 0; k < 3; k++) v[k] /= nv;
}

/* Links from node (r, c) to (r + dr, c + dc) for the four "forward" offsets
 * of a neighbourhood at distance s (1: sequential, 2: interlaced), each
 * undirected link once with i < j. */
static int make_links(int R, int C, int s, const double *x0, link_topo *out)
{
    const int off[4][2] = {{0, 1}, {1, 0}, {1, 1}, {1, -1}};
    int m = 0;
    for (int r = 0; r < R; r++)
        for (int c = 0; c < C; c++)
            for (int k = 0; k < 4; k++) {
                int r2 = r + s * off[k][0], c2 = c + s * off[k][1];
                if (r2 >= R || c2 < 0 || c2 >= C) continue;
                int i = r * C + c, j = r2 * C + c2;
                const double *a = x0 + 3 * i, *b = x0 + 3 * j;
                double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
                if (out) {
                    out[m].i = i;
                    out[m].j = j;
                    out[m].rest = sqrt(dx * dx + dy * dy + dz * dz);
                }
                m++;
            }
    return m;
}

static int links_to_blocks(bsr *A, int n, const link_topo *seq, int n_seq, const link_topo *lint, int n_int,
                           int *seq_blk, int *int_blk, int *own)
{
    int ne = n_seq + n_int;
    int *ei = malloc((size_t)ne * sizeof *ei), *ej = malloc((size_t)ne * sizeof *ej);
    int *blk = malloc(2 * (size_t)ne * sizeof *blk);
    int rc = -1;
    if (ei && ej && blk) {
        for (int e = 0; e < n_seq; e++) {
            ei[e] = seq[e].i;
            ej[e] = seq[e].j;
        }
        for (int e = 0; e < n_int; e++) {
            ei[n_seq + e] = lint[e].i;
            ej[n_seq + e] = lint[e].j;
        }
        rc = oc_bsr_build(A, n, ne, ei, ej, blk);
        if (rc == 0) {
            *own = oc_bsr_edges_own_offdiag(A, ne, blk);
            memcpy(seq_blk, blk, 2 * (size_t)n_seq * sizeof *blk);
            memcpy(int_blk, blk + 2 * (size_t)n_seq, 2 * (size_t)n_int * sizeof *blk);
        }
    }
    free(ei);
    free(ej);
    free(blk);
    return rc;
}

void cloth_destroy(cloth *c)
{
    if (!c) return;
    oc_self_contact_unbind_cloth(c);
    free(c->mass);
    free(c->seq);
    free(c->lint);
    oc_state_free(&c->st);
    oc_state_free(&c->retry_bk);
    free(c->retry_xs);
    free(c->retry_fsum);
    free(c->con);
    free(c->con_force);
    free(c->cand);
    free(c->cand_on);
    free(c->cand_pull);
    free(c->cand2);
    free(c->cand2_on);
    free(c->con1);
    free(c->f_ext);
    free(c->body);
    free(c->body_ws);
    free(c->vbody);
    free(c->body_dev);
    oc_bsr_free(&c->A);
    free(c->seq_blk);
    free(c->int_blk);
    free(c->air_blk);
    free(c->lim_shift);
    free(c->lim_rho);
    free(c->lim_viol);
    free(c->slack_age);
    free(c->warm_dv);
    free(c->K_seq);
    free(c->K_int);
    free(c->work);
    free(c->cflag);
    free(c->clist);
    free(c->sl);
    free(c->Ah);
    free(c->sl_act);
    free(c->sl_held);
    free(c->sl_vtx);
    oc_mg_free(&c->mg);
    free(c);
}

/* The multigrid's levels where the solver uses them: always for
 * CLOTH_PRECOND_MULTIGRID, for CLOTH_PRECOND_AUTO under Newton where the
 * grid coarsens. 0, -1 (out of memory) or -2 (the grid does not coarsen). */
static int multigrid_levels(cloth *c, const cloth_solver *s)
{
    int want = s->precond == CLOTH_PRECOND_MULTIGRID ||
               (s->precond == CLOTH_PRECOND_AUTO && s->nonlinear == CLOTH_NEWTON);
    if (!want || c->mg.nlev > 0) return 0;
    int r = oc_mg_create(&c->mg, c->rows, c->cols, &c->A);
    return r == -2 && s->precond == CLOTH_PRECOND_AUTO ? 0 : r;
}

cloth_status cloth_create(const cloth_desc *d, cloth **out, cloth_error *err)
{
    if (err) {
        err->code = CLOTH_OK;
        err->message[0] = '\0';
    }
    if (!out) return oc_error_set(err, CLOTH_EINVAL, "cloth_create: out is NULL");
    *out = NULL;
    cloth_status s = cloth_desc_validate(d, err);
    if (s != CLOTH_OK) return s;

    cloth *c = calloc(1, sizeof *c);
    if (!c) return oc_error_set(err, CLOTH_ENOMEM, "cloth_create: out of memory");
    c->desc = *d;
    int R = d->rows, C = d->cols, n = R * C;
    c->rows = R;
    c->cols = C;
    c->n = n;
    size_t n3 = 3 * (size_t)n;

    c->mass = malloc((size_t)n * sizeof *c->mass);
    double *x0 = malloc(n3 * sizeof *x0);
    if (!c->mass || !x0 || oc_state_alloc(&c->st, n, 0, 0) != 0) goto nomem;

    /* rest positions and lumped masses: each node carries the area of the
     * cells around it (a quarter cell per adjacent cell) */
    double u[3], v[3];
    frame(d, u, v);
    double dx = d->width / (C - 1), dy = d->height / (R - 1);
    for (int r = 0; r < R; r++)
        for (int col = 0; col < C; col++) {
            int i = r * C + col;
            for (int k = 0; k < 3; k++) x0[3 * i + k] = d->origin[k] + col * dx * u[k] + r * dy * v[k];
            double wr = (r == 0 || r == R - 1) ? 0.5 : 1.0, wc = (col == 0 || col == C - 1) ? 0.5 : 1.0;
            c->mass[i] = d->material.density * dx * dy * wr * wc;
        }

    c->n_seq = make_links(R, C, 1, x0, NULL);
    c->n_int = make_links(R, C, 2, x0, NULL);
    c->seq = malloc((size_t)c->n_seq * sizeof *c->seq);
    c->lint = malloc((size_t)c->n_int * sizeof *c->lint);
    if (!c->seq || !c->lint) goto nomem;
    make_links(R, C, 1, x0, c->seq);
    make_links(R, C, 2, x0, c->lint);

    /* the state has the interlaced links' plastic state: allocate it now */
    oc_state_free(&c->st);
    if (oc_state_alloc(&c->st, n, c->n_int, c->n_seq) != 0) goto nomem;
    /* the substep retry's workspace: a hard step allocates nothing either */
    if (oc_state_alloc(&c->retry_bk, n, c->n_int, c->n_seq) != 0) goto nomem;
    c->retry_xs = malloc(n3 * sizeof *c->retry_xs);
    c->retry_fsum = malloc(n3 * sizeof *c->retry_fsum);
    if (!c->retry_xs || !c->retry_fsum) goto nomem;
    memcpy(c->st.x, x0, n3 * sizeof *x0);
    for (int e = 0; e < c->n_int; e++) c->st.l1[e] = c->lint[e].rest;
    free(x0);
    x0 = NULL;

    c->con = calloc((size_t)n, sizeof *c->con);
    c->con_force = calloc(n3, sizeof *c->con_force);
    c->f_ext = calloc(n3, sizeof *c->f_ext);
    if (!c->f_ext) goto nomem;
    c->seq_blk = malloc(2 * (size_t)c->n_seq * sizeof *c->seq_blk);
    c->int_blk = malloc(2 * (size_t)c->n_int * sizeof *c->int_blk);
    c->lim_shift = calloc((size_t)c->n_seq + 1, sizeof *c->lim_shift);
    c->lim_rho = calloc((size_t)c->n_seq + 1, sizeof *c->lim_rho);
    c->lim_viol = calloc((size_t)c->n_seq + 1, sizeof *c->lim_viol);
    c->slack_age = calloc((size_t)c->n_seq + 1, sizeof *c->slack_age);
    c->warm_dv = calloc(n3, sizeof *c->warm_dv);
    c->K_seq = malloc(9 * (size_t)c->n_seq * sizeof *c->K_seq);
    c->K_int = malloc(9 * (size_t)c->n_int * sizeof *c->K_int);
    if (!c->con || !c->con_force || !c->seq_blk || !c->int_blk || !c->lim_shift || !c->lim_rho || !c->lim_viol ||
        !c->slack_age || !c->warm_dv || !c->K_seq || !c->K_int)
        goto nomem;
    if (links_to_blocks(&c->A, n, c->seq, c->n_seq, c->lint, c->n_int, c->seq_blk, c->int_blk, &c->links_own_blocks) !=
        0)
        goto nomem;
    if (oc_air_blocks(c) != 0) goto nomem;
    if (oc_workspace_alloc(c) != 0) goto nomem;
    c->Ah = calloc(9 * (size_t)c->A.nnzb + 1, sizeof *c->Ah); /* + the AVX rows' padding double (mat3.h) */
    if (!c->Ah) goto nomem;
    c->cflag = calloc((size_t)n, 1);
    c->cand = calloc(6 * (size_t)n, sizeof *c->cand);
    c->cand_on = calloc((size_t)n, 1);
    c->cand_pull = malloc((size_t)n * sizeof *c->cand_pull);
    c->cand2 = calloc(6 * (size_t)n, sizeof *c->cand2);
    c->cand2_on = calloc((size_t)n, 1);
    c->con1 = calloc((size_t)n, sizeof *c->con1);
    if (!c->cand || !c->cand_on || !c->cand_pull || !c->cand2 || !c->cand2_on || !c->con1) goto nomem;
    for (int i = 0; i < n; i++) c->cand_pull[i] = INFINITY;
    c->clist = calloc((size_t)n, sizeof *c->clist);
    c->sl = malloc(9 * (size_t)c->n_seq * sizeof *c->sl);
    c->sl_act = malloc((size_t)c->n_seq * sizeof *c->sl_act);
    c->sl_vtx = calloc(n3, sizeof *c->sl_vtx);
    c->sl_held = calloc((size_t)c->n_seq + (size_t)n, 1);
    if (!c->sl || !c->sl_act || !c->sl_vtx || !c->sl_held) goto nomem;
    if (!c->cflag || !c->clist) goto nomem;
    /* the multigrid's levels only where the solves use them (made later by
     * cloth_set_solver if it is chosen then) */
    {
        int r = multigrid_levels(c, &d->solver);
        if (r == -2) {
            cloth_destroy(c);
            return oc_error_set(err, CLOTH_EINVAL,
                                "cloth_create: the multigrid preconditioner needs a grid that coarsens (%d x %d does "
                                "not: a side under 5 nodes); choose another preconditioner",
                                R, C);
        }
        if (r != 0) goto nomem;
    }

    *out = c;
    return CLOTH_OK;
nomem:
    free(x0);
    cloth_destroy(c);
    return oc_error_set(err, CLOTH_ENOMEM, "cloth_create: out of memory for a %d x %d grid", R, C);
}

const char *cloth_last_error(const cloth *c) { return c ? c->err : "cloth is NULL"; }
int cloth_rows(const cloth *c) { return c ? c->rows : 0; }
int cloth_cols(const cloth *c) { return c ? c->cols : 0; }
int cloth_vertex_count(const cloth *c) { return c ? c->n : 0; }
const double *cloth_positions(const cloth *c) { return c ? c->st.x : NULL; }
const double *cloth_velocities(const cloth *c) { return c ? c->st.v : NULL; }
const double *cloth_masses(const cloth *c) { return c ? c->mass : NULL; }

cloth_desc cloth_get_desc(const cloth *c)
{
    if (!c) return cloth_default_desc();
    return c->desc;
}

/* Setting positions or velocities by hand breaks the BDF2 history and the warm start: they restart
 * from this state. The limit's multipliers are forces at the links' lengths: only new positions
 * (positions set) make them stale. */
static void forget_history(cloth *c, int positions)
{
    c->st.has_prev = 0;
    memset(c->st.dv_prev, 0, 3 * (size_t)c->n * sizeof *c->st.dv_prev);
    if (positions) memset(c->st.lim_shift, 0, (size_t)c->n_seq * sizeof *c->st.lim_shift);
}

cloth_status cloth_set_positions(cloth *c, const double *x)
{
    if (!c) return CLOTH_EINVAL;
    if (!x) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_positions: x is NULL");
    if (!oc_all_finite(x, 3 * (size_t)c->n))
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_positions: positions must be finite");
    memcpy(c->st.x, x, 3 * (size_t)c->n * sizeof *x);
    forget_history(c, 1);
    return CLOTH_OK;
}

cloth_status cloth_set_velocities(cloth *c, const double *v)
{
    if (!c) return CLOTH_EINVAL;
    if (!v) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_velocities: v is NULL");
    if (!oc_all_finite(v, 3 * (size_t)c->n))
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_velocities: velocities must be finite");
    memcpy(c->st.v, v, 3 * (size_t)c->n * sizeof *v);
    forget_history(c, 0);
    return CLOTH_OK;
}

cloth_status cloth_add_velocities(cloth *c, const double *dv)
{
    if (!c) return CLOTH_EINVAL;
    if (!dv) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_add_velocities: dv is NULL");
    size_t n3 = 3 * (size_t)c->n;
    for (size_t k = 0; k < n3; k++)
        if (!isfinite(dv[k]) || !isfinite(c->st.v[k] + dv[k]))
            return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_add_velocities: dv[%zu] = %g: the velocity must stay finite",
                                 k, dv[k]);
    for (size_t k = 0; k < n3; k++) c->st.v[k] += dv[k];
    return CLOTH_OK;
}

cloth_status cloth_set_warm_start(cloth *c, const double *dv)
{
    if (!c) return CLOTH_EINVAL;
    if (!dv) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_warm_start: dv is NULL");
    size_t n3 = 3 * (size_t)c->n;
    for (size_t k = 0; k < n3; k++)
        if (!isfinite(dv[k])) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_warm_start: dv[%zu] = %g", k, dv[k]);
    memcpy(c->warm_dv, dv, n3 * sizeof *dv);
    c->warm_set = 1;
    return CLOTH_OK;
}

cloth_status cloth_set_vertex(cloth *c, int vertex, const double x[3], const double v[3])
{
    if (!c) return CLOTH_EINVAL;
    if (vertex < 0 || vertex >= c->n)
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_vertex: vertex %d out of range [0, %d)", vertex, c->n);
    if (!x && !v) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_vertex: x and v are both NULL: nothing to set");
    if ((x && !finite3(x)) || (v && !finite3(v)))
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_vertex: position and velocity must be finite");
    for (int k = 0; k < 3; k++) {
        if (x) c->st.x[3 * vertex + k] = x[k];
        if (v) c->st.v[3 * vertex + k] = v[k];
    }
    forget_history(c, x != NULL);
    return CLOTH_OK;
}

cloth_status cloth_set_material(cloth *c, const cloth_material *m)
{
    if (!c) return CLOTH_EINVAL;
    cloth_error e;
    if (cloth_material_validate(m, &e) != CLOTH_OK) return oc_cloth_fail(c, e.code, "%s", e.message);
    c->desc.material = *m;
    return CLOTH_OK;
}

cloth_status cloth_set_solver(cloth *c, const cloth_solver *s)
{
    if (!c) return CLOTH_EINVAL;
    cloth_error e;
    if (cloth_solver_validate(s, &e) != CLOTH_OK) return oc_cloth_fail(c, e.code, "%s", e.message);
    {
        int r = multigrid_levels(c, s);
        if (r == -2)
            return oc_cloth_fail(c, CLOTH_EINVAL,
                                 "cloth_set_solver: the multigrid preconditioner needs a grid that coarsens (%d x %d "
                                 "does not: a side under 5 nodes)",
                                 c->rows, c->cols);
        if (r != 0) return oc_cloth_fail(c, CLOTH_ENOMEM, "cloth_set_solver: out of memory for the multigrid levels");
    }
    c->desc.solver = *s;
    return CLOTH_OK;
}

cloth_status cloth_set_gravity(cloth *c, const double g[3])
{
    if (!c) return CLOTH_EINVAL;
    if (!g || !finite3(g)) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_gravity: gravity must be finite");
    memcpy(c->desc.gravity, g, sizeof c->desc.gravity);
    return CLOTH_OK;
}

const double *cloth_external_forces(const cloth *c) { return c ? c->f_ext : NULL; }

cloth_status cloth_set_external_forces(cloth *c, const double *f)
{
    if (!c) return CLOTH_EINVAL;
    size_t n3 = 3 * (size_t)c->n;
    if (!f) {
        memset(c->f_ext, 0, n3 * sizeof *c->f_ext);
        return CLOTH_OK;
    }
    if (!oc_all_finite(f, n3))
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_external_forces: forces must be finite");
    memcpy(c->f_ext, f, n3 * sizeof *c->f_ext);
    return CLOTH_OK;
}

int cloth_link_count(const cloth *c, cloth_link_type t)
{
    if (!c) return 0;
    return t == CLOTH_SEQUENTIAL ? c->n_seq : t == CLOTH_INTERLACED ? c->n_int : 0;
}

cloth_status cloth_get_link(const cloth *c, cloth_link_type t, int index, cloth_link *out)
{
    if (!c) return CLOTH_EINVAL;
    if (!out) return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_get_link: out is NULL");
    int m = cloth_link_count(c, t);
    if (t != CLOTH_SEQUENTIAL && t != CLOTH_INTERLACED)
        return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_get_link: unknown link type %d", (int)t);
    if (index < 0 || index >= m)
        return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_get_link: index %d out of range [0, %d)", index, m);
    const link_topo *L = t == CLOTH_SEQUENTIAL ? &c->seq[index] : &c->lint[index];
    out->i = L->i;
    out->j = L->j;
    out->rest = L->rest;
    if (t == CLOTH_INTERLACED) {
        out->plastic = c->st.plastic[index];
        out->l1 = c->st.l1[index];
    } else { /* the rest length the law uses: grown by its tension set */
        out->plastic = c->st.seq_set[index] > 0.0;
        out->l1 = seq_law(&c->desc.material, L->rest, c->st.seq_set[index]).rest;
    }
    return CLOTH_OK;
}
