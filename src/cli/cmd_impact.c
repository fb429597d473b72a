/* cmd_impact.c - `rockfuzz impact` (placeholder until the impact module lands). */
#include "cli/cli.h"
#include <stdio.h>
int rf_cli_impact(int argc, char **argv) { (void)argc; (void)argv; fprintf(stderr, "rockfuzz impact: not built yet\n"); return 1; }
