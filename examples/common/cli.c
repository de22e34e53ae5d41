/* Command-line scanning on getopt_long (cli.h). */
#include <string.h>
#include "cli.h"

void cli_start(void)
{
    optind = 0; /* glibc: start over, reading the ordering from the option string again */
    opterr = 0; /* the callers print their own messages */
}

/* Whether arg spells the long option name in full: --name or --name=value. */
static int exact(const char *arg, const char *name)
{
    size_t n = strlen(name);
    return !strncmp(arg, "--", 2) && !strncmp(arg + 2, name, n) && (arg[2 + n] == '\0' || arg[2 + n] == '=');
}

int cli_next(int argc, char **argv, const struct option *opts, const char **arg)
{
    int at = optind ? optind : 1, index = -1;
    /* +: stop at the first non-option; leading ':' tells a missing value apart */
    int c = getopt_long(argc, argv, "+:h", opts, &index);
    if (c == -1) {
        *arg = optind < argc ? argv[optind] : "";
        return optind < argc ? CLI_OPERAND : CLI_END;
    }
    *arg = argv[at];
    if (c == ':') return CLI_NO_VALUE;
    if (c == '?' || (index >= 0 && !exact(argv[at], opts[index].name))) return CLI_UNKNOWN;
    return c;
}
