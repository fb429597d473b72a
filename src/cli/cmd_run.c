/* cmd_run.c - `rockfuzz run` (placeholder until the study module lands). */
#include "cli/cli.h"
#include <stdio.h>
int rf_cli_run(int argc, char **argv) { (void)argc; (void)argv; fprintf(stderr, "rockfuzz run: not built yet\n"); return 1; }
