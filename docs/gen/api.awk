# Markdown reference of one public header: its opening comment, its types,
# then each group of ODECLOTH_API declarations with the comment directly
# above them, one code block per section of the header (/* ---- name */).
# usage: awk -v path=core/include/odecloth/cloth.h -f api.awk HEADER
function add(text) {
    if (group != "") { blocks = blocks (blocks != "" ? "\n" : "") group; group = "" }
    blocks = blocks text
}
function flush() { add("") }
function section_end() {
    flush()
    if (blocks != "") body = body (heading != "" ? "### " heading "\n\n" : "") "```c\n" blocks "```\n\n"
    blocks = ""
}
function forget() { flush(); comment = "" }
BEGIN { name = path; sub(/.*\//, "", name) }
# the file's opening comment, before the include guard: the header's overview
NR == 1 && /^\/\*/ { in_overview = 1 }
in_overview {
    line = $0
    sub(/^ ?\/?\*+ ?/, "", line); sub(/ *\*\/$/, "", line); sub(/^\/$/, "", line)
    overview = overview line "\n"
    if ($0 ~ /\*\//) in_overview = 0
    next
}
# the types users fill in or read: typedef struct / enum NAME
/^typedef (struct|enum) [A-Za-z_]+/ {
    t = $0; sub(/^typedef (struct|enum) /, "", t)
    if (t ~ /^[A-Za-z0-9_]+ \**[A-Za-z0-9_]+;/) sub(/^[A-Za-z0-9_]+ \**/, "", t) # typedef struct x *name;
    sub(/[^A-Za-z0-9_].*/, "", t)
    t = "`" t "`"
    if (types == "") { types = "Types (their fields are documented in the header): " t; col = length(types) }
    else if (col + length(t) > 110) { types = types ",\n" t; col = length(t) }
    else { types = types ", " t; col += 2 + length(t) }
}
/^#/ { forget(); next }
/^\/\* *-----+ .*\*\/ *$/ {
    section_end()
    heading = $0; sub(/^\/\* *-+ */, "", heading); sub(/ *\*\/ *$/, "", heading)
    next
}
# comments and typedefs directly above declarations (no blank line
# between) are kept with them as their explanation
in_comment || in_typedef {
    comment = comment $0 "\n"
    if (in_comment && $0 ~ /\*\//) in_comment = 0
    if (in_typedef && $0 ~ /^}/) in_typedef = 0
    next
}
/^\/\*/ {
    if (group != "" || comment == "") forget()
    comment = comment $0 "\n"
    if ($0 !~ /\*\//) in_comment = 1
    next
}
/^typedef .*;/ && comment != "" { comment = comment $0 "\n"; next }
/^typedef (struct|enum) .*\{ *$/ && comment != "" && group == "" { comment = comment $0 "\n"; in_typedef = 1; next }
/^ODECLOTH_API/ {
    if (comment != "") { flush(); group = comment; comment = "" }
    in_decl = 1
}
in_decl {
    line = $0
    if (sub(/^ODECLOTH_API /, "", line) == 0) sub(/^             /, "", line)
    group = group line "\n"
    if ($0 ~ /;/) in_decl = 0
    next
}
/^[ \t]*$/ { forget(); next }
{ forget() }
END {
    section_end()
    sub(/^\n+/, "", overview); sub(/\n+$/, "", overview)
    print "## " name "\n"
    print "[`" path "`](../" path ")\n"
    if (overview != "") print "```text\n" overview "\n```\n"
    if (types != "") print types ".\n"
    printf "%s", body
}
