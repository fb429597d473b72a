/* cli_args.c - the one checked reading of option values and counts on the
 * command line (cli.h): a value is never taken from the next option, and a
 * count is plain decimal digits inside its documented range. */
#include "cli/cli.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
