/* cli_args.c - reading the values of command-line options, shared by the
 * subcommands (cli.h). */
#include "cli/cli.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

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
