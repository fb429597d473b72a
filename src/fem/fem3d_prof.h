/* fem3d_prof.h - per-phase timers of the 3D time loop (docs/fem-speed.md,
 * "Threads"): wall and thread-CPU seconds per phase and per thread, printed
 * to stderr at the end of each run.  Compiled in only with
 * -DRF_FEM3D_PROFILE (e.g. cmake -DCMAKE_C_FLAGS=-DRF_FEM3D_PROFILE); without
 * it every macro is empty and costs nothing.  A diagnostic: its counters are
 * process-global, so profile one run at a time.  Internal header. */
#ifndef ROCKFUZZ_FEM3D_PROF_H
#define ROCKFUZZ_FEM3D_PROF_H

/* Phases of one step, in the order they run. */
enum { F3P_FRAME, F3P_FORK, F3P_UB, F3P_KERNEL, F3P_KWAIT, F3P_GATHER, F3P_JOIN, F3P_TORQUE, F3P_COMMIT,
       F3P_DASH, F3P_LOCATE, F3P_UPDATE, F3P_PREDICT, F3P_SOLVE, F3P_ACCOUNT, F3P_ENERGY, F3P_RUN, F3P_SETUP, F3P_N };

#ifdef RF_FEM3D_PROFILE
typedef struct {
    double wall, cpu;
} f3p_mark;
f3p_mark f3p_now(void);
/* Adds the time since *m to phase p of the calling thread and restarts *m. */
void f3p_lap(int p, f3p_mark *m);
void f3p_report(long steps, long elements, long nodes, long boulder_nodes);
#define F3P_MARK(m) f3p_mark m = f3p_now()
#define F3P_LAP(p, m) f3p_lap(p, &m)
#define F3P_SET(dst, src) ((dst) = (src))
#define F3P_REPORT(steps, elements, nodes, bnodes) f3p_report(steps, elements, nodes, bnodes)
#else
#define F3P_MARK(m) ((void)0)
#define F3P_LAP(p, m) ((void)0)
#define F3P_SET(dst, src) ((void)0)
#define F3P_REPORT(steps, elements, nodes, bnodes) ((void)0)
#endif

#endif
