/* main.c - the rockfuzz program: dispatches to one file per subcommand. */
#include "cli/cli.h"

#include <errno.h>
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
        "  report DIR                 write DIR/report.html again, of a study run or of a\n"
        "                             `rockfuzz trajectory --out DIR` run\n"
        "  material [OPTIONS]         drive one material point along a strain path; see\n"
        "                             `rockfuzz material --help`\n"
        "  presets [NAME]             named materials for trajectory files, with their\n"
        "                             fuzzy ranges; see `rockfuzz presets --help`\n"
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
 * several times per time step (8 at a/h = 3: ~200 us per step on 2 threads).
 * How a waiting thread waits decides whether the second core pays:
 * - the runtime's default (libgomp: spin ~300 000 times, then sleep): a
 *   thread that the OS has descheduled on a busy machine costs its partner
 *   whole time slices (a loaded 2-core machine: 90-129 s on 2 threads
 *   instead of 13 s on 1, docs/fem-speed.md);
 * - passive (sleep at once): safe under load, but every meeting is a futex
 *   wake-up: on the idle machine the default 3D impact (a/h = 3) took 0.97 s
 *   on 2 threads against 0.66 s on 1, and a/h = 6 reached only 1.6x;
 * - a short spin (GOMP_SPINCOUNT = 10 000, some 10 us) then sleep: idle,
 *   1.61x at a/h = 3 and 1.86x at a/h = 6; under load about as bad as
 *   passive (docs/fem-speed.md, "Threads").
 * The runtime reads these variables when it is loaded, before main, so when
 * the user has chosen neither, the program restarts itself once with the short
 * spin (Linux; the results do not depend on it). */
static void short_openmp_waits(char **argv)
{
#if defined(__linux__) && defined(_OPENMP)
    if (getenv("OMP_WAIT_POLICY") || getenv("GOMP_SPINCOUNT"))
        return;
    if (setenv("GOMP_SPINCOUNT", "10000", 1) == 0)
        execv("/proc/self/exe", argv); /* returns only on failure: go on with the default policy */
#else
    (void)argv;
#endif
}

/* The one check of standard output, for every command: a write that failed
 * (a full disk, /dev/full, a closed pipe's EIO) is an error, whatever the
 * command returned.  Both the sticky error flag (a write that failed while
 * the buffer was flushed along the way) and the final flush are checked. */
static int stdout_checked(int rc)
{
    errno = 0;
    int failed = fflush(stdout) != 0;
    int e = errno;
    failed |= ferror(stdout) != 0;
    if (!failed)
        return rc;
    fprintf(stderr, "rockfuzz: writing to standard output failed: %s\n",
            e ? strerror(e) : "an earlier write failed");
    return rc ? rc : 1;
}

static int dispatch(int argc, char **argv)
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
        short_openmp_waits(argv);
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
    if (!strcmp(cmd, "presets"))
        return rf_cli_presets(argc - 1, argv + 1);
    fprintf(stderr, "rockfuzz: unknown command '%s' (try `rockfuzz --help`)\n", cmd);
    return 2;
}

int main(int argc, char **argv)
{
    return stdout_checked(dispatch(argc, argv));
}
