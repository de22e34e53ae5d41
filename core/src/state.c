/* The evolving state (positions, velocities, plastic state, step history)
 * apart from the model: save, restore, compare. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

int state_alloc(struct cloth_state *s, int n, int n_int)
{
    memset(s, 0, sizeof *s);
    size_t n3 = 3 * (size_t)n;
    s->n = n;
    s->n_int = n_int;
    s->x = calloc(n3, sizeof *s->x);
    s->v = calloc(n3, sizeof *s->v);
    s->x_prev = calloc(n3, sizeof *s->x_prev);
    s->v_prev = calloc(n3, sizeof *s->v_prev);
    s->dv_prev = calloc(n3, sizeof *s->dv_prev);
    s->plastic = calloc((size_t)n_int + 1, sizeof *s->plastic);
    s->l1 = calloc((size_t)n_int + 1, sizeof *s->l1);
    if (!s->x || !s->v || !s->x_prev || !s->v_prev || !s->dv_prev || !s->plastic || !s->l1) {
        state_free(s);
        return -1;
    }
    return 0;
}

void state_free(struct cloth_state *s)
{
    free(s->x);
    free(s->v);
    free(s->x_prev);
    free(s->v_prev);
    free(s->dv_prev);
    free(s->plastic);
    free(s->l1);
    memset(s, 0, sizeof *s);
}

void state_copy(struct cloth_state *dst, const struct cloth_state *src)
{
    size_t n3 = 3 * (size_t)src->n * sizeof(double);
    memcpy(dst->x, src->x, n3);
    memcpy(dst->v, src->v, n3);
    memcpy(dst->x_prev, src->x_prev, n3);
    memcpy(dst->v_prev, src->v_prev, n3);
    memcpy(dst->dv_prev, src->dv_prev, n3);
    memcpy(dst->plastic, src->plastic, (size_t)src->n_int * sizeof *src->plastic);
    memcpy(dst->l1, src->l1, (size_t)src->n_int * sizeof *src->l1);
    dst->h_prev = src->h_prev;
    dst->has_prev = src->has_prev;
}

cloth_state *cloth_state_create(const cloth *c)
{
    if (!c) return NULL;
    cloth_state *s = malloc(sizeof *s);
    if (!s) return NULL;
    if (state_alloc(s, c->n, c->n_int) != 0) {
        free(s);
        return NULL;
    }
    return s;
}

void cloth_state_destroy(cloth_state *s)
{
    if (!s) return;
    state_free(s);
    free(s);
}

cloth_status cloth_save(const cloth *c, cloth_state *s)
{
    if (!c) return CLOTH_EINVAL;
    if (!s) return cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_save: state is NULL");
    if (s->n != c->n || s->n_int != c->n_int)
        return cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_save: state was made for another cloth size");
    state_copy(s, &c->st);
    return CLOTH_OK;
}

cloth_status cloth_restore(cloth *c, const cloth_state *s)
{
    if (!c) return CLOTH_EINVAL;
    if (!s) return cloth_fail(c, CLOTH_EINVAL, "cloth_restore: state is NULL");
    if (s->n != c->n || s->n_int != c->n_int)
        return cloth_fail(c, CLOTH_EINVAL, "cloth_restore: state was made for another cloth size");
    state_copy(&c->st, s);
    return CLOTH_OK;
}

static double maxdiff(const double *a, const double *b, size_t n, double m)
{
    for (size_t k = 0; k < n; k++) {
        double d = fabs(a[k] - b[k]);
        if (d > m || d != d) m = d != d ? INFINITY : d;
    }
    return m;
}

double cloth_state_diff(const cloth_state *a, const cloth_state *b)
{
    if (!a || !b || a->n != b->n || a->n_int != b->n_int) return -1.0;
    size_t n3 = 3 * (size_t)a->n;
    double m = maxdiff(a->x, b->x, n3, 0.0);
    m = maxdiff(a->v, b->v, n3, m);
    m = maxdiff(a->l1, b->l1, (size_t)a->n_int, m);
    for (int e = 0; e < a->n_int; e++)
        if (a->plastic[e] != b->plastic[e]) return m + 1.0;
    return m;
}
