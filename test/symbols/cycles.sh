#!/bin/bash
# No source file of a library calls into a file that calls it back: the
# file-level graph (an edge A -> B where an object of A leaves a symbol
# undefined that an object of B defines) has no cycle. Each cycle found is
# listed, file by file, with the symbols that make its edges.
# usage: cycles.sh LIBRARY.a|OBJECT.o... (a static library or its objects)
set -u
if [ $# -eq 0 ]; then
    echo "cycles: usage: cycles.sh LIBRARY.a|OBJECT.o..."
    exit 1
fi
if ! command -v nm >/dev/null; then
    echo "cycles: nm not found (binutils)"
    exit 1
fi
# POSIX format with file names: "lib.a[member.o]: name type ..." or
# "path/member.o: name type ..."; a member's name is its source's, less ".o"
symbols=$(nm -A -P "$@") || exit 1
echo "$symbols" | awk '
function file_of(s) {
    sub(/:$/, "", s)
    if (s ~ /\]$/) { sub(/^.*\[/, "", s); sub(/\]$/, "", s) } else sub(/^.*\//, "", s)
    sub(/\.o(bj)?$/, "", s)
    return s
}
# Tarjan: strongly connected components; a component of two or more files is a cycle
function visit(v,    k, w) {
    index_of[v] = low[v] = ++counter
    stack[++top] = v
    on_stack[v] = 1
    for (k = 1; k <= nout[v]; k++) {
        w = out[v, k]
        if (!(w in index_of)) {
            visit(w)
            if (low[w] < low[v]) low[v] = low[w]
        } else if (on_stack[w] && index_of[w] < low[v]) low[v] = index_of[w]
    }
    if (low[v] == index_of[v]) {
        ncomp++
        size[ncomp] = 0
        do {
            w = stack[top--]
            on_stack[w] = 0
            comp[w] = ncomp
            size[ncomp]++
        } while (w != v)
    }
}
# One cycle through v within its component: a breadth-first path back to v
function cycle_from(v,    queue, head, tail, seen, from, u, k, w, path, x, m, node) {
    head = 1; tail = 0
    for (k = 1; k <= nout[v]; k++) {
        w = out[v, k]
        if (comp[w] == comp[v] && !(w in seen)) { seen[w] = 1; from[w] = v; queue[++tail] = w }
    }
    while (head <= tail && !(v in seen)) {
        u = queue[head++]
        for (k = 1; k <= nout[u]; k++) {
            w = out[u, k]
            if (comp[w] == comp[u] && !(w in seen)) { seen[w] = 1; from[w] = u; queue[++tail] = w }
        }
    }
    # the path back, then forward
    m = 0
    for (x = v; ; x = from[x]) { node[++m] = x; if (from[x] == v) break }
    node[++m] = v
    path = node[m]
    for (k = m - 1; k >= 1; k--) path = path " -> " node[k]
    print "cycles: one cycle: " path
}
{
    f = file_of($1); name = $2; type = $3
    files[f] = 1
    if (type == "U") undef[f, name] = 1
    else if (type ~ /^[A-TV-Z]$/) definer[name] = f
}
END {
    for (key in undef) {
        split(key, p, SUBSEP)
        a = p[1]; name = p[2]
        if (!(name in definer) || definer[name] == a) continue
        b = definer[name]
        if (!((a, b) in via)) { out[a, ++nout[a]] = b; via[a, b] = name }
        else via[a, b] = via[a, b] " " name
    }
    # a fixed order, so that the report is the same each run
    n = 0
    for (f in files) list[++n] = f
    for (i = 2; i <= n; i++)
        for (j = i; j > 1 && list[j - 1] > list[j]; j--) { t = list[j]; list[j] = list[j - 1]; list[j - 1] = t }
    for (i = 1; i <= n; i++)
        if (!(list[i] in index_of)) visit(list[i])
    bad = 0
    for (i = 1; i <= n; i++) {
        c = comp[list[i]]
        if (size[c] < 2 || (c in shown)) continue
        shown[c] = 1
        bad++
        members = ""
        for (j = 1; j <= n; j++) if (comp[list[j]] == c) members = members " " list[j]
        print "cycles: these files call each other round:" members
        cycle_from(list[i])
        print "cycles: the calls among them:"
        for (j = 1; j <= n; j++)
            for (k = 1; k <= n; k++)
                if (comp[list[j]] == c && comp[list[k]] == c && ((list[j], list[k]) in via))
                    print "    " list[j] " -> " list[k] ": " via[list[j], list[k]]
    }
    nedges = 0
    for (key in via) nedges++
    print "cycles: " n " files, " nedges " calls between files, " bad " group(s) of files calling each other round"
    exit bad > 0
}'
