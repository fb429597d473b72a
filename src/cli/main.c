/* main.c - the rockfuzz program: dispatches to one file per subcommand. */
#include "cli/cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void usage(FILE *f)
{
    fprintf(f,
        "rockfuzz %s - epistemic uncertainty analysis of rockfall impacts\n"
        "(fuzzy numbers propagated by the Transformation Method)\n"
        "\n"
        "Usage: rockfuzz COMMAND [OPTIONS]\n"
        "\n"
        "Commands:\n"
        "  run STUDY.yaml --out DIR   run a fuzzy study; see `rockfuzz run --help`\n"
        "  impact [OPTIONS]           simulate one boulder impact; see `rockfuzz impact --help`\n"
        "  trajectory FILE.yaml       rockfall trajectories on a slope profile; see\n"
        "                             `rockfuzz trajectory --help`\n"
        "  status DIR                 progress of a running or stopped study run in DIR\n"
        "  report DIR                 write DIR/report.html again from DIR/result.json\n"
        "  material [OPTIONS]         drive one material point along a strain path; see\n"
        "                             `rockfuzz material --help`\n"
        "\n"
        "Options:\n"
        "  -h, --help                 show this help\n"
        "  --version                  print the version\n"
        "\n"
        "Example:\n"
        "  rockfuzz run examples/product.yaml --out out/product\n"
        "  (study file format, outputs and errors: `rockfuzz run --help`, docs/user-guide.md)\n"
        "\n"
        "Units are SI (m, kg, s, Pa) unless an option says otherwise.\n",
        ROCKFUZZ_VERSION);
}

/* `rockfuzz impact` runs one FE impact on all cores.  Its threads meet
 * several times per time step; with the OpenMP runtime's default waiting
 * (spinning), a thread that the OS has descheduled on a busy machine costs
 * its partner whole time slices: measured on a loaded 2-core machine, a 3D
 * impact took 90-129 s on 2 threads instead of 13 s on 1 (docs/fem-speed.md);
 * with passive waiting 4.5-11 s.  The runtime reads OMP_WAIT_POLICY when it
 * is loaded, before main, so when the user has not chosen a policy the
 * program restarts itself once with OMP_WAIT_POLICY=passive (Linux; the
 * results do not depend on it). */
static void passive_openmp_waits(char **argv)
{
#if defined(__linux__) && defined(_OPENMP)
    if (getenv("OMP_WAIT_POLICY"))
        return;
    if (setenv("OMP_WAIT_POLICY", "passive", 1) == 0)
        execv("/proc/self/exe", argv); /* returns only on failure: go on with the default policy */
#else
    (void)argv;
#endif
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "-h") || !strcmp(cmd, "--help") || !strcmp(cmd, "help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(cmd, "--version")) {
        printf("rockfuzz %s\n", ROCKFUZZ_VERSION);
        return 0;
    }
    if (!strcmp(cmd, "run"))
        return rf_cli_run(argc - 1, argv + 1);
    if (!strcmp(cmd, "impact")) {
        passive_openmp_waits(argv);
        return rf_cli_impact(argc - 1, argv + 1);
    }
    if (!strcmp(cmd, "trajectory"))
        return rf_cli_trajectory(argc - 1, argv + 1);
    if (!strcmp(cmd, "status"))
        return rf_cli_status(argc - 1, argv + 1);
    if (!strcmp(cmd, "report"))
        return rf_cli_report(argc - 1, argv + 1);
    if (!strcmp(cmd, "material"))
        return rf_cli_material(argc - 1, argv + 1);
    fprintf(stderr, "rockfuzz: unknown command '%s' (try `rockfuzz --help`)\n", cmd);
    return 2;
}
