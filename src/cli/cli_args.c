/* cli_args.c - the one checked reading of option values and counts on the
 * command line (cli.h): a value is never taken from the next option, and a
 * count is plain decimal digits inside its documented range. */
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

const char *rf_cli_value(const char *cmd, int argc, char **argv, int *i)
{
    const char *opt = argv[*i];
    if (*i + 1 >= argc || !strncmp(argv[*i + 1], "--", 2)) {
        fprintf(stderr, "rockfuzz %s: %s needs a value%s%s%s (try --help)\n", cmd, opt,
                *i + 1 < argc ? " (got the option '" : "", *i + 1 < argc ? argv[*i + 1] : "",
                *i + 1 < argc ? "')" : "");
        return NULL;
    }
    return argv[++*i];
}

int rf_cli_count(const char *cmd, const char *opt, const char *v, long long min, long long max, long long *out)
{
    char *end = NULL;
    long long n = 0;
    int ok = v && v[0] >= '0' && v[0] <= '9' && strspn(v, "0123456789") == strlen(v);
    if (ok) {
        errno = 0;
        n = strtoll(v, &end, 10);
        ok = !errno && *end == '\0' && n >= min && n <= max;
    }
    if (!ok) {
        fprintf(stderr, "rockfuzz %s: %s = %s: expected an integer in [%lld, %lld]\n", cmd, opt, v ? v : "(missing)",
                min, max);
        return 0;
    }
    *out = n;
    return 1;
}
