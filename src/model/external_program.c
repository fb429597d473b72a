/* external_program.c - finding the external model's program at creation:
 * argv[0] with a '/' is a path (resolved now, against this process's working
 * directory), otherwise it is looked up on PATH; either way it must be an
 * executable regular file.  Uses external_text.c (external_internal.h). */
#undef _POSIX_C_SOURCE
#define _GNU_SOURCE /* realpath */
#include "external_internal.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int is_executable_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode) && access(path, X_OK) == 0;
}

rf_status ext_resolve_program(const char *name, char **out, rf_error *err)
{
    if (!name[0])
        return rf_fail(err, RF_EINVAL, "external model: argv[0] (the program) is empty");
    if (strchr(name, '/')) {
        /* Relative paths are resolved now, against this process's working
         * directory: the child runs in another directory. */
        char *real = realpath(name, NULL);
        if (!real)
            return rf_fail(err, RF_EINVAL, "external model: program '%s' not found: %s", name, strerror(errno));
        if (!is_executable_file(real)) {
            rf_status st = rf_fail(err, RF_EINVAL, "external model: program '%s' is not an executable file", name);
            free(real);
            return st;
        }
        *out = real;
        return RF_OK;
    }
    const char *path = getenv("PATH");
    if (!path || !path[0])
        path = "/usr/local/bin:/usr/bin:/bin";
    const char *p = path;
    for (;;) {
        size_t n = strcspn(p, ":");
        strbuf cand = {0};
        if (n == 0)
            ext_sb_puts(&cand, ".");
        else
            ext_sb_append(&cand, p, n);
        ext_sb_printf(&cand, "/%s", name);
        if (cand.oom) {
            free(cand.data);
            return rf_fail(err, RF_ENOMEM, "out of memory looking up program '%s'", name);
        }
        if (is_executable_file(cand.data)) {
            char *real = n == 0 ? realpath(cand.data, NULL) : NULL;
            if (real) {
                free(cand.data);
                cand.data = real;
            }
            *out = cand.data;
            return RF_OK;
        }
        free(cand.data);
        if (!p[n])
            break;
        p += n + 1;
    }
    return rf_fail(err, RF_EINVAL, "external model: program '%s' not found on PATH (%s)", name, path);
}
