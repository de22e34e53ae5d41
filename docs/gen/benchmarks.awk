# Writes docs/benchmarks.md: the prose of benchmarks.md.in, each @name@ in
# it replaced by a table or figure computed from the benchmarks' CSVs in
# DATA (examples/gallery: the files the benchmarks wrote with --out).
# usage: awk -v data=examples/gallery -f benchmarks.awk benchmarks.md.in

# the rows of DATA/name.csv, split into cell[row, column] (and, when its first line names the columns,
# col[name] = column); returns the row count
function load(name, has_header,    path, line, n, i, k, f) {
    path = data "/" name ".csv"
    n = 0
    while ((getline line < path) > 0) {
        k = split(line, f, ",")
        if (has_header && !header_read) { for (i = 1; i <= k; i++) col[f[i]] = i; header_read = 1; continue }
        n++
        for (i = 1; i <= k; i++) cell[n, i] = f[i]
    }
    close(path)
    if (n == 0) { print "benchmarks.awk: nothing in " path > "/dev/stderr"; exit 1 }
    return n
}
function c(r, name) { return cell[r, col[name]] }
function reset() { split("", cell); split("", col); header_read = 0 }
function fmt(x) { return x >= 100 ? sprintf("%.0f", x) : x >= 10 ? sprintf("%.1f", x) : sprintf("%.3g", x) }

# steps per CPU second and CG iterations per step, per grid, step and preconditioner; the fastest in bold
function step_table(    n, r, i, key, best, line, pcs, np, p, out, s, x, seen, keys, nk, sps, cg, part) {
    reset(); n = load("bench_step", 1)
    np = split("jacobi block ssor multigrid", pcs, " ")
    out = "| grid | h | Jacobi: steps per CPU s, CG it | block Jacobi | SSOR | multigrid |\n|---|---|---|---|---|---|\n"
    for (r = 1; r <= n; r++) {
        key = c(r, "grid") " " c(r, "hz")
        if (!(key in seen)) { seen[key] = 1; keys[++nk] = key }
        sps[key, c(r, "precond")] = c(r, "cpu_steps_per_s") + 0
        cg[key, c(r, "precond")] = c(r, "cg_iterations") + 0
        part[key, c(r, "precond")] = c(r, "partial") + 0
    }
    for (i = 1; i <= nk; i++) {
        key = keys[i]; split(key, s, " ")
        best = ""
        for (p = 1; p <= np; p++)
            if ((key, pcs[p]) in sps && (best == "" || sps[key, pcs[p]] > sps[key, best])) best = pcs[p]
        line = "| " s[1] "x" s[1] " | 1/" s[2]
        for (p = 1; p <= np; p++) {
            if (!((key, pcs[p]) in sps)) { line = line " | "; continue }
            x = fmt(sps[key, pcs[p]]) (part[key, pcs[p]] ? "*" : "")
            line = line " | " (pcs[p] == best ? "**" x "**" : x) ", " fmt(cg[key, pcs[p]])
        }
        out = out line " |\n"
    }
    return out
}

# the most steps per CPU second of any preconditioner on grid N at rate hz
function step_best(N, hz,    n, r, best) {
    reset(); n = load("bench_step", 1)
    for (r = 1; r <= n; r++)
        if (c(r, "grid") == N && c(r, "hz") == hz && c(r, "cpu_steps_per_s") + 0 > best)
            best = c(r, "cpu_steps_per_s") + 0
    if (best == "") { print "benchmarks.awk: no bench_step row at " N ", " hz > "/dev/stderr"; exit 1 }
    return fmt(best)
}

# the drape benchmark's rows: time, failures, iterations, strain, the slowest step
function drape_table(    n, r, out, gain) {
    reset(); n = load("bench_drape_newton", 1)
    out = "| scene | variant | N | wall, CPU s | failed, substepped | Newton, CG per step | p99, max strain " \
          "| slowest, median ms | energy gain J |\n|---|---|---|---|---|---|---|---|---|\n"
    for (r = 1; r <= n; r++) {
        gain = c(r, "energy_gain_J"); if (gain == "nan") gain = ""; else gain = sprintf("%.2g", gain)
        out = out "| " c(r, "scene") " | " c(r, "variant") " | " c(r, "N") " | " fmt(c(r, "wall_s") + 0) ", " \
              fmt(c(r, "cpu_s") + 0) " | " c(r, "failed_steps") ", " c(r, "substepped_steps") " | " \
              fmt(c(r, "newton_per_step") + 0) ", " \
              fmt(c(r, "cg_per_step") + 0) " | " sprintf("%.4f, %.4f", c(r, "p99_strain"), c(r, "max_strain")) \
              " | " fmt(c(r, "max_step_ms") + 0) ", " fmt(c(r, "median_step_ms") + 0) " | " gain " |\n"
    }
    return out
}
# one figure of the drape benchmark: column name of scene's row at N
function drape(scene, N, name,    n, r) {
    reset(); n = load("bench_drape_newton", 1)
    for (r = 1; r <= n; r++) if (c(r, "scene") == scene && c(r, "N") == N) return fmt(c(r, name) + 0)
    print "benchmarks.awk: no " scene " row at N = " N > "/dev/stderr"; exit 1
}

# the stability map counted: per method, stable cells and the failures by kind
function stability_table(    n, r, m, i, out, title, names, k, cells, count, held) {
    reset(); n = load("bench_stability", 0)  # no header: method, k_t, h, status, status name, ..., held (9)
    k = split("explicit symplectic be_rule be_norule bdf2", names, " ")
    title["explicit"] = "explicit Euler"; title["symplectic"] = "symplectic Euler"
    title["be_rule"] = "backward Euler, definiteness rule"; title["be_norule"] = "backward Euler, no rule"
    title["bdf2"] = "BDF2, definiteness rule"
    for (r = 1; r <= n; r++) {
        m = cell[r, 1]; cells[m]++
        count[m, cell[r, 5]]++
        if (cell[r, 5] == "stable" && cell[r, 9] == 1) held[m]++
    }
    out = "| method | cells | stable | only with the limit | strain | CG indefinite | CG max it " \
          "| energy growth | NaN |\n|---|---|---|---|---|---|---|---|---|\n"
    for (i = 1; i <= k; i++) {
        m = names[i]
        out = out "| " title[m] " | " cells[m] " | " count[m, "stable"] + 0 " | " held[m] + 0 " | " \
              count[m, "strain"] + 0 " | " count[m, "CG indefinite"] + 0 " | " count[m, "CG max iterations"] + 0 \
              " | " count[m, "energy growth"] + 0 " | " count[m, "NaN"] + 0 " |\n"
    }
    return out
}

# a figure of the stability map's start state (the same in every row of bench_stability.csv): w (the top
# mode's frequency, rad/s), zeta (its damping ratio), line (symplectic Euler's bound, ms), budget (J) or
# tenth (a tenth of the budget, J)
function stab(name,    n) {
    reset(); n = load("bench_stability", 0)
    if (name == "w") return sprintf("%.0f", cell[1, 15])
    if (name == "zeta") return sprintf("%.3g", cell[1, 16])
    if (name == "line") return sprintf("%.3g", 1000 * cell[1, 14])
    if (name == "budget") return sprintf("%.2f", cell[1, 17])
    if (name == "tenth") return sprintf("%.2f", cell[1, 17] / 10)
    print "benchmarks.awk: no stability figure " name > "/dev/stderr"; exit 1
}

# scaling: time, iterations and memory per grid
function scaling_table(    n, r, out) {
    reset(); n = load("bench_scaling", 1)
    out = "| grid | nodes | ms per step | CG iterations | RSS growth, bytes per node |\n|---|---|---|---|---|\n"
    for (r = 1; r <= n; r++)
        out = out "| " c(r, "grid") "x" c(r, "grid") " | " c(r, "nodes") " | " fmt(c(r, "median_step_ms") + 0) \
              " | " sprintf("%.0f", c(r, "cg_iterations")) " | " c(r, "rss_bytes_per_node") " |\n"
    return out
}
# the least-squares exponent of column name against the node count
function scaling_exponent(name,    n, r, x, y, sx, sy, sxx, sxy) {
    reset(); n = load("bench_scaling", 1)
    for (r = 1; r <= n; r++) {
        x = log(c(r, "nodes")); y = log(c(r, name))
        sx += x; sy += y; sxx += x * x; sxy += x * y
    }
    return sprintf("%.2f", (n * sxy - sx * sy) / (n * sxx - sx * sx))
}

# the accuracy-driven controller on both scenes of the work-precision chart
function controller_table(    n, r, sc, t, i, out, method, seen, tols, nt, fig) {
    reset(); n = load("bench_workprecision", 0)  # no header; see examples/bench_workprecision.c
    for (r = 1; r <= n; r++) {
        if (cell[r, 2] != "controller") continue
        t = cell[r, 4]; sc = cell[r, 1]
        if (!(t in seen)) { seen[t] = 1; tols[++nt] = t }
        method = cell[r, 14] >= 0.5 ? "symplectic" : "BE"
        fig[t, sc] = sprintf("%.2f, %.1f %s, %.2g (%.2g), %.2f", cell[r, 6] / cell[r, 5], cell[r, 12], method,
                             cell[r, 7], cell[r, 16], cell[r, 15] / cell[r, 6])
    }
    out = "| tolerance m/s | swing: error / requested, substeps, CPU s / s (frontier), estimate / error " \
          "| sphere: the same |\n|---|---|---|\n"
    for (i = 1; i <= nt; i++) out = out "| " tols[i] " | " fig[tols[i], "swing"] " | " fig[tols[i], "sphere"] " |\n"
    return out
}

# the contacts' cost per step, per grid and collider
function contact_table(    n, r, out, tri, what) {
    reset(); n = load("bench_contact", 1)
    what["sphere"] = "sphere r 0.3"; what["box"] = "box 0.6 x 0.6 x 0.4"
    what["trimesh1000"] = "trimesh, 1000 triangles, triangle tests on (default)"
    what["trimesh-vtx"] = "the same, triangle tests off"
    what["trimesh-link"] = "the same, link tests instead"; what["box-link"] = "box, link tests instead"
    out = "| grid, h | collider | finding contacts ms | whole step ms | share " \
          "| contacts (by triangle, link tests) |\n|---|---|---|---|---|---|\n"
    for (r = 1; r <= n; r++) {
        tri = c(r, "triangle_contacts") + c(r, "edge_contacts")
        out = out "| " c(r, "grid") "x" c(r, "grid") ", 1/" c(r, "hz") " | " what[c(r, "collider")] " | " \
              fmt(c(r, "contact_ms") + 0) " | " fmt(c(r, "step_ms") + 0) " | " \
              sprintf("%.0f%%", 100 * c(r, "contact_share")) \
              " | " sprintf("%.0f", c(r, "contacts")) \
              (tri > 0 ? sprintf(" (%.0f)", tri) : "") " |\n"
    }
    return out
}

# @wpfile(name)@ (it expands to nothing) names the work-precision run the next figures come from:
# bench_workprecision or bench_workprecision_cotton
# one figure of that run (name.csv, no header; see
# examples/bench_workprecision.c): series at rate hz on scene and grid; field mm or m (its error), cpu
# (CPU s per simulated s) or unconverged (steps kept unconverged)
function wp(scene, grid, series, hz, field,    n, r) {
    reset(); n = load(wp_file, 0)
    for (r = 1; r <= n; r++) {
        if (cell[r, 1] != scene || cell[r, 17] != grid || cell[r, 2] != series || cell[r, 3] != hz) continue
        if (field == "cpu") return sprintf("%.2g", cell[r, 7])
        if (field == "unconverged") return cell[r, 20] + 0
        if (cell[r, 9] == 1) return "blown up"
        return field == "mm" ? sprintf("%.2g", 1000 * cell[r, 6]) : sprintf("%.2g", cell[r, 6])
    }
    print "benchmarks.awk: no " series " at 1/" hz " on " scene ", " grid " in " wp_file > "/dev/stderr"; exit 1
}
# how far a work-precision run's reference moves when its h is halved, m
function wpref(scene, grid,    n, r) {
    reset(); n = load(wp_file, 0)
    for (r = 1; r <= n; r++)
        if (cell[r, 1] == scene && cell[r, 17] == grid && cell[r, 2] == "reference_change")
            return sprintf("%.2g", cell[r, 6])
    print "benchmarks.awk: no reference on " scene ", " grid " in " wp_file > "/dev/stderr"; exit 1
}
# a fitted order (name_orders.csv): field order, window (1/lo..1/hi), or the
# errors at its ends, lo_mm and hi_mm
function wpo(scene, grid, series, field,    n, r) {
    reset(); n = load(wp_file "_orders", 1)
    for (r = 1; r <= n; r++) {
        if (c(r, "scene") != scene || c(r, "grid") != grid || c(r, "series") != series) continue
        if (field == "order") return sprintf("%.2f", c(r, "order"))
        if (field == "window") return "1/" c(r, "hz_lo") "..1/" c(r, "hz_hi")
        if (field == "lo_mm") return sprintf("%.2g", 1000 * c(r, "error_at_hz_lo_m"))
        if (field == "hi_mm") return sprintf("%.2g", 1000 * c(r, "error_at_hz_hi_m"))
    }
    print "benchmarks.awk: no order of " series " on " scene ", " grid " in " wp_file > "/dev/stderr"; exit 1
}

# a table a benchmark wrote itself (DATA/name.md), without its comment lines
function include(name,    path, line, out) {
    path = data "/" name ".md"
    while ((getline line < path) > 0) if (line !~ /^<!--/) out = out line "\n"
    close(path)
    if (out == "") { print "benchmarks.awk: nothing in " path > "/dev/stderr"; exit 1 }
    sub(/^\n+/, "", out)
    return out
}

# @name@ or @name(arg,arg)@ in the template: the table or figure
function expand(key,    a, f) {
    if (key == "step_table") return step_table()
    if (key == "drape_table") return drape_table()
    if (key == "stability_table") return stability_table()
    if (key == "scaling_table") return scaling_table()
    if (key == "controller_table") return controller_table()
    if (key == "contact_table") return contact_table()
    if (key ~ /^include\(/) { sub(/^[a-z_]+\(/, "", key); sub(/\)$/, "", key); return include(key) }
    if (key ~ /^scaling_exponent\(/) { sub(/^[a-z_]+\(/, "", key); sub(/\)$/, "", key); return scaling_exponent(key) }
    if (key ~ /^wp[a-z]*\(/) {
        f = key; sub(/\(.*/, "", f); sub(/^[a-z_]+\(/, "", key); sub(/\)$/, "", key); split(key, a, ",")
        if (f == "wpfile") { wp_file = a[1]; return "" }
        if (f == "wp") return wp(a[1], a[2], a[3], a[4], a[5])
        if (f == "wpref") return wpref(a[1], a[2])
        if (f == "wpo") return wpo(a[1], a[2], a[3], a[4])
    }
    if (key ~ /^stab\(/) { sub(/^[a-z_]+\(/, "", key); sub(/\)$/, "", key); return stab(key) }
    if (key ~ /^step_best\(/) {
        sub(/^[a-z_]+\(/, "", key); sub(/\)$/, "", key); split(key, a, ",")
        return step_best(a[1], a[2])
    }
    if (key ~ /^drape\(/) {
        sub(/^drape\(/, "", key); sub(/\)$/, "", key); split(key, a, ",")
        return drape(a[1], a[2], a[3])
    }
    print "benchmarks.awk: unknown @" key "@" > "/dev/stderr"; exit 1
}
{
    line = $0
    while (match(line, /@[a-z_]+(\([a-z_0-9,.-]*\))?@/)) {
        f = expand(substr(line, RSTART + 1, RLENGTH - 2))
        if (line == substr(line, RSTART, RLENGTH)) sub(/\n$/, "", f)  # a table on its own line
        line = substr(line, 1, RSTART - 1) f substr(line, RSTART + RLENGTH)
    }
    print line
}
