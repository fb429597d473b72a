/* fem_driver.h - the one stage loop of the FE solvers (fem_driver.c).  A run
 * is: prepare (check, automatic settings, Hertz reference), mesh, assemble
 * (elements, masses, kernels, contact, gravity, time step), begin (the run's
 * record), the steps (frame, step, energy, account, stop), extract (outputs
 * and history) and release.  The driver writes that order once, with the
 * time-step halving around it; a geometry (the axisymmetric model in
 * fem_solver.c, the 3D model in fem3d_solver.c) gives its stages as a table of
 * functions over its own run state and keeps only what is geometric. */
#ifndef ROCKFUZZ_FEM_DRIVER_H
#define ROCKFUZZ_FEM_DRIVER_H

#include "fem_core.h"
#include "rockfuzz/fem3d.h"

/* What one attempt runs on and writes to. */
typedef struct {
    rf_fem_workspace *ws;
    const rf_impact_input *in;
    const rf_fem_options *opt;   /* this attempt's options (its tuning's dt_safety halved on a retry) */
    const rf_fem3d_options *o3;  /* the 3D model's settings (NULL: defaults); the axisymmetric one ignores it */
    rf_impact_output *out;
    rf_fem_history *hist;        /* may be NULL */
    rf_fem3d_report *rep;        /* the 3D model's diagnostics, may be NULL */
} fem_attempt;

/* What the driver reads of an assembled run. */
typedef struct {
    double dt;        /* time step [s] */
    double t_hertz;   /* Hertz contact duration [s]: the run's time scale */
    double ke0;       /* initial kinetic energy [J] */
    double gravity;   /* [m/s^2] */
    int columns;      /* history columns of a step's row */
} fem_drive_params;

/* A step's record for the account (fem_run_account). */
typedef struct {
    double Fc, rad, comp, closure, row[13];
    double travel; /* the boulder's displacement along the slope [m] (the roll rule; 0: none) */
} fem_step_row;

/* The stages of one geometry; run is its own run state (zeroed, its pool set, by the caller). */
typedef struct {
    const char *who; /* "fem", "fem3d": the prefix of its messages */
    rf_status (*prepare)(void *run, const fem_attempt *a, rf_error *err);
    rf_status (*mesh)(void *run, rf_error *err);
    rf_status (*assemble)(void *run, rf_error *err);
    void (*params)(const void *run, fem_drive_params *p);
    /* one step at time t: advance, check the step's stability, fill the row */
    rf_status (*step)(void *run, double t, fem_step_row *r, rf_error *err);
    /* after the account (may be NULL): the contact was open/closed before and after */
    void (*accounted)(void *run, int was_in_contact, int in_contact);
    rf_status (*frame)(void *run, int k, double t, rf_error *err); /* VTK frame k of the state at t */
    void (*extract)(void *run, fem_run *R, long nsteps, const fem_attempt *a);
    void (*history)(void *run, fem_run *R, rf_fem_history *hist); /* after fem_run_history (may be NULL) */
    long (*release)(void *run); /* frees the run; returns the element that outgrew the step (-1 none) */
} fem_geometry;

/* One attempt: the stages in order over run; *unstable as release says. */
rf_status fem_drive(const fem_geometry *g, void *run, const fem_attempt *a, long *unstable, rf_error *err);

/* The public entry: checks, the options' defaults, the halving retries of
 * attempt (ctx: a fem_attempt whose opt each retry replaces) and the wall time. */
rf_status fem_drive_impact(fem_attempt_fn attempt, fem_attempt *a, const char *who, rf_error *err);

#endif
