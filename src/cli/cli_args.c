/* cli_args.c - reading the values of command-line options, shared by the
 * subcommands (cli.h). */
#include "cli/cli.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int rf_cli_parse_double(const char *cmd, const char *opt, const char *s, double *x)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v)) {
        fprintf(stderr, "rockfuzz %s: --%s '%s': not a finite number\n", cmd, opt, s);
        return 0;
    }
    *x = v;
    return 1;
}

const char *rf_cli_dir_argument(const char *cmd, int argc, char **argv, const char *help, int *status)
{
    const char *dir = NULL;
    for (int a = 1; a < argc; a++) {
        if (!strcmp(argv[a], "-h") || !strcmp(argv[a], "--help")) {
            fputs(help, stdout);
            *status = 0;
            return NULL;
        }
        if (argv[a][0] == '-' || dir) {
            fprintf(stderr, "rockfuzz %s: unexpected argument '%s' (see `rockfuzz %s --help`)\n", cmd, argv[a], cmd);
            *status = 2;
            return NULL;
        }
        dir = argv[a];
    }
    if (!dir) {
        fprintf(stderr, "rockfuzz %s: missing the run directory (see `rockfuzz %s --help`)\n", cmd, cmd);
        *status = 2;
    }
    return dir;
}
