/* terrain_fixture.h - the made-up terrain of the terrain Monte Carlo tests, in
 * a temporary folder: a DEM and a class raster as ESRI ASCII grids (cell
 * centres from (0, 0), north row first), and a trajectory file written there
 * and loaded.  Include after cmocka.h. */
#ifndef ROCKFUZZ_TESTS_TERRAIN_FIXTURE_H
#define ROCKFUZZ_TESTS_TERRAIN_FIXTURE_H

#include <stdio.h>
#include <unistd.h>

#include "rockfuzz/trajectory.h"

typedef struct {
    int nx, ny;
    double cell;                          /* [m] */
    double (*ground)(double x, double y); /* height [m] */
    double rock_above;                    /* class 1 (rock) where y > rock_above [m], else 2 (talus) */
} terrain_fixture;

/* The DEM (classes 0) or the class raster (classes 1) at path. */
static inline void fixture_write_asc(const terrain_fixture *t, const char *path, int classes)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "ncols %d\nnrows %d\nxllcenter 0\nyllcenter 0\ncellsize %g\nNODATA_value -9999\n", t->nx, t->ny,
            t->cell);
    for (int j = t->ny - 1; j >= 0; j--) { /* north first */
        for (int i = 0; i < t->nx; i++) {
            if (classes)
                fprintf(f, "%s%d", i ? " " : "", j * t->cell > t->rock_above ? 1 : 2);
            else
                fprintf(f, "%s%.6f", i ? " " : "", t->ground(i * t->cell, j * t->cell));
        }
        fputc('\n', f);
    }
    assert_int_equal(fclose(f), 0);
}

/* dir (a mkdtemp template) created, with dem.asc and classes.asc in it; 0 or -1. */
static inline int fixture_setup(char *dir, const terrain_fixture *t)
{
    if (!mkdtemp(dir))
        return -1;
    char p[256];
    snprintf(p, sizeof p, "%s/dem.asc", dir), fixture_write_asc(t, p, 0);
    snprintf(p, sizeof p, "%s/classes.asc", dir), fixture_write_asc(t, p, 1);
    return 0;
}

/* yaml written to dir/name and loaded into s (a failure fails the test). */
static inline void fixture_load(const char *dir, const char *name, const char *yaml, rf_traj_spec *s)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(yaml, f);
    assert_int_equal(fclose(f), 0);
    rf_error err;
    if (rf_traj_load(path, s, &err) != RF_OK)
        fail_msg("%s", err.msg);
}

/* The folder and its three files (name: the trajectory file's) removed. */
static inline void fixture_teardown(const char *dir, const char *name)
{
    char p[256];
    const char *names[3] = {"dem.asc", "classes.asc", name};
    for (int k = 0; k < 3; k++)
        snprintf(p, sizeof p, "%s/%s", dir, names[k]), unlink(p);
    rmdir(dir);
}

#endif
