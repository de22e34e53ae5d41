/* Command-line scanning for the demos and benchmarks: getopt_long, options
 * in order up to the first argument that is not one, names matched exactly
 * (no abbreviations), and each program's own messages for what it refuses. */
#ifndef ODECLOTH_CLI_H
#define ODECLOTH_CLI_H

#include <getopt.h>

enum {
    CLI_END = -1,      /* no arguments left */
    CLI_UNKNOWN = -2,  /* an option the table does not have (or -x, or --flag=value) */
    CLI_NO_VALUE = -3, /* an option that takes a value, last on the line */
    CLI_OPERAND = -4,  /* an argument that is no option (or follows --): it and the rest from optind */
};

/* Starts a scan of a new argument list (getopt's state reset). */
void cli_start(void);

/* The next option of argv: the val of its entry in opts (a getopt_long table
 * ending in a zero entry; -h is 'h'), its value in optarg; or a CLI_ code,
 * *arg then the argument refused. */
int cli_next(int argc, char **argv, const struct option *opts, const char **arg);

#endif
