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

# @step_cg(a,b,hz)@: preconditioner a's CG iterations per step over b's, their range over the grids at
# rate hz (all: every rate), "1.9-3.1"
function step_cg(pa, pb, hz,    n, r, key, it, lo, hi, x, k, s) {
    reset(); n = load("bench_step", 1)
    for (r = 1; r <= n; r++) it[c(r, "grid") " " c(r, "hz"), c(r, "precond")] = c(r, "cg_iterations") + 0
    for (k in it) {
        split(k, s, SUBSEP); key = s[1]
        if (s[2] != pb || !((key, pa) in it) || (hz != "all" && key !~ (" " hz "$"))) continue
        x = it[key, pa] / it[k]
        if (lo == "" || x < lo) lo = x
        if (hi == "" || x > hi) hi = x
    }
    if (lo == "") { print "benchmarks.awk: no " pa " against " pb " at " hz > "/dev/stderr"; exit 1 }
    return sprintf("%.2g-%.2g", lo, hi)
}
# @step_wall@: the least steps per wall second of any bench_step row as a share of its per CPU second
function step_wall(    n, r, x, lo) {
    reset(); n = load("bench_step", 1)
    for (r = 1; r <= n; r++) {
        x = c(r, "steps_per_s") / c(r, "cpu_steps_per_s")
        if (lo == "" || x < lo) lo = x
    }
    return sprintf("%.2f", lo)
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

# @drape_wall@: the most wall time of a drape benchmark row as a multiple of its CPU time
function drape_wall(    n, r, x, hi) {
    reset(); n = load("bench_drape_newton", 1)
    for (r = 1; r <= n; r++) {
        x = c(r, "wall_s") / c(r, "cpu_s")
        if (hi == "" || x > hi) hi = x
    }
    return sprintf("%.1f", hi)
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
# tenth (a tenth of the budget, J), bending or compression (c_b / k_b, c_t / k_c, s); past: the
# smallest h of the map past the line
function stab(name,    n, r, x) {
    reset(); n = load("bench_stability", 0)
    if (name == "w") return sprintf("%.0f", cell[1, 15])
    if (name == "zeta") return sprintf("%.3g", cell[1, 16])
    if (name == "line") return sprintf("%.3g", 1000 * cell[1, 14])
    if (name == "budget") return sprintf("%.2f", cell[1, 17])
    if (name == "tenth") return sprintf("%.2f", cell[1, 17] / 10)
    if (name == "bending") return sci(cell[1, 12])
    if (name == "compression") return sci(cell[1, 13])
    if (name == "past") {  # the smallest h of the map past the line
        for (r = 1; r <= n; r++)
            if (cell[r, 3] + 0 > cell[1, 14] + 0 && (x == "" || cell[r, 3] + 0 < x)) x = cell[r, 3] + 0
        return per_h(x)
    }
    print "benchmarks.awk: no stability figure " name > "/dev/stderr"; exit 1
}

# "a, b and c" of the n words w[1..n]
function join_and(w, n,    i, out) {
    for (i = 1; i <= n; i++) out = out (i == 1 ? "" : i == n ? " and " : ", ") w[i]
    return out
}
# x as 4e-4 or 2.5e-4
function sci(x,    s) { s = sprintf("%.1e", x); sub(/\.0e/, "e", s); sub(/e-0/, "e-", s); return s }
function per_h(h) { return "1/" sprintf("%.0f", 1 / h) }
# the stability map's cells of the methods ms ("be_rule+bdf2"): nk k_t values sk[j] (as they come), per k_t
# the h values sh[j, i] (ascending) and whether every method's cell there is stable (sok) or fails (sbad)
function smap_load(ms,    n, r, want, m, i, j, key, kj, hi, nh) {
    reset(); n = load("bench_stability", 0)
    split("", sk); split("", sh); split("", sok); split("", sbad); split("", sheld); split("", snh); nk = 0
    split(ms, m, "+"); for (i in m) want[m[i]] = 1
    for (r = 1; r <= n; r++) {
        if (!(cell[r, 1] in want)) continue
        key = sprintf("%.0f", cell[r, 2])
        if (!(key in kj)) { kj[key] = ++nk; sk[nk] = key }
        j = kj[key]
        if (!((j, cell[r, 3]) in hi)) { hi[j, cell[r, 3]] = ++snh[j]; sh[j, snh[j]] = cell[r, 3] + 0
                                        sok[j, snh[j]] = 1; sbad[j, snh[j]] = 1 }
        i = hi[j, cell[r, 3]]
        if (cell[r, 5] == "stable") sbad[j, i] = 0; else sok[j, i] = 0
        if (cell[r, 9] == 1) sheld[j, i] = 1
    }
    if (nk == 0) { print "benchmarks.awk: no method " ms " in bench_stability" > "/dev/stderr"; exit 1 }
}
# one k_t's figure (an h, or "" when it has none): kind stable_to (the largest h up to which every cell is
# stable), fail_from (the smallest h from which every cell fails), stable_max (the largest stable h) or
# held_min (the smallest h of a cell stable only with the elongation limit)
function smap_k(j, kind,    i, x) {
    if (kind == "stable_to") { for (i = 1; i <= snh[j] && sok[j, i]; i++) x = sh[j, i]; return x }
    if (kind == "fail_from") { for (i = snh[j]; i >= 1 && sbad[j, i]; i--) x = sh[j, i]; return x }
    if (kind == "stable_max") { for (i = 1; i <= snh[j]; i++) if (!sbad[j, i]) x = sh[j, i]; return x }
    if (kind == "held_min") { for (i = snh[j]; i >= 1; i--) if (sheld[j, i]) x = sh[j, i]; return x }
    print "benchmarks.awk: no stability kind " kind > "/dev/stderr"; exit 1
}
# @smap(methods,kind,how)@: kind's h over the k_t values, how = min, max or by ("1/1286 at k_t 20;
# 1/827 at 63, 200 and 632": each value with the k_t values that have it, in the map's order)
function smap(ms, kind, how,    j, x, best, v, nv, seen, ks, nks, w, out, g) {
    smap_load(ms)
    for (j = 1; j <= nk; j++) {
        x = smap_k(j, kind); if (x == "") continue
        if (how == "min" && (best == "" || x < best)) best = x
        if (how == "max" && (best == "" || x > best)) best = x
        if (!(x in seen)) { seen[x] = ++nv; v[nv] = x }
        ks[seen[x], ++nks[seen[x]]] = sk[j]
    }
    if (how != "by") {
        if (best == "") { print "benchmarks.awk: no " kind " in " ms > "/dev/stderr"; exit 1 }
        return per_h(best)
    }
    for (g = 1; g <= nv; g++) {
        split("", w); for (j = 1; j <= nks[g]; j++) w[j] = ks[g, j]
        out = out (g == 1 ? "" : "; ") per_h(v[g]) (g == 1 ? " at k_t " : " at ") join_and(w, nks[g])
    }
    return out
}
# @sfails(methods,k_t)@: the h values at which a cell fails at that k_t, "1/24, 1/16 and 1/10"
function sfails(ms, k,    j, i, w, n) {
    smap_load(ms)
    for (j = 1; j <= nk; j++) if (sk[j] == k) for (i = 1; i <= snh[j]; i++) if (!sok[j, i]) w[++n] = per_h(sh[j, i])
    if (n == 0) { print "benchmarks.awk: no failure of " ms " at k_t " k > "/dev/stderr"; exit 1 }
    return join_and(w, n)
}
# @sgrid(h)@ or @sgrid(k)@: the map's step sizes ("1/2000 .. 1/10 s (13 steps)") or stiffnesses
function sgrid(what,    n, r, lo, hi, x, seen, count, col) {
    reset(); n = load("bench_stability", 0); col = what == "h" ? 3 : 2
    for (r = 1; r <= n; r++) {
        x = cell[r, col] + 0
        if (!(x in seen)) { seen[x] = 1; count++ }
        if (lo == "" || x < lo) lo = x
        if (hi == "" || x > hi) hi = x
    }
    if (what == "h") return per_h(lo) " .. " per_h(hi) " s (" count " steps)"
    return sprintf("%.0f .. %.0f N/m (%d)", lo, hi, count)
}
# @stwin(methods)@: when the twins without the limit failed, the range in ms ("1.2-7")
function stwin(ms,    n, r, m, want, i, lo, hi, x) {
    reset(); n = load("bench_stability", 0)
    split(ms, m, "+"); for (i in m) want[m[i]] = 1
    for (r = 1; r <= n; r++) {
        if (!(cell[r, 1] in want) || cell[r, 9] != 1) continue
        x = 1000 * cell[r, 11]
        if (lo == "" || x < lo) lo = x
        if (hi == "" || x > hi) hi = x
    }
    if (lo == "") { print "benchmarks.awk: no twin of " ms " failed" > "/dev/stderr"; exit 1 }
    return sprintf("%.2g-%.2g", lo, hi)
}
# @senergy(methods)@: the cells that failed by energy growth, "1.98 J at k_t 2000, h = 1/1286"
function senergy(ms,    n, r, m, want, i, w, nw) {
    reset(); n = load("bench_stability", 0)
    split(ms, m, "+"); for (i in m) want[m[i]] = 1
    for (r = 1; r <= n; r++)
        if ((cell[r, 1] in want) && cell[r, 5] == "energy growth")
            w[++nw] = sprintf("%.3g J at k_t %.0f, h = %s", cell[r, 18], cell[r, 2], per_h(cell[r, 3]))
    if (nw == 0) { print "benchmarks.awk: no energy growth in " ms > "/dev/stderr"; exit 1 }
    return join_and(w, nw)
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

# @ctl(scene,tol,field)@: a figure of the controller's run at tolerance tol on scene (tol min: its run with
# the smallest error) in bench_workprecision.csv: ratio (error / requested), requested_mm, error_mm,
# frames (60 per simulated s), refshare or referr (the reference's change against requested or error, %)
function ctl(scene, tol, field,    n, r, x, ref) {
    reset(); n = load("bench_workprecision", 0)
    for (r = 1; r <= n; r++) {
        if (cell[r, 1] == scene && cell[r, 2] == "reference_change") ref = cell[r, 6]
        if (cell[r, 1] != scene || cell[r, 2] != "controller") continue
        if (tol == "min" ? x == "" || cell[r, 6] + 0 < cell[x, 6] : cell[r, 4] + 0 == tol + 0) x = r
    }
    if (x == "" || ref == "") { print "benchmarks.awk: no controller at " tol " on " scene > "/dev/stderr"; exit 1 }
    if (field == "ratio") return sprintf("%.2f", cell[x, 6] / cell[x, 5])
    if (field == "requested_mm") return sprintf("%.3g", 1000 * cell[x, 5])
    if (field == "error_mm") return sprintf("%.2f", 1000 * cell[x, 6])
    if (field == "frames") return sprintf("%.0f", 60 * cell[x, 10])
    if (field == "refshare") return sprintf("%.0f%%", 100 * ref / cell[x, 5])
    if (field == "referr") return sprintf("%.0f%%", 100 * ref / cell[x, 6])
    print "benchmarks.awk: no controller figure " field > "/dev/stderr"; exit 1
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
# the range of a series' errors over the rates lo..hi Hz, mm ("0.18-0.24")
function wprange(scene, grid, series, lo, hi,    n, r, a, b, x) {
    reset(); n = load(wp_file, 0)
    for (r = 1; r <= n; r++) {
        if (cell[r, 1] != scene || cell[r, 17] != grid || cell[r, 2] != series) continue
        if (cell[r, 3] + 0 < lo + 0 || cell[r, 3] + 0 > hi + 0 || cell[r, 9] == 1) continue
        x = 1000 * cell[r, 6]
        if (a == "" || x < a) a = x
        if (b == "" || x > b) b = x
    }
    if (a == "") { print "benchmarks.awk: no " series " over 1/" lo "..1/" hi " in " wp_file > "/dev/stderr"; exit 1 }
    return sprintf("%.2g-%.2g", a, b)
}
# the smallest step from which a series never blows up, "1/1536"
function wpstable(scene, grid, series,    n, r, lo, bad, hz) {
    reset(); n = load(wp_file, 0)
    for (r = 1; r <= n; r++)
        if (cell[r, 1] == scene && cell[r, 17] == grid && cell[r, 2] == series && cell[r, 9] == 1 &&
            cell[r, 3] + 0 > bad + 0) bad = cell[r, 3] + 0
    for (r = 1; r <= n; r++) {
        hz = cell[r, 3] + 0
        if (cell[r, 1] == scene && cell[r, 17] == grid && cell[r, 2] == series && hz > bad + 0 &&
            (lo == "" || hz < lo)) lo = hz
    }
    if (lo == "") { print "benchmarks.awk: " series " never stable in " wp_file > "/dev/stderr"; exit 1 }
    return "1/" lo
}
# the implicit series' blown-up runs on scene and grid, per step: "at 1/24 for BE and BDF2; at 1/60 ..."
# (BE backward Euler; linearised at CG 1e-5 with block Jacobi unless named)
function wpblown(scene, grid,    n, r, title, hz, nh, w, nw, out, i, j, t, by) {
    split("bdf2_1e-5:BDF2,be_1e-2:BE at CG 1e-2,be_1e-3:BE at CG 1e-3,be_1e-5:BE,be_1e-5_jacobi:BE with Jacobi," \
          "be_1e-5_multigrid:BE with multigrid,be_1e-5_ssor:BE with SSOR,newton1_be:one-iteration Newton BE," \
          "newton1_bdf2:one-iteration Newton BDF2,newton_be:Newton BE,newton_bdf2:Newton BDF2", w, ",")
    for (i in w) { split(w[i], t, ":"); title[t[1]] = t[2] }
    reset(); n = load(wp_file, 0)
    for (r = 1; r <= n; r++) {
        if (cell[r, 1] != scene || cell[r, 17] != grid || cell[r, 9] != 1 || !(cell[r, 2] in title)) continue
        if (!((cell[r, 3] + 0) in nw)) hz[++nh] = cell[r, 3] + 0
        by[cell[r, 3] + 0, ++nw[cell[r, 3] + 0]] = title[cell[r, 2]]
    }
    for (i = 1; i <= nh; i++)
        for (j = i + 1; j <= nh; j++) if (hz[j] < hz[i]) { t[0] = hz[i]; hz[i] = hz[j]; hz[j] = t[0] }
    for (i = 1; i <= nh; i++) {
        split("", w); for (j = 1; j <= nw[hz[i]]; j++) w[j] = by[hz[i], j]
        out = out (i == 1 ? "" : "; ") "at 1/" hz[i] " for " join_and(w, nw[hz[i]])
    }
    if (out == "") out = "nowhere"
    return out
}
# log CPU s per s at which series s (in the arrays wpe, wpc of wp_points) reaches error e: log-log
# interpolated between its runs, its cheapest run's above its largest error, "" below its smallest
function wp_cost(s, e,    i, lo, hi, t) {
    for (i = 1; i <= wpn[s]; i++) {
        if (wpe[s, i] >= e && (hi == "" || wpe[s, i] < wpe[s, hi])) hi = i
        if (wpe[s, i] <= e && (lo == "" || wpe[s, i] > wpe[s, lo])) lo = i
    }
    if (hi == "") { for (i = 1; i <= wpn[s]; i++) if (t == "" || wpc[s, i] < t) t = wpc[s, i]; return t }
    if (lo == "") return ""
    if (wpe[s, hi] == wpe[s, lo]) return wpc[s, lo]
    t = (e - wpe[s, lo]) / (wpe[s, hi] - wpe[s, lo])
    return wpc[s, lo] + t * (wpc[s, hi] - wpc[s, lo])
}
# the cheapest of the series in list at error e ("" where none reaches it)
function wp_front(list, e,    i, n, s, x, best) {
    n = split(list, s, " ")
    for (i = 1; i <= n; i++) { x = wp_cost(s[i], e); if (x != "" && (best == "" || x < best)) best = x }
    return best
}
# @wpcross(scene,grid,a,b)@: the error (mm) at which series a's cost crosses b's (b: one series, or
# others: the cheapest of every other fixed-step series), scanning down from the largest error; a
# series reaches an error above its runs' at its cheapest run's cost
function wpcross(scene, grid, a, b,    n, r, s, others, seen, es, ne, i, j, t, d, dp, ep, x) {
    reset(); n = load(wp_file, 0); split("", wpn); split("", wpe); split("", wpc)
    for (r = 1; r <= n; r++) {
        s = cell[r, 2]
        if (cell[r, 1] != scene || cell[r, 17] != grid || cell[r, 9] == 1) continue
        if (s == "controller" || s == "reference_change" || !(cell[r, 6] + 0 > 0)) continue
        i = ++wpn[s]; wpe[s, i] = log(cell[r, 6]); wpc[s, i] = log(cell[r, 7])
        if (s != a && (b == "others" || s == b) && !(s in seen)) { seen[s] = 1; others = others " " s }
        if (s == a || (b == "others" || s == b)) es[++ne] = wpe[s, i]
    }
    if (!wpn[a] || others == "") { print "benchmarks.awk: no " a " or " b " in " wp_file > "/dev/stderr"; exit 1 }
    for (i = 1; i <= ne; i++) for (j = i + 1; j <= ne; j++) if (es[j] > es[i]) { t = es[i]; es[i] = es[j]; es[j] = t }
    for (i = 1; i <= ne; i++) {
        t = wp_cost(a, es[i]); x = wp_front(others, es[i])
        if (t == "" || x == "") break
        d = t - x
        if (dp != "" && (d > 0) != (dp > 0) && es[i] != ep)
            return sprintf("%.2g", 1000 * exp(ep + (es[i] - ep) * dp / (dp - d)))
        dp = d; ep = es[i]
    }
    print "benchmarks.awk: " a " does not cross " b " on " scene ", " grid " in " wp_file > "/dev/stderr"; exit 1
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
    if (key == "step_wall") return step_wall()
    if (key == "drape_wall") return drape_wall()
    if (key ~ /^include\(/) { sub(/^[a-z_]+\(/, "", key); sub(/\)$/, "", key); return include(key) }
    if (key ~ /^scaling_exponent\(/) { sub(/^[a-z_]+\(/, "", key); sub(/\)$/, "", key); return scaling_exponent(key) }
    if (key ~ /^wp[a-z]*\(/) {
        f = key; sub(/\(.*/, "", f); sub(/^[a-z_]+\(/, "", key); sub(/\)$/, "", key); split(key, a, ",")
        if (f == "wpfile") { wp_file = a[1]; return "" }
        if (f == "wp") return wp(a[1], a[2], a[3], a[4], a[5])
        if (f == "wpref") return wpref(a[1], a[2])
        if (f == "wpo") return wpo(a[1], a[2], a[3], a[4])
        if (f == "wprange") return wprange(a[1], a[2], a[3], a[4], a[5])
        if (f == "wpstable") return wpstable(a[1], a[2], a[3])
        if (f == "wpblown") return wpblown(a[1], a[2])
        if (f == "wpcross") return wpcross(a[1], a[2], a[3], a[4])
    }
    if (key ~ /^s(map|fails|grid|twin|energy)\(/) {
        f = key; sub(/\(.*/, "", f); sub(/^[a-z_]+\(/, "", key); sub(/\)$/, "", key); split(key, a, ",")
        if (f == "smap") return smap(a[1], a[2], a[3])
        if (f == "sfails") return sfails(a[1], a[2])
        if (f == "sgrid") return sgrid(a[1])
        if (f == "stwin") return stwin(a[1])
        return senergy(a[1])
    }
    if (key ~ /^ctl\(/) {
        sub(/^[a-z_]+\(/, "", key); sub(/\)$/, "", key); split(key, a, ",")
        return ctl(a[1], a[2], a[3])
    }
    if (key ~ /^stab\(/) { sub(/^[a-z_]+\(/, "", key); sub(/\)$/, "", key); return stab(key) }
    if (key ~ /^step_cg\(/) {
        sub(/^[a-z_]+\(/, "", key); sub(/\)$/, "", key); split(key, a, ",")
        return step_cg(a[1], a[2], a[3])
    }
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
    while (match(line, /@[a-z_]+(\([a-z_0-9,.+-]*\))?@/)) {
        f = expand(substr(line, RSTART + 1, RLENGTH - 2))
        if (line == substr(line, RSTART, RLENGTH)) sub(/\n$/, "", f)  # a table on its own line
        line = substr(line, 1, RSTART - 1) f substr(line, RSTART + RLENGTH)
    }
    print line
}
