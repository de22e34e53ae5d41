/* obj_intersections: how many pairs of a mesh's triangles pass through each
 * other, for OBJ files such as the demos write with --obj.
 *
 *   obj_intersections FILE.obj...
 *
 * Per file, one line: the intersecting pairs (triangles sharing no vertex
 * where an edge of one crosses the other: examples/common/intersections.h)
 * and how many vertices their triangles have. The faces are taken as given
 * and must be triangles; "v" and "f" lines are read (indices 1-based or
 * negative, with or without /texture/normal parts), others skipped.
 *
 * A file that cannot be read or is not such an OBJ gets a message naming
 * it and the line; the others are still counted, and the exit status is 1.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "common/cli.h"
#include "common/intersections.h"

static const char usage[] = "usage: obj_intersections FILE.obj...\n"
                            "Prints, per file, the pairs of triangles that pass through each other (sharing\n"
                            "no vertex, an edge of one crossing the other) and the vertices involved.\n"
                            "Exit status 1 if a file could not be read, 2 on a usage error.\n";

typedef struct mesh {
    double *x;
    int nv, cap_v;
    int *tri;
    int nt, cap_t;
} mesh;

/* Appends to a growing array of `size`-byte items; -1 when out of memory. */
static int grow(void *pp, int *cap, int n, size_t size)
{
    if (n < *cap) return 0;
    int c = *cap ? 2 * *cap : 1024;
    void *p = realloc(*(void **)pp, (size_t)c * size);
    if (!p) return -1;
    *(void **)pp = p;
    *cap = c;
    return 0;
}

/* A "v" line's three coordinates; -1 with a message on a bad one. */
static int read_vertex(mesh *m, char *s, const char *where)
{
    double p[3];
    for (int k = 0; k < 3; k++) {
        char *end;
        p[k] = strtod(s, &end);
        if (end == s || !isfinite(p[k])) {
            fprintf(stderr, "%s: vertex coordinate %d is not a finite number\n", where, k + 1);
            return -1;
        }
        s = end;
    }
    if (grow(&m->x, &m->cap_v, m->nv, 3 * sizeof *m->x)) {
        fprintf(stderr, "%s: out of memory\n", where);
        return -1;
    }
    memcpy(m->x + 3 * (size_t)m->nv++, p, sizeof p);
    return 0;
}

/* An "f" line's vertex indices (relative ones resolved against the
 * vertices read so far); -1 with a message unless a triangle of valid ones. */
static int read_face(mesh *m, char *s, const char *where)
{
    int idx[3], n = 0;
    for (char *tok = strtok(s, " \t\r\n"); tok; tok = strtok(NULL, " \t\r\n")) {
        char *end;
        errno = 0;
        long i = strtol(tok, &end, 10);
        if (end == tok || (*end && *end != '/') || errno) {
            fprintf(stderr, "%s: face vertex '%s' is not an index\n", where, tok);
            return -1;
        }
        if (i < 0) i += m->nv + 1;
        if (i < 1 || i > m->nv) {
            fprintf(stderr, "%s: face vertex '%s' is not one of the %d vertices read\n", where, tok, m->nv);
            return -1;
        }
        if (n < 3) idx[n] = (int)i - 1;
        n++;
    }
    if (n != 3) {
        fprintf(stderr, "%s: a face of %d vertices (only triangles are counted)\n", where, n);
        return -1;
    }
    if (grow(&m->tri, &m->cap_t, m->nt, 3 * sizeof *m->tri)) {
        fprintf(stderr, "%s: out of memory\n", where);
        return -1;
    }
    memcpy(m->tri + 3 * (size_t)m->nt++, idx, sizeof idx);
    return 0;
}

/* Reads path into m; -1 with a message on any error. */
static int read_obj(const char *path, mesh *m)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "%s: %s\n", path, strerror(errno));
        return -1;
    }
    char *line = NULL, where[1100];
    size_t len = 0;
    int rc = 0;
    errno = 0;
    for (long no = 1; rc == 0 && getline(&line, &len, f) != -1; no++) {
        snprintf(where, sizeof where, "%s:%ld", path, no);
        char *s = line + strspn(line, " \t");
        if (s[0] == 'v' && (s[1] == ' ' || s[1] == '\t')) rc = read_vertex(m, s + 2, where);
        else if (s[0] == 'f' && (s[1] == ' ' || s[1] == '\t')) rc = read_face(m, s + 2, where);
    }
    if (rc == 0 && ferror(f)) {
        fprintf(stderr, "%s: %s\n", path, errno ? strerror(errno) : "read error");
        rc = -1;
    }
    if (rc == 0 && m->nt == 0) {
        fprintf(stderr, "%s: no triangles (not an OBJ mesh?)\n", path);
        rc = -1;
    }
    free(line);
    fclose(f);
    return rc;
}

static int count_file(const char *path)
{
    mesh m = {0};
    intersections is;
    int rc = read_obj(path, &m);
    if (rc == 0 && (rc = intersections_count(m.x, m.nv, m.tri, m.nt, &is, NULL)) != 0)
        fprintf(stderr, "%s: out of memory\n", path);
    if (rc == 0)
        printf("%s: %ld intersecting pairs, %d of %d vertices involved (%d triangles)\n", path, is.pairs, is.vertices,
               m.nv, m.nt);
    free(m.x);
    free(m.tri);
    return rc;
}

int main(int argc, char **argv)
{
    static const struct option options[] = {
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    const char *arg = NULL;
    cli_start();
    int opt = cli_next(argc, argv, options, &arg), bad = 0, files = 0;
    if (opt == 'h') {
        fputs(usage, stdout);
        return 0;
    }
    if (opt == CLI_UNKNOWN) { /* the only option is --help: a file comes first */
        fprintf(stderr, "obj_intersections: unknown option '%s'\n%s", arg, usage);
        return 2;
    }
    for (int a = optind; a < argc; a++, files++)
        if (count_file(argv[a])) bad = 1;
    if (!files) {
        fprintf(stderr, "obj_intersections: no files given\n%s", usage);
        return 2;
    }
    return bad;
}
