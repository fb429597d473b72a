/* test_faults.c - fault injection as SQLite does it: the n-th allocation
 * fails, or the n-th write fails, for every n up to the number the operation
 * makes (a sample of them when there are many; ROCKFUZZ_FAULTS_ALL=1 runs
 * every n).  Each operation must then fail cleanly (a status and a message,
 * no crash) or succeed through its own fallback; in the ASan/UBSan build LSan
 * checks at exit that no failure path leaks; and nothing is half-written (the
 * store passes SQLite's integrity check and every row is whole; result.json,
 * when present, is complete).
 *
 * How the faults get in (see CMakeLists.txt and docs/user-guide.md):
 *   - rockfuzz's own allocations: this executable is linked with
 *     -Wl,--wrap=malloc,calloc,realloc,strdup, so every call from the static
 *     library goes through the __wrap_* counters below;
 *   - SQLite's allocations: SQLITE_CONFIG_MALLOC with counting methods;
 *   - SQLite's writes: a VFS shim registered as the default VFS whose xWrite
 *     fails with SQLITE_IOERR_WRITE on the n-th call;
 *   - stdio files (reports): fclose of the n-th file reports ENOSPC, as a
 *     full disk does when the buffer is flushed.
 *   - file writes of the JSON writers: the file size limit (RLIMIT_FSIZE)
 *     set to n bytes, so that the write crossing it fails with EFBIG;
 * Operations: the TM (formula model), the result store, one FE impact (as a
 * study's model), a whole study run (rf_study_run) into a folder, a
 * trajectory run with its CSV writers (a failed close must fail the run),
 * and a profile run's and a terrain run's result.json
 * (rf_traj_write_json_file: never left truncated, a previous one kept). */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <sqlite3.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <signal.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "rockfuzz/analysis.h"
#include "rockfuzz/store.h"
#include "rockfuzz/study.h"
#include "rockfuzz/study_run.h"
#include "rockfuzz/terrain.h"
#include "rockfuzz/tm.h"
#include "rockfuzz/trajectory.h"

/* ---- the fault counters ---------------------------------------------------
 * Global mutable state, on purpose: the allocator and the VFS are process-wide
 * and have no user pointer.  Only this test executable has it. */
static atomic_long alloc_countdown; /* > 0: the allocation that brings it to 0 fails */
static atomic_long allocs;          /* allocations counted since reset */
static atomic_long write_countdown, writes;
static atomic_long close_countdown, closes;

static int fail_now(atomic_long *countdown, atomic_long *count)
{
    atomic_fetch_add(count, 1);
    return atomic_load(countdown) > 0 && atomic_fetch_sub(countdown, 1) == 1;
}

void *__real_malloc(size_t n);
void *__real_calloc(size_t k, size_t n);
void *__real_realloc(void *p, size_t n);
char *__real_strdup(const char *s);
int __real_fclose(FILE *f);

void *__wrap_malloc(size_t n)
{
    if (fail_now(&alloc_countdown, &allocs)) {
        errno = ENOMEM;
        return NULL;
    }
    return __real_malloc(n);
}

void *__wrap_calloc(size_t k, size_t n)
{
    if (fail_now(&alloc_countdown, &allocs)) {
        errno = ENOMEM;
        return NULL;
    }
    return __real_calloc(k, n);
}

void *__wrap_realloc(void *p, size_t n)
{
    if (fail_now(&alloc_countdown, &allocs)) {
        errno = ENOMEM;
        return NULL;
    }
    return __real_realloc(p, n);
}

char *__wrap_strdup(const char *s)
{
    if (fail_now(&alloc_countdown, &allocs)) {
        errno = ENOMEM;
        return NULL;
    }
    return __real_strdup(s);
}

int __wrap_fclose(FILE *f)
{
    int rc = __real_fclose(f);
    if (fail_now(&close_countdown, &closes)) {
        errno = ENOSPC;
        return EOF;
    }
    return rc;
}

/* SQLite's allocator, counted with ours. */
static sqlite3_mem_methods sqlite_mem;

static void *sq_malloc(int n)
{
    return fail_now(&alloc_countdown, &allocs) ? NULL : sqlite_mem.xMalloc(n);
}

static void *sq_realloc(void *p, int n)
{
    return fail_now(&alloc_countdown, &allocs) ? NULL : sqlite_mem.xRealloc(p, n);
}

/* A VFS shim: the default VFS with a failing xWrite. */
typedef struct {
    sqlite3_file base;
    sqlite3_file *real; /* follows this struct in the same allocation */
} shim_file;

static sqlite3_vfs *real_vfs;
static sqlite3_vfs shim_vfs;
static sqlite3_io_methods shim_io;

#define REAL(f) (((shim_file *)(f))->real)
static int s_close(sqlite3_file *f)
{
    int rc = REAL(f)->pMethods ? REAL(f)->pMethods->xClose(REAL(f)) : SQLITE_OK;
    return rc;
}
static int s_read(sqlite3_file *f, void *b, int n, sqlite3_int64 o) { return REAL(f)->pMethods->xRead(REAL(f), b, n, o); }
static int s_write(sqlite3_file *f, const void *b, int n, sqlite3_int64 o)
{
    if (fail_now(&write_countdown, &writes))
        return SQLITE_IOERR_WRITE;
    return REAL(f)->pMethods->xWrite(REAL(f), b, n, o);
}
static int s_truncate(sqlite3_file *f, sqlite3_int64 n) { return REAL(f)->pMethods->xTruncate(REAL(f), n); }
static int s_sync(sqlite3_file *f, int fl) { return REAL(f)->pMethods->xSync(REAL(f), fl); }
static int s_size(sqlite3_file *f, sqlite3_int64 *n) { return REAL(f)->pMethods->xFileSize(REAL(f), n); }
static int s_lock(sqlite3_file *f, int l) { return REAL(f)->pMethods->xLock(REAL(f), l); }
static int s_unlock(sqlite3_file *f, int l) { return REAL(f)->pMethods->xUnlock(REAL(f), l); }
static int s_check(sqlite3_file *f, int *r) { return REAL(f)->pMethods->xCheckReservedLock(REAL(f), r); }
static int s_fcntl(sqlite3_file *f, int op, void *a) { return REAL(f)->pMethods->xFileControl(REAL(f), op, a); }
static int s_sector(sqlite3_file *f) { return REAL(f)->pMethods->xSectorSize(REAL(f)); }
static int s_dev(sqlite3_file *f) { return REAL(f)->pMethods->xDeviceCharacteristics(REAL(f)); }
static int s_shm_map(sqlite3_file *f, int pg, int sz, int ext, void volatile **pp)
{
    return REAL(f)->pMethods->xShmMap(REAL(f), pg, sz, ext, pp);
}
static int s_shm_lock(sqlite3_file *f, int off, int n, int fl) { return REAL(f)->pMethods->xShmLock(REAL(f), off, n, fl); }
static void s_shm_barrier(sqlite3_file *f) { REAL(f)->pMethods->xShmBarrier(REAL(f)); }
static int s_shm_unmap(sqlite3_file *f, int del) { return REAL(f)->pMethods->xShmUnmap(REAL(f), del); }

static int s_open(sqlite3_vfs *vfs, const char *name, sqlite3_file *f, int flags, int *out_flags)
{
    (void)vfs;
    shim_file *sf = (shim_file *)f;
    sf->real = (sqlite3_file *)(sf + 1);
    memset(sf->real, 0, (size_t)real_vfs->szOsFile);
    int rc = real_vfs->xOpen(real_vfs, name, sf->real, flags, out_flags);
    sf->base.pMethods = rc == SQLITE_OK && sf->real->pMethods ? &shim_io : NULL;
    return rc;
}
static int s_delete(sqlite3_vfs *v, const char *n, int sync) { (void)v; return real_vfs->xDelete(real_vfs, n, sync); }
static int s_access(sqlite3_vfs *v, const char *n, int fl, int *r) { (void)v; return real_vfs->xAccess(real_vfs, n, fl, r); }
static int s_full(sqlite3_vfs *v, const char *n, int k, char *o) { (void)v; return real_vfs->xFullPathname(real_vfs, n, k, o); }
static int s_rand(sqlite3_vfs *v, int n, char *o) { (void)v; return real_vfs->xRandomness(real_vfs, n, o); }
static int s_sleep(sqlite3_vfs *v, int us) { (void)v; return real_vfs->xSleep(real_vfs, us); }
static int s_time(sqlite3_vfs *v, double *t) { (void)v; return real_vfs->xCurrentTime(real_vfs, t); }
static int s_lasterr(sqlite3_vfs *v, int n, char *b) { (void)v; return real_vfs->xGetLastError(real_vfs, n, b); }
static int s_time64(sqlite3_vfs *v, sqlite3_int64 *t) { (void)v; return real_vfs->xCurrentTimeInt64(real_vfs, t); }

static void install_faults(void)
{
    sqlite3_config(SQLITE_CONFIG_GETMALLOC, &sqlite_mem);
    sqlite3_mem_methods m = sqlite_mem;
    m.xMalloc = sq_malloc;
    m.xRealloc = sq_realloc;
    assert_int_equal(sqlite3_config(SQLITE_CONFIG_MALLOC, &m), SQLITE_OK);
    assert_int_equal(sqlite3_initialize(), SQLITE_OK);
    real_vfs = sqlite3_vfs_find(NULL);
    assert_non_null(real_vfs);
    shim_io = (sqlite3_io_methods){2, s_close, s_read, s_write, s_truncate, s_sync, s_size, s_lock, s_unlock,
                                   s_check, s_fcntl, s_sector, s_dev, s_shm_map, s_shm_lock, s_shm_barrier,
                                   s_shm_unmap, NULL, NULL};
    shim_vfs = *real_vfs;
    shim_vfs.iVersion = 2;
    shim_vfs.szOsFile = (int)sizeof(shim_file) + real_vfs->szOsFile;
    shim_vfs.zName = "rockfuzz-faults";
    shim_vfs.pNext = NULL;
    shim_vfs.xOpen = s_open;
    shim_vfs.xDelete = s_delete;
    shim_vfs.xAccess = s_access;
    shim_vfs.xFullPathname = s_full;
    shim_vfs.xRandomness = s_rand;
    shim_vfs.xSleep = s_sleep;
    shim_vfs.xCurrentTime = s_time;
    shim_vfs.xGetLastError = s_lasterr;
    shim_vfs.xCurrentTimeInt64 = s_time64;
    shim_vfs.xDlOpen = NULL;
    shim_vfs.xDlError = NULL;
    shim_vfs.xDlSym = NULL;
    shim_vfs.xDlClose = NULL;
    assert_int_equal(sqlite3_vfs_register(&shim_vfs, 1), SQLITE_OK);
}

/* ---- the driver ------------------------------------------------------- */

typedef enum { FAULT_ALLOC, FAULT_WRITE, FAULT_CLOSE } fault_kind;

static atomic_long *countdown_of(fault_kind k)
{
    return k == FAULT_ALLOC ? &alloc_countdown : k == FAULT_WRITE ? &write_countdown : &close_countdown;
}

static atomic_long *count_of(fault_kind k)
{
    return k == FAULT_ALLOC ? &allocs : k == FAULT_WRITE ? &writes : &closes;
}

static const char *kind_name(fault_kind k)
{
    return k == FAULT_ALLOC ? "allocation" : k == FAULT_WRITE ? "SQLite write" : "fclose";
}

/* One operation: returns its status; err must carry a message on failure.
 * check() afterwards verifies that nothing is half-written. */
typedef rf_status (*op_fn)(void *user, rf_error *err);
typedef void (*check_fn)(void *user, rf_status st);

/* Set: a fault that hit must make the operation fail (no fallback exists, e.g. for a file write). */
static int strict;

/* Run op once without faults to count, then with the n-th fault for n = 1..count. */
static void inject(const char *what, fault_kind kind, op_fn op, check_fn check, void *user)
{
    rf_error err;
    atomic_store(countdown_of(kind), 0);
    atomic_store(count_of(kind), 0);
    memset(&err, 0, sizeof err);
    rf_status st = op(user, &err);
    if (st != RF_OK)
        fail_msg("%s: fails without faults: %s", what, err.msg);
    if (check)
        check(user, st);
    long total = atomic_load(count_of(kind));
    const char *all = getenv("ROCKFUZZ_FAULTS_ALL");
    long step = all && all[0] == '1' ? 1 : total / 100 + 1;
    long failed = 0, survived = 0;
    for (long n = 1; n <= total; n += step) {
        atomic_store(count_of(kind), 0);
        atomic_store(countdown_of(kind), n);
        memset(&err, 0, sizeof err);
        st = op(user, &err);
        int hit = atomic_load(countdown_of(kind)) <= 0;
        atomic_store(countdown_of(kind), 0);
        if (st != RF_OK) {
            failed++;
            if (!err.msg[0])
                fail_msg("%s: %s %ld of %ld: status %s without a message", what, kind_name(kind), n, total,
                         rf_status_name(st));
        } else {
            survived += hit; /* handled by a fallback (e.g. no thread: evaluate on the caller's) */
            if (hit && strict)
                fail_msg("%s: %s %ld of %ld failed, yet the operation reported success", what, kind_name(kind), n,
                         total);
        }
        if (check)
            check(user, st);
    }
    print_message("%-22s %-12s: %ld counted, %ld injected (step %ld): %ld failed cleanly, %ld recovered\n", what,
                  kind_name(kind), total, (total + step - 1) / step, step, failed, survived);
}

/* ---- the operations ---------------------------------------------------- */

static const char *tm_study =
    "scheme: general\nlevels: 3\nparameters:\n  a: {tfn: [2, 1, 1]}\n  b: {tfn: [3, 1, 2]}\n"
    "model: {formula: {f: \"a*b + b\", g: \"a/b\"}}\noptions: {jobs: 1}\n";

static rf_status op_tm(void *user, rf_error *err)
{
    (void)user;
    rf_study s;
    rf_status st = rf_study_load_buffer("tm.yaml", tm_study, strlen(tm_study), &s, err);
    if (st != RF_OK)
        return st;
    rf_tm_options opt;
    rf_study_tm_options(&s, &opt);
    rf_tm_result res;
    rf_analysis an;
    memset(&res, 0, sizeof res);
    memset(&an, 0, sizeof an);
    st = rf_tm_run(s.inputs, s.n_params, &s.model, &opt, &res, err);
    if (st == RF_OK)
        st = rf_analysis_compute(&res, &an, err);
    rf_analysis_free(&an);
    rf_tm_result_free(&res);
    rf_study_free(&s);
    return st;
}

typedef struct {
    char dir[64];
    char path[128];
    int rows; /* rows a complete operation writes */
} store_case;

static rf_status op_store(void *user, rf_error *err)
{
    store_case *c = user;
    unlink(c->path);
    static const char *const in[2] = {"a", "b"}, *const out[1] = {"f"};
    rf_store_key key = {"faults", "1", 2, 1, in, out};
    rf_store *s = NULL;
    rf_status st = rf_store_open(c->path, &key, 0, &s, err);
    if (st == RF_OK)
        st = rf_store_begin_run(s, (size_t)c->rows, "faults", err);
    for (int k = 0; k < c->rows && st == RF_OK; k++) {
        double x[2] = {k, 0.5 * k}, y = 3.0 * k, got = 0;
        st = rf_store_put_started(s, x, err);
        if (st == RF_OK)
            st = rf_store_put(s, x, 1, &y, NULL, 0.1, err);
        if (st == RF_OK && rf_store_lookup(s, x, &got, err) != 1)
            st = err->msg[0] ? err->code : rf_fail(err, RF_EINTERNAL, "row %d not found after commit", k);
    }
    rf_store_close(s);
    return st;
}

/* Whatever was committed is whole: integrity ok, every finished row has its outputs. */
static void check_store(void *user, rf_status st)
{
    store_case *c = user;
    struct stat sb;
    if (stat(c->path, &sb) != 0 || sb.st_size == 0)
        return; /* failed before the file was written: nothing to check */
    sqlite3 *db = NULL;
    long saved = atomic_load(&alloc_countdown);
    atomic_store(&alloc_countdown, 0);
    assert_int_equal(sqlite3_open_v2(c->path, &db, SQLITE_OPEN_READONLY, NULL), SQLITE_OK);
    sqlite3_stmt *q = NULL;
    assert_int_equal(sqlite3_prepare_v2(db, "PRAGMA quick_check", -1, &q, NULL), SQLITE_OK);
    assert_int_equal(sqlite3_step(q), SQLITE_ROW);
    assert_string_equal((const char *)sqlite3_column_text(q, 0), "ok");
    sqlite3_finalize(q);
    if (sqlite3_prepare_v2(db, "SELECT count(*), coalesce(sum(ok = 1 AND length(y) = 8), 0), "
                               "coalesce(sum(ok = 1), 0) FROM results", -1, &q, NULL) == SQLITE_OK) {
        assert_int_equal(sqlite3_step(q), SQLITE_ROW);
        int rows = sqlite3_column_int(q, 0), whole = sqlite3_column_int(q, 1), ok = sqlite3_column_int(q, 2);
        assert_int_equal(whole, ok);
        if (st == RF_OK)
            assert_int_equal(rows, c->rows);
    }
    sqlite3_finalize(q);
    sqlite3_close(db);
    atomic_store(&alloc_countdown, saved);
}

static const char *fe_study =
    "levels: 1\nparameters:\n  velocity: {tfn: [10, 1, 1]}\n"
    "model:\n  impact: {solver: fem, refinement: 2, domain_factor: 4}\n";

static rf_status op_fe(void *user, rf_error *err)
{
    (void)user;
    rf_study s;
    rf_status st = rf_study_load_buffer("fe.yaml", fe_study, strlen(fe_study), &s, err);
    if (st != RF_OK)
        return st;
    double x = 10, y[16];
    st = s.model.n_outputs <= 16 ? rf_model_eval(&s.model, &x, y, err) : RF_EINTERNAL;
    rf_study_free(&s);
    return st;
}

typedef struct {
    char dir[64];
    char study[128];
    char out[128];
} run_case;

static rf_status op_run(void *user, rf_error *err)
{
    run_case *c = user;
    rf_study_run_options o;
    rf_study_run_options_default(&o);
    o.out_dir = c->out;
    o.plots = 0;
    o.fresh = 1;
    return rf_study_run(c->study, &o, NULL, err);
}

/* result.json, when present, is the complete one (written last, renamed into place). */
static void check_run(void *user, rf_status st)
{
    run_case *c = user;
    char path[256];
    snprintf(path, sizeof path, "%s/result.json.tmp", c->out);
    assert_int_not_equal(access(path, F_OK), 0);
    snprintf(path, sizeof path, "%s/result.json", c->out);
    FILE *f = fopen(path, "rb");
    if (!f) {
        assert_int_not_equal(st, RF_OK);
        return;
    }
    char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    assert_true(n > 2 && buf[0] == '{' && strstr(buf, "\"warnings\"") && strstr(buf + n - 3, "}"));
}

/* A trajectory run and its writers: Monte Carlo with recorded trajectories,
 * statistics, every CSV file into a folder. */
static const char *traj_file =
    "name: f\nprofile:\n  points: [[0, 30], [20, 10], [60, 0], [100, 0]]\n  material: rock\n"
    "materials:\n  rock: {R_n: {uniform: [0.3, 0.4]}, R_t: 0.8, friction_angle: 30, roughness: 2}\n"
    "block: {shape: sphere, radius: 0.5, density: 2600}\nrelease: {x: 1, y: 31, vx: 1, vy: 0}\n"
    "bounce: {law: constant}\ncollectors: [{name: fence, x: 50}]\nsamples: 20\nrecord: 5\nseed: 7\n";

typedef struct {
    char dir[64];
} traj_case;

static rf_status op_traj(void *user, rf_error *err)
{
    traj_case *c = user;
    rf_traj_spec spec;
    rf_traj_ensemble e;
    rf_traj_stats t;
    rf_status st = rf_traj_load_buffer("f.yaml", traj_file, strlen(traj_file), &spec, err);
    if (st != RF_OK)
        return st;
    if ((st = rf_traj_run(&spec, 1, &e, err)) == RF_OK) {
        if ((st = rf_traj_stats_compute_spec(&spec, &e, &t, err)) == RF_OK) {
            st = rf_traj_write_csv(c->dir, &spec, &e, &t, err);
            rf_traj_stats_free(&t);
        }
        rf_traj_ensemble_free(&e);
    }
    rf_traj_spec_free(&spec);
    return st;
}

/* The JSON document of a profile run and of a terrain run (a plane DEM as an
 * ESRI ASCII grid written here) into DIR/result.json by
 * rf_traj_write_json_file: on any failure DIR/result.json.tmp is gone and
 * DIR/result.json is byte for byte what it was before; on success it is the
 * whole document. */
static const char *terrain_fmt =
    "name: t\nterrain: {dem: %s/dem.asc, material: rock}\n"
    "materials: {rock: {R_n: {uniform: [0.3, 0.4]}, R_t: 0.8, friction_angle: 30}}\n"
    "block: {shape: sphere, radius: 0.5, density: 2600}\n"
    "release: {points: [[50, 80], [40, 85]], height: 1.0, velocity: [0, 0, 0]}\n"
    "bounce: {law: constant}\nbarriers: [{name: fence, line: [[10, 40], [90, 40]], height: 4, capacity: 2.0e6}]\n"
    "samples: 10\nrecord: 3\nseed: 3\n";

typedef struct {
    char dir[64];
    char path[128];  /* DIR/result.json */
    char yaml[1024]; /* the trajectory or terrain file */
    char before[1 << 17];
    long n_before;   /* bytes of result.json before the operation, -1: none */
} json_case;

static long slurp(const char *path, char *buf, size_t size)
{
    long saved = atomic_load(&alloc_countdown);
    atomic_store(&alloc_countdown, 0);
    FILE *f = fopen(path, "rb");
    long n = -1;
    if (f) {
        n = (long)fread(buf, 1, size - 1, f);
        buf[n] = '\0';
        __real_fclose(f);
    }
    atomic_store(&alloc_countdown, saved);
    return n;
}

/* Load, run and write the JSON file (ensemble and statistics freed). */
static rf_status json_run(json_case *c, rf_traj_spec *spec, rf_traj_ensemble *e, rf_traj_stats *t, rf_error *err)
{
    rf_status st = rf_traj_load_buffer("j.yaml", c->yaml, strlen(c->yaml), spec, err);
    if (st != RF_OK)
        return st;
    st = spec->terrain ? rf_terrain_run(spec, 1, NULL, NULL, e, err) : rf_traj_run(spec, 1, e, err);
    if (st == RF_OK) {
        if ((st = rf_traj_stats_compute_spec(spec, e, t, err)) != RF_OK)
            rf_traj_ensemble_free(e);
    }
    if (st != RF_OK)
        rf_traj_spec_free(spec);
    return st;
}

static rf_status op_json(void *user, rf_error *err)
{
    json_case *c = user;
    c->n_before = slurp(c->path, c->before, sizeof c->before);
    rf_traj_spec spec;
    rf_traj_ensemble e;
    rf_traj_stats t;
    rf_status st = json_run(c, &spec, &e, &t, err);
    if (st != RF_OK)
        return st;
    st = rf_traj_write_json_file(c->path, &spec, &e, &t, 100, err);
    rf_traj_stats_free(&t);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&spec);
    return st;
}

static void check_json(void *user, rf_status st)
{
    json_case *c = user;
    char tmp[160], now[1 << 17];
    snprintf(tmp, sizeof tmp, "%s.tmp", c->path);
    assert_int_not_equal(access(tmp, F_OK), 0);
    long n = slurp(c->path, now, sizeof now);
    if (st != RF_OK) {
        assert_int_equal(n, c->n_before);
        assert_true(n < 0 || !memcmp(now, c->before, (size_t)n));
        return;
    }
    assert_true(n > 100 && n < (long)sizeof now - 1);
    assert_true(now[0] == '{' && !strcmp(now + n - 2, "}\n") && strstr(now, "\"wall_seconds\": "));
    assert_non_null(strstr(now, "\"fence\""));
}

/* Failed writes: the file size limit (RLIMIT_FSIZE, SIGXFSZ ignored) set to
 * n bytes makes the write that crosses it fail with EFBIG, as a full disk
 * does, at every n from 0 to the document's size (a sample of them). */
static void write_limits(json_case *c, const char *what)
{
    rf_traj_spec spec;
    rf_traj_ensemble e;
    rf_traj_stats t;
    rf_error err;
    if (json_run(c, &spec, &e, &t, &err) != RF_OK)
        fail_msg("%s: %s", what, err.msg);
    assert_int_equal(rf_traj_write_json_file(c->path, &spec, &e, &t, 100, &err), RF_OK);
    check_json(c, RF_OK);
    long size = slurp(c->path, c->before, sizeof c->before), failed = 0;
    c->n_before = size;
    struct rlimit saved, lim;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &saved), 0);
    void (*old)(int) = signal(SIGXFSZ, SIG_IGN);
    for (long n = 0; n < size; n += size / 60 + 1) {
        lim = saved, lim.rlim_cur = (rlim_t)n;
        assert_int_equal(setrlimit(RLIMIT_FSIZE, &lim), 0);
        memset(&err, 0, sizeof err);
        rf_status st = rf_traj_write_json_file(c->path, &spec, &e, &t, 100, &err);
        assert_int_equal(setrlimit(RLIMIT_FSIZE, &saved), 0);
        if (st == RF_OK)
            fail_msg("%s: a file size limit of %ld < %ld bytes, yet the write reported success", what, n, size);
        if (!strstr(err.msg, c->path) || !strstr(err.msg, "File too large"))
            fail_msg("%s: limit %ld: '%s'", what, n, err.msg);
        check_json(c, st);
        failed++;
    }
    signal(SIGXFSZ, old);
    print_message("%-22s %-12s: %ld bytes, %ld limits: %ld failed cleanly\n", what, "write", size, failed, failed);
    rf_traj_stats_free(&t);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&spec);
}

static void json_faults(json_case *c, const char *what)
{
    write_limits(c, what);
    inject(what, FAULT_ALLOC, op_json, check_json, c);
    strict = 1; /* a failed close is a failed write */
    inject(what, FAULT_CLOSE, op_json, check_json, c);
    strict = 0;
    unlink(c->path); /* and with no file before */
    inject(what, FAULT_CLOSE, op_json, check_json, c);
}

/* ---- the tests ---------------------------------------------------------- */

/* A fresh folder, in memory (/dev/shm) when there is one: the loops fsync a lot. */
static void temp_dir(char *buf, size_t size)
{
    struct stat sb;
    snprintf(buf, size, "%s/rockfuzz-faults-XXXXXX", stat("/dev/shm", &sb) == 0 && access("/dev/shm", W_OK) == 0
                                                            ? "/dev/shm" : "/tmp");
}

static void test_tm(void **state)
{
    (void)state;
    inject("TM (formula)", FAULT_ALLOC, op_tm, NULL, NULL);
}

static void test_store(void **state)
{
    (void)state;
    store_case c = {"", "", 12};
    temp_dir(c.dir, sizeof c.dir);
    assert_non_null(mkdtemp(c.dir));
    snprintf(c.path, sizeof c.path, "%s/store.sqlite", c.dir);
    inject("store", FAULT_ALLOC, op_store, check_store, &c);
    inject("store", FAULT_WRITE, op_store, check_store, &c);
    char cmd[160];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", c.dir);
    assert_int_equal(system(cmd), 0);
}

static void test_fe_impact(void **state)
{
    (void)state;
    inject("FE impact (one eval)", FAULT_ALLOC, op_fe, NULL, NULL);
}

static void test_study_run(void **state)
{
    (void)state;
    run_case c = {"", "", ""};
    temp_dir(c.dir, sizeof c.dir);
    assert_non_null(mkdtemp(c.dir));
    snprintf(c.study, sizeof c.study, "%s/s.yaml", c.dir);
    snprintf(c.out, sizeof c.out, "%s/out", c.dir);
    FILE *f = fopen(c.study, "w");
    assert_non_null(f);
    fputs(tm_study, f);
    assert_int_equal(fclose(f), 0);
    inject("study run", FAULT_ALLOC, op_run, check_run, &c);
    inject("study run", FAULT_WRITE, op_run, check_run, &c);
    inject("study run", FAULT_CLOSE, op_run, check_run, &c);
    char cmd[160];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", c.dir);
    assert_int_equal(system(cmd), 0);
}

static void test_traj_run(void **state)
{
    (void)state;
    traj_case c = {""};
    temp_dir(c.dir, sizeof c.dir);
    assert_non_null(mkdtemp(c.dir));
    inject("trajectory run", FAULT_ALLOC, op_traj, NULL, &c);
    strict = 1; /* a file whose close failed is a failed run, never a silent success */
    inject("trajectory CSV files", FAULT_CLOSE, op_traj, NULL, &c);
    strict = 0;
    char cmd[160];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", c.dir);
    assert_int_equal(system(cmd), 0);
}

static void test_traj_json(void **state)
{
    (void)state;
    json_case *c = calloc(1, sizeof *c);
    assert_non_null(c);
    temp_dir(c->dir, sizeof c->dir);
    assert_non_null(mkdtemp(c->dir));
    snprintf(c->path, sizeof c->path, "%s/result.json", c->dir);
    snprintf(c->yaml, sizeof c->yaml, "%s", traj_file);
    json_faults(c, "trajectory JSON");
    /* a terrain run: a plane falling to the south, 41 x 41 nodes 2.5 m apart */
    char dem[160];
    snprintf(dem, sizeof dem, "%s/dem.asc", c->dir);
    FILE *f = fopen(dem, "w");
    assert_non_null(f);
    fprintf(f, "ncols 41\nnrows 41\nxllcorner -1.25\nyllcorner -1.25\ncellsize 2.5\n");
    for (int r = 0; r < 41; r++) {
        for (int k = 0; k < 41; k++)
            fprintf(f, "%g ", 0.6 * 2.5 * (40 - r));
        fputc('\n', f);
    }
    assert_int_equal(__real_fclose(f), 0);
    snprintf(c->yaml, sizeof c->yaml, terrain_fmt, c->dir);
    unlink(c->path);
    json_faults(c, "terrain JSON");
    char cmd[160];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", c->dir);
    assert_int_equal(system(cmd), 0);
    free(c);
}

int main(void)
{
    install_faults();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tm),
        cmocka_unit_test(test_store),
        cmocka_unit_test(test_fe_impact),
        cmocka_unit_test(test_study_run),
        cmocka_unit_test(test_traj_run),
        cmocka_unit_test(test_traj_json),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
