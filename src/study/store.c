/* store.c - the SQLite result store (see store.h).
 *
 * Opening never writes to a file before it is known to be a rockfuzz store
 * (or absent/empty): a foreign or corrupt database is reported and left as it
 * is.  Every result is one autocommitted INSERT in WAL mode, so a process
 * killed at any moment leaves every committed result readable and nothing
 * half-written.  A mutex serialises the callers (one writer at a time). */
#include "rockfuzz/store.h"

#include <errno.h>
#include <pthread.h>
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/util.h"

#define STORE_FORMAT "rockfuzz-store"
#define STORE_FORMAT_VERSION "1"

struct rf_store {
    sqlite3 *db;
    char *path;
    size_t n_inputs, n_outputs;
    sqlite3_stmt *lookup;
    sqlite3_stmt *put;
    pthread_mutex_t lock;
};

static double unix_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static rf_status db_fail(rf_error *err, sqlite3 *db, const char *path, const char *what)
{
    int code = db ? sqlite3_extended_errcode(db) : SQLITE_ERROR;
    const char *msg = db ? sqlite3_errmsg(db) : "unknown error";
    const char *hint = "";
    if ((code & 0xff) == SQLITE_FULL)
        hint = " (the disk or the file-size limit is full; results committed so far are kept)";
    else if ((code & 0xff) == SQLITE_IOERR)
        hint = " (I/O error; results committed so far are kept)";
    return rf_fail(err, RF_EIO, "result store %s: %s: %s%s", path, what, msg, hint);
}

static char *join_names(size_t n, const char *const *names)
{
    size_t len = 1;
    for (size_t i = 0; i < n; i++)
        len += strlen(names[i]) + 1;
    char *s = malloc(len), *p = s;
    if (!s)
        return NULL;
    for (size_t i = 0; i < n; i++) {
        size_t l = strlen(names[i]);
        if (i)
            *p++ = ',';
        memcpy(p, names[i], l);
        p += l;
    }
    *p = '\0';
    return s;
}

/* meta value for key into buf ("" if absent); -1 on a database error. */
static int meta_get(sqlite3 *db, const char *key, char *buf, size_t size)
{
    sqlite3_stmt *st = NULL;
    buf[0] = '\0';
    if (sqlite3_prepare_v2(db, "SELECT value FROM meta WHERE key = ?1", -1, &st, NULL) != SQLITE_OK)
        return -1;
    sqlite3_bind_text(st, 1, key, -1, SQLITE_STATIC);
    int rc = sqlite3_step(st);
    if (rc == SQLITE_ROW) {
        const unsigned char *v = sqlite3_column_text(st, 0);
        snprintf(buf, size, "%s", v ? (const char *)v : "");
    }
    sqlite3_finalize(st);
    return rc == SQLITE_ROW || rc == SQLITE_DONE ? 0 : -1;
}

static int meta_set(sqlite3 *db, const char *key, const char *value)
{
    sqlite3_stmt *st = NULL;
    if (sqlite3_prepare_v2(db, "INSERT OR REPLACE INTO meta(key, value) VALUES(?1, ?2)", -1, &st, NULL) !=
        SQLITE_OK)
        return -1;
    sqlite3_bind_text(st, 1, key, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 2, value, -1, SQLITE_STATIC);
    int rc = sqlite3_step(st);
    sqlite3_finalize(st);
    return rc == SQLITE_DONE ? 0 : -1;
}

/* Is db a rockfuzz store?  Reads only. */
static rf_status check_format(sqlite3 *db, const char *path, rf_error *err)
{
    char fmt[64], ver[16];
    sqlite3_stmt *st = NULL;
    int rc = sqlite3_prepare_v2(db, "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name IN "
                                    "('meta', 'results')", -1, &st, NULL);
    if (rc != SQLITE_OK)
        return rf_fail(err, RF_EIO, "%s is not a rockfuzz result store (%s); it was left untouched: move it "
                                    "away or choose another --out directory",
                       path, sqlite3_errmsg(db));
    rc = sqlite3_step(st);
    int tables = rc == SQLITE_ROW ? sqlite3_column_int(st, 0) : -1;
    sqlite3_finalize(st);
    if (rc != SQLITE_ROW)
        return rf_fail(err, RF_EIO, "%s is not a rockfuzz result store (%s); it was left untouched", path,
                       sqlite3_errmsg(db));
    if (tables != 2 || meta_get(db, "format", fmt, sizeof fmt) != 0 || strcmp(fmt, STORE_FORMAT) != 0)
        return rf_fail(err, RF_EIO, "%s is an SQLite database but not a rockfuzz result store; it was left "
                                    "untouched: move it away or choose another --out directory",
                       path);
    if (meta_get(db, "format_version", ver, sizeof ver) != 0 || strcmp(ver, STORE_FORMAT_VERSION) != 0)
        return rf_fail(err, RF_EIO, "%s: rockfuzz store format version '%s', this program reads version %s; it "
                                    "was left untouched",
                       path, ver, STORE_FORMAT_VERSION);
    return RF_OK;
}

/* The first whitespace-separated token where a and b differ, for messages. */
static void first_difference(const char *a, const char *b, char *buf, size_t size)
{
    size_t i = 0, start = 0;
    while (a[i] && a[i] == b[i]) {
        if (a[i] == ' ')
            start = i + 1;
        i++;
    }
    size_t ea = start, eb = start;
    while (a[ea] && a[ea] != ' ')
        ea++;
    while (b[eb] && b[eb] != ' ')
        eb++;
    snprintf(buf, size, "stored '%.*s', now '%.*s'", (int)(ea - start > 200 ? 200 : ea - start), a + start,
             (int)(eb - start > 200 ? 200 : eb - start), b + start);
}

static const char *SCHEMA =
    "CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);"
    "CREATE TABLE results(x BLOB PRIMARY KEY, ok INTEGER NOT NULL, y BLOB, error TEXT, seconds REAL,"
    " finished REAL NOT NULL, x_text TEXT);";

/* Why a database could not be opened: SQLite's message plus the system's
 * (a read-only folder, a directory in the way, ...). */
static rf_status open_fail(rf_error *err, sqlite3 *db, const char *path)
{
    int e = db ? sqlite3_system_errno(db) : ENOMEM;
    struct stat sb;
    if (stat(path, &sb) == 0 && !S_ISREG(sb.st_mode))
        return rf_fail(err, RF_EIO, "result store %s: cannot open: it is not a regular file", path);
    return rf_fail(err, RF_EIO, "result store %s: cannot open: %s%s%s", path,
                   db ? sqlite3_errmsg(db) : "out of memory", e ? ": " : "", e ? strerror(e) : "");
}

/* SQLite's own structural check (PRAGMA quick_check: b-trees, pages, records;
 * O(size)), run before anything is written.  *damaged = 1 when it fails. */
static rf_status integrity_check(sqlite3 *db, const char *path, int *damaged, rf_error *err)
{
    sqlite3_stmt *st = NULL;
    *damaged = 0;
    int rc = sqlite3_prepare_v2(db, "PRAGMA quick_check", -1, &st, NULL);
    char first[512] = "";
    int bad = rc != SQLITE_OK;
    if (bad)
        snprintf(first, sizeof first, "%s", sqlite3_errmsg(db));
    while (!bad && (rc = sqlite3_step(st)) == SQLITE_ROW) {
        const unsigned char *row = sqlite3_column_text(st, 0);
        if (!row || strcmp((const char *)row, "ok") != 0) {
            snprintf(first, sizeof first, "%s", row ? (const char *)row : "?");
            bad = 1;
        }
    }
    if (!bad && rc != SQLITE_DONE) {
        snprintf(first, sizeof first, "%s", sqlite3_errmsg(db));
        bad = 1;
    }
    sqlite3_finalize(st);
    if (!bad)
        return RF_OK;
    *damaged = 1;
    return rf_fail(err, RF_EIO,
                   "%s is damaged (SQLite integrity check: %s); nothing in its folder was changed and its results "
                   "are not used. Rerun with --fresh to move it aside (to %s.damaged) and start over, or choose "
                   "another --out directory; result.json of the last complete run, if any, is still valid",
                   path, first, path);
}

/* --fresh on a damaged store: keep it (and its WAL) as PATH.damaged*, start a new one. */
static rf_status move_aside(const char *path, rf_error *err)
{
    static const char *const sfx[3] = {"", "-wal", "-shm"};
    for (int k = 0; k < 3; k++) {
        char from[4096], to[4096];
        snprintf(from, sizeof from, "%s%s", path, sfx[k]);
        snprintf(to, sizeof to, "%s.damaged%s", path, sfx[k]);
        if (rename(from, to) != 0 && errno != ENOENT)
            return rf_fail(err, RF_EIO, "cannot move the damaged store %s aside to %s: %s", from, to,
                           strerror(errno));
    }
    return RF_OK;
}

/* SQLite's side files of path (-wal, -shm) that do not exist now: on a
 * refusal they are removed again, so the folder is left as it was found. */
static void note_side_files(const char *path, int absent[2])
{
    static const char *const sfx[2] = {"-wal", "-shm"};
    for (int k = 0; k < 2; k++) {
        char f[4096];
        struct stat sb;
        snprintf(f, sizeof f, "%s%s", path, sfx[k]);
        absent[k] = stat(f, &sb) != 0 && errno == ENOENT;
    }
}

static void remove_new_side_files(const char *path, const int absent[2])
{
    static const char *const sfx[2] = {"-wal", "-shm"};
    for (int k = 0; k < 2; k++) {
        char f[4096];
        snprintf(f, sizeof f, "%s%s", path, sfx[k]);
        if (absent[k])
            unlink(f);
    }
}

/* Open an existing file as a store: format, then integrity.  Reads only; no
 * checkpoint on close, so a refused file is left exactly as it was. */
static rf_status open_existing(rf_store *s, const char *path, int *damaged, rf_error *err)
{
    *damaged = 0;
    if (sqlite3_open_v2(path, &s->db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_FULLMUTEX, NULL) != SQLITE_OK)
        return open_fail(err, s->db, path);
    sqlite3_db_config(s->db, SQLITE_DBCONFIG_NO_CKPT_ON_CLOSE, 1, (int *)NULL);
    sqlite3_busy_timeout(s->db, 10000);
    sqlite3_extended_result_codes(s->db, 1);
    int code = 0;
    rf_status st = check_format(s->db, path, err);
    if (st != RF_OK) {
        code = sqlite3_extended_errcode(s->db) & 0xff;
        *damaged = code == SQLITE_CORRUPT; /* NOTADB: not an SQLite file, so not ours */
        if (*damaged)
            integrity_check(s->db, path, damaged, err);
        return st;
    }
    if ((st = integrity_check(s->db, path, damaged, err)) != RF_OK)
        return st;
    sqlite3_db_config(s->db, SQLITE_DBCONFIG_NO_CKPT_ON_CLOSE, 0, (int *)NULL);
    return RF_OK;
}

/* s->db on the file at path: an existing one checked (a damaged one moved
 * aside with fresh), else a new empty database.  *exists: an old store is open. */
static rf_status open_or_create(rf_store *s, const char *path, int fresh, int *exists, rf_error *err)
{
    struct stat sb;
    *exists = stat(path, &sb) == 0 && sb.st_size > 0;
    int damaged = 0, absent[2];
    note_side_files(path, absent);
    if (*exists) {
        rf_status st = open_existing(s, path, &damaged, err);
        if (st == RF_OK)
            return RF_OK;
        sqlite3_close(s->db);
        s->db = NULL;
        remove_new_side_files(path, absent); /* ours, empty: nothing was written */
        if (!(damaged && fresh))
            return st;
        if ((st = move_aside(path, err)) != RF_OK)
            return st;
        *exists = 0;
    }
    if (sqlite3_open_v2(path, &s->db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_FULLMUTEX | SQLITE_OPEN_CREATE, NULL) !=
        SQLITE_OK)
        return open_fail(err, s->db, path);
    sqlite3_busy_timeout(s->db, 10000);
    sqlite3_extended_result_codes(s->db, 1);
    return RF_OK;
}

/* Same model, settings, version and names?  Checked before anything is written. */
static rf_status check_key(rf_store *s, const rf_store_key *key, const char *inputs, const char *outputs, int fresh,
                           rf_error *err)
{
    static const char *const keys[4] = {"identity", "rockfuzz_version", "inputs", "outputs"};
    static const char *const what[4] = {"model or its settings", "rockfuzz version", "input names", "output names"};
    const char *now[4] = {key->identity, key->version, inputs, outputs};
    char *stored = malloc(65536);
    if (!stored)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    rf_status st = RF_OK;
    for (int k = 0; k < 4 && st == RF_OK; k++) {
        if (meta_get(s->db, keys[k], stored, 65536) != 0) {
            st = db_fail(err, s->db, s->path, "cannot read its meta table");
        } else if (strcmp(stored, now[k]) != 0 && !fresh) {
            char diff[512];
            first_difference(stored, now[k], diff, sizeof diff);
            st = rf_fail(err, RF_EINVAL,
                         "%s holds results of a different %s (%s); they are not mixed with this run: rerun with "
                         "--fresh to discard them, or choose another --out directory",
                         s->path, what[k], diff);
        }
    }
    free(stored);
    return st;
}

/* WAL mode, the tables of a new store, and the key, in one transaction. */
static rf_status write_key(rf_store *s, const rf_store_key *key, const char *inputs, const char *outputs, int exists,
                           int fresh, rf_error *err)
{
    sqlite3 *db = s->db;
    if (sqlite3_exec(db, "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;", NULL, NULL, NULL) != SQLITE_OK)
        return db_fail(err, db, s->path, "cannot switch to WAL mode");
    if (!exists && sqlite3_exec(db, SCHEMA, NULL, NULL, NULL) != SQLITE_OK)
        return db_fail(err, db, s->path, "cannot create the tables");
    if (sqlite3_exec(db, "BEGIN IMMEDIATE", NULL, NULL, NULL) != SQLITE_OK)
        return db_fail(err, db, s->path, "cannot start a transaction");
    if ((exists && fresh && sqlite3_exec(db, "DELETE FROM results", NULL, NULL, NULL) != SQLITE_OK) ||
        meta_set(db, "format", STORE_FORMAT) || meta_set(db, "format_version", STORE_FORMAT_VERSION) ||
        meta_set(db, "identity", key->identity) || meta_set(db, "rockfuzz_version", key->version) ||
        meta_set(db, "inputs", inputs) || meta_set(db, "outputs", outputs)) {
        rf_status st = db_fail(err, db, s->path, "cannot write its meta table");
        sqlite3_exec(db, "ROLLBACK", NULL, NULL, NULL);
        return st;
    }
    if (sqlite3_exec(db, "COMMIT", NULL, NULL, NULL) != SQLITE_OK) {
        rf_status st = db_fail(err, db, s->path, "cannot commit its meta table");
        sqlite3_exec(db, "ROLLBACK", NULL, NULL, NULL);
        return st;
    }
    if (sqlite3_prepare_v2(db, "SELECT ok, y FROM results WHERE x = ?1", -1, &s->lookup, NULL) != SQLITE_OK ||
        sqlite3_prepare_v2(db,
                           "INSERT OR REPLACE INTO results(x, ok, y, error, seconds, finished, x_text) "
                           "VALUES(?1, ?2, ?3, ?4, ?5, ?6, ?7)",
                           -1, &s->put, NULL) != SQLITE_OK)
        return db_fail(err, db, s->path, "cannot prepare its statements");
    return RF_OK;
}

rf_status rf_store_open(const char *path, const rf_store_key *key, int fresh, rf_store **out, rf_error *err)
{
    *out = NULL;
    if (!path || !key || !key->identity || !key->version)
        return rf_fail(err, RF_EINTERNAL, "rf_store_open: NULL argument");
    rf_store *s = calloc(1, sizeof *s);
    char *inputs = join_names(key->n_inputs, key->input_names);
    char *outputs = join_names(key->n_outputs, key->output_names);
    if (!s || !inputs || !outputs || !(s->path = rf_strdup(path))) {
        free(s);
        free(inputs);
        free(outputs);
        return rf_fail(err, RF_ENOMEM, "out of memory for the result store");
    }
    pthread_mutex_init(&s->lock, NULL);
    s->n_inputs = key->n_inputs;
    s->n_outputs = key->n_outputs;
    int exists = 0;
    rf_status st = open_or_create(s, path, fresh, &exists, err);
    if (st == RF_OK && exists)
        st = check_key(s, key, inputs, outputs, fresh, err);
    if (st == RF_OK)
        st = write_key(s, key, inputs, outputs, exists, fresh, err);
    free(inputs);
    free(outputs);
    if (st != RF_OK) {
        rf_store_close(s);
        return st;
    }
    *out = s;
    return RF_OK;
}

void rf_store_close(rf_store *s)
{
    if (!s)
        return;
    sqlite3_finalize(s->lookup);
    sqlite3_finalize(s->put);
    sqlite3_close(s->db);
    pthread_mutex_destroy(&s->lock);
    free(s->path);
    free(s);
}

rf_status rf_store_begin_run(rf_store *s, size_t planned_total, const char *study_name, rf_error *err)
{
    char total[32], started[64], pid[32], host[256] = "";
    snprintf(total, sizeof total, "%zu", planned_total);
    snprintf(started, sizeof started, "%.6f", unix_now());
    snprintf(pid, sizeof pid, "%ld", (long)getpid());
    gethostname(host, sizeof host - 1);
    pthread_mutex_lock(&s->lock);
    rf_status st = RF_OK;
    if (sqlite3_exec(s->db, "BEGIN IMMEDIATE", NULL, NULL, NULL) != SQLITE_OK ||
        meta_set(s->db, "planned_total", total) || meta_set(s->db, "run_started", started) ||
        meta_set(s->db, "run_pid", pid) || meta_set(s->db, "run_host", host) ||
        meta_set(s->db, "study", study_name ? study_name : "") ||
        sqlite3_exec(s->db, "COMMIT", NULL, NULL, NULL) != SQLITE_OK) {
        st = db_fail(err, s->db, s->path, "cannot record the plan");
        sqlite3_exec(s->db, "ROLLBACK", NULL, NULL, NULL);
    }
    pthread_mutex_unlock(&s->lock);
    return st;
}

int rf_store_lookup(rf_store *s, const double *x, double *y, rf_error *err)
{
    pthread_mutex_lock(&s->lock);
    int found = 0;
    sqlite3_reset(s->lookup);
    sqlite3_bind_blob(s->lookup, 1, x, (int)(s->n_inputs * sizeof(double)), SQLITE_STATIC);
    int rc = sqlite3_step(s->lookup);
    if (rc == SQLITE_ROW) {
        int ok = sqlite3_column_int(s->lookup, 0);
        const void *blob = sqlite3_column_blob(s->lookup, 1);
        int bytes = sqlite3_column_bytes(s->lookup, 1);
        if (ok == 1 && blob && (size_t)bytes == s->n_outputs * sizeof(double)) {
            memcpy(y, blob, (size_t)bytes);
            found = 1;
        }
    } else if (rc != SQLITE_DONE) {
        db_fail(err, s->db, s->path, "cannot look up a result");
        found = -1;
    }
    sqlite3_reset(s->lookup);
    sqlite3_clear_bindings(s->lookup);
    pthread_mutex_unlock(&s->lock);
    return found;
}

rf_status rf_store_put(rf_store *s, const double *x, int ok, const double *y, const char *error, double seconds,
                       rf_error *err)
{
    char text[512];
    size_t used = 0;
    for (size_t i = 0; i < s->n_inputs && used < sizeof text; i++)
        used += (size_t)snprintf(text + used, sizeof text - used, "%s%.17g", i ? ", " : "", x[i]);
    pthread_mutex_lock(&s->lock);
    sqlite3_reset(s->put);
    sqlite3_bind_blob(s->put, 1, x, (int)(s->n_inputs * sizeof(double)), SQLITE_STATIC);
    sqlite3_bind_int(s->put, 2, ok > 0 ? 1 : ok < 0 ? -1 : 0);
    if (ok > 0)
        sqlite3_bind_blob(s->put, 3, y, (int)(s->n_outputs * sizeof(double)), SQLITE_STATIC);
    else
        sqlite3_bind_null(s->put, 3);
    if (ok == 0)
        sqlite3_bind_text(s->put, 4, error ? error : "failed", -1, SQLITE_TRANSIENT);
    else if (ok < 0)
        sqlite3_bind_text(s->put, 4, "started, never finished (the run was killed, or this evaluation crashed it)",
                          -1, SQLITE_STATIC);
    else
        sqlite3_bind_null(s->put, 4);
    sqlite3_bind_double(s->put, 5, seconds);
    sqlite3_bind_double(s->put, 6, unix_now());
    sqlite3_bind_text(s->put, 7, text, -1, SQLITE_TRANSIENT);
    rf_status st = RF_OK;
    if (sqlite3_step(s->put) != SQLITE_DONE)
        st = db_fail(err, s->db, s->path, "cannot commit a result");
    sqlite3_reset(s->put);
    sqlite3_clear_bindings(s->put);
    pthread_mutex_unlock(&s->lock);
    return st;
}

rf_status rf_store_note_set(rf_store *s, const char *key, const char *value, rf_error *err)
{
    char k[128];
    snprintf(k, sizeof k, "note.%s", key);
    pthread_mutex_lock(&s->lock);
    rf_status st = meta_set(s->db, k, value) == 0 ? RF_OK : db_fail(err, s->db, s->path, "cannot write a note");
    pthread_mutex_unlock(&s->lock);
    return st;
}

rf_status rf_store_note_get(rf_store *s, const char *key, char *buf, size_t size, rf_error *err)
{
    char k[128];
    snprintf(k, sizeof k, "note.%s", key);
    pthread_mutex_lock(&s->lock);
    rf_status st = meta_get(s->db, k, buf, size) == 0 ? RF_OK : db_fail(err, s->db, s->path, "cannot read a note");
    pthread_mutex_unlock(&s->lock);
    return st;
}

rf_status rf_store_put_started(rf_store *s, const double *x, rf_error *err)
{
    return rf_store_put(s, x, -1, NULL, NULL, 0, err);
}

rf_status rf_store_limit_pages(rf_store *s, long pages, rf_error *err)
{
    char sql[64];
    snprintf(sql, sizeof sql, "PRAGMA max_page_count=%ld", pages);
    pthread_mutex_lock(&s->lock);
    rf_status st = sqlite3_exec(s->db, sql, NULL, NULL, NULL) == SQLITE_OK
                       ? RF_OK
                       : db_fail(err, s->db, s->path, "cannot set max_page_count");
    pthread_mutex_unlock(&s->lock);
    return st;
}

/* ----------------------------------------------------------- read-only */

static rf_status open_readonly(const char *path, sqlite3 **db, rf_error *err)
{
    struct stat sb;
    if (stat(path, &sb) != 0)
        return rf_fail(err, RF_EIO, "%s: no result store here (%s)", path, strerror(errno));
    if (sqlite3_open_v2(path, db, SQLITE_OPEN_READONLY, NULL) != SQLITE_OK) {
        rf_status st = rf_fail(err, RF_EIO, "result store %s: cannot open: %s", path,
                               *db ? sqlite3_errmsg(*db) : "out of memory");
        sqlite3_close(*db);
        *db = NULL;
        return st;
    }
    sqlite3_busy_timeout(*db, 5000);
    rf_status st = check_format(*db, path, err);
    if (st != RF_OK) {
        sqlite3_close(*db);
        *db = NULL;
    }
    return st;
}

rf_status rf_store_read_info(const char *path, rf_store_info *info, rf_error *err)
{
    memset(info, 0, sizeof *info);
    sqlite3 *db = NULL;
    rf_status st = open_readonly(path, &db, err);
    if (st != RF_OK)
        return st;
    char buf[64];
    if (meta_get(db, "identity", info->identity, sizeof info->identity) ||
        meta_get(db, "rockfuzz_version", info->version, sizeof info->version) ||
        meta_get(db, "study", info->study, sizeof info->study) ||
        meta_get(db, "run_host", info->host, sizeof info->host)) {
        st = db_fail(err, db, path, "cannot read its meta table");
        goto done;
    }
    meta_get(db, "run_pid", buf, sizeof buf);
    info->pid = strtol(buf, NULL, 10);
    meta_get(db, "planned_total", buf, sizeof buf);
    info->planned_total = (size_t)strtoull(buf, NULL, 10);
    meta_get(db, "run_started", buf, sizeof buf);
    info->run_started = strtod(buf, NULL);
    sqlite3_stmt *q = NULL;
    if (sqlite3_prepare_v2(db,
                           "SELECT coalesce(sum(ok = 1), 0), coalesce(sum(ok = 0), 0), coalesce(min(finished), 0),"
                           " coalesce(max(finished), 0), coalesce(sum(seconds), 0),"
                           " coalesce(sum(finished >= ?1 AND ok >= 0), 0), coalesce(sum(ok < 0), 0) FROM results",
                           -1, &q, NULL) != SQLITE_OK) {
        st = db_fail(err, db, path, "cannot read its results");
        goto done;
    }
    sqlite3_bind_double(q, 1, info->run_started);
    if (sqlite3_step(q) == SQLITE_ROW) {
        info->done = (size_t)sqlite3_column_int64(q, 0);
        info->failed = (size_t)sqlite3_column_int64(q, 1);
        info->first_update = sqlite3_column_double(q, 2);
        info->last_update = sqlite3_column_double(q, 3);
        info->eval_seconds = sqlite3_column_double(q, 4);
        info->done_this_run = (size_t)sqlite3_column_int64(q, 5);
        info->unfinished = (size_t)sqlite3_column_int64(q, 6);
    } else {
        st = db_fail(err, db, path, "cannot read its results");
    }
    sqlite3_finalize(q);
done:
    sqlite3_close(db);
    return st;
}

size_t rf_store_failures(const char *path, size_t max, char (*x_text)[512], char (*message)[512], rf_error *err)
{
    sqlite3 *db = NULL;
    if (open_readonly(path, &db, err) != RF_OK)
        return 0;
    sqlite3_stmt *q = NULL;
    size_t n = 0;
    if (sqlite3_prepare_v2(db, "SELECT x_text, error FROM results WHERE ok <= 0 ORDER BY finished LIMIT ?1", -1,
                           &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int64(q, 1, (sqlite3_int64)max);
        while (n < max && sqlite3_step(q) == SQLITE_ROW) {
            const unsigned char *a = sqlite3_column_text(q, 0), *b = sqlite3_column_text(q, 1);
            snprintf(x_text[n], 512, "%s", a ? (const char *)a : "");
            snprintf(message[n], 512, "%s", b ? (const char *)b : "");
            n++;
        }
    }
    sqlite3_finalize(q);
    sqlite3_close(db);
    return n;
}

/* ---- side rows: a model's own data kept with its results (rf_model_side_store) ----
 * Table side_rows(key, row): a row of doubles as a blob under a text key,
 * created when the first row is written (stores of before have none); an
 * identical (key, row) is kept once.  Each row read back is checked for its
 * width; what the values mean is checked by the model. */
static const char *SIDE_SCHEMA = "CREATE TABLE IF NOT EXISTS side_rows(key TEXT NOT NULL, row BLOB NOT NULL,"
                                 " finished REAL NOT NULL, PRIMARY KEY(key, row))";

rf_status rf_store_side_put(rf_store *s, const char *key, const double *row, size_t width, rf_error *err)
{
    sqlite3_stmt *st = NULL;
    pthread_mutex_lock(&s->lock);
    int rc = sqlite3_exec(s->db, SIDE_SCHEMA, NULL, NULL, NULL);
    if (rc == SQLITE_OK)
        rc = sqlite3_prepare_v2(s->db, "INSERT OR IGNORE INTO side_rows(key, row, finished) VALUES(?, ?, ?)", -1,
                                &st, NULL);
    if (rc == SQLITE_OK) {
        sqlite3_bind_text(st, 1, key, -1, SQLITE_STATIC);
        sqlite3_bind_blob(st, 2, row, (int)(width * sizeof *row), SQLITE_STATIC);
        sqlite3_bind_double(st, 3, unix_now());
        rc = sqlite3_step(st) == SQLITE_DONE ? SQLITE_OK : SQLITE_ERROR;
    }
    rf_status out = rc == SQLITE_OK ? RF_OK : db_fail(err, s->db, s->path, "cannot commit a side row");
    sqlite3_finalize(st);
    pthread_mutex_unlock(&s->lock);
    return out;
}

/* 1 if the store has the table side_rows, 0 if not, -1 on error. */
static int has_side_rows(sqlite3 *db)
{
    sqlite3_stmt *st = NULL;
    if (sqlite3_prepare_v2(db, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = 'side_rows'", -1, &st,
                           NULL) != SQLITE_OK)
        return -1;
    int rc = sqlite3_step(st);
    sqlite3_finalize(st);
    return rc == SQLITE_ROW ? 1 : rc == SQLITE_DONE ? 0 : -1;
}

rf_status rf_store_side_each(rf_store *s, const char *key, size_t width, rf_status (*fn)(void *u, const double *row),
                             void *u, rf_error *err)
{
    sqlite3_stmt *st = NULL;
    pthread_mutex_lock(&s->lock);
    int has = has_side_rows(s->db);
    rf_status out = has < 0 ? db_fail(err, s->db, s->path, "cannot read the side rows") : RF_OK;
    if (has > 0 && sqlite3_prepare_v2(s->db, "SELECT row FROM side_rows WHERE key = ? ORDER BY rowid", -1, &st,
                                      NULL) != SQLITE_OK)
        out = db_fail(err, s->db, s->path, "cannot read the side rows");
    if (st)
        sqlite3_bind_text(st, 1, key, -1, SQLITE_STATIC);
    double *row = malloc(width * sizeof *row + 1);
    int rc = SQLITE_DONE;
    if (!row && out == RF_OK)
        out = rf_fail(err, RF_ENOMEM, "out of memory");
    while (out == RF_OK && st && (rc = sqlite3_step(st)) == SQLITE_ROW) {
        const void *blob = sqlite3_column_blob(st, 0);
        if ((size_t)sqlite3_column_bytes(st, 0) != width * sizeof *row || !blob)
            out = rf_fail(err, RF_EIO, "result store %s: a side row of %s has %d bytes, not %zu values: the store "
                          "is damaged; rerun with --fresh", s->path, key, sqlite3_column_bytes(st, 0), width);
        else
            out = (memcpy(row, blob, width * sizeof *row), fn(u, row));
    }
    if (out == RF_OK && st && rc != SQLITE_DONE)
        out = db_fail(err, s->db, s->path, "cannot read the side rows");
    free(row);
    sqlite3_finalize(st);
    pthread_mutex_unlock(&s->lock);
    return out;
}
