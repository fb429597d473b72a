/* cmd_report.c - `rockfuzz report DIR`: regenerate DIR/report.html from
 * DIR/result.json and the figures already there; nothing is evaluated. */
#include "cli/cli.h"

#include <stdio.h>
#include <string.h>

#include "rockfuzz/report.h"

int rf_cli_report(int argc, char **argv)
{
    const char *dir = NULL;
    for (int a = 1; a < argc; a++) {
        if (!strcmp(argv[a], "-h") || !strcmp(argv[a], "--help")) {
            printf("Usage: rockfuzz report DIR\n\n"
                   "Write DIR/report.html (self-contained: figures embedded) from DIR/result.json and\n"
                   "the PNG figures of a finished `rockfuzz run`, without evaluating anything.\n"
                   "Exit status: 0 on success, 1 on an error, 2 on a usage error.\n");
            return 0;
        }
        if (argv[a][0] == '-' || dir) {
            fprintf(stderr, "rockfuzz report: unexpected argument '%s' (see `rockfuzz report --help`)\n", argv[a]);
            return 2;
        }
        dir = argv[a];
    }
    if (!dir) {
        fprintf(stderr, "rockfuzz report: missing the run directory (see `rockfuzz report --help`)\n");
        return 2;
    }
    rf_error err;
    memset(&err, 0, sizeof err);
    if (rf_report_write_html(dir, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz report: %s\n", err.msg);
        return 1;
    }
    printf("%s/report.html\n", dir);
    return 0;
}
