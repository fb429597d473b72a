/* textfile.c - reading a whole input file safely (core/textfile.h). */
#include "core/textfile.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Why fd cannot be read as an input file, or NULL if it can. */
static const char *unreadable(int fd)
{
    struct stat sb;
    if (fstat(fd, &sb) != 0)
        return strerror(errno);
    if (S_ISDIR(sb.st_mode))
        return "it is a directory";
    if (S_ISFIFO(sb.st_mode)) {
        struct pollfd p = {fd, POLLIN, 0};
        if (poll(&p, 1, RF_PIPE_WAIT_MS) <= 0 || !(p.revents & (POLLIN | POLLHUP)))
            return "it is a pipe or FIFO and nothing was written to it within 5 s";
        return NULL;
    }
    if (!S_ISREG(sb.st_mode))
        return "it is not a regular file";
    return NULL;
}

rf_status rf_require_regular_file(const char *path, const char *what, rf_error *err)
{
    struct stat sb;
    if (stat(path, &sb) != 0)
        return rf_fail(err, RF_EIO, "%s: cannot open the %s: %s", path, what, strerror(errno));
    if (S_ISREG(sb.st_mode))
        return RF_OK;
    const char *kind = S_ISDIR(sb.st_mode) ? "a directory" : S_ISFIFO(sb.st_mode) ? "a pipe or FIFO"
                       : S_ISCHR(sb.st_mode) || S_ISBLK(sb.st_mode) ? "a device" : "not a regular file";
    return rf_fail(err, RF_EIO, "%s: cannot read the %s: it is %s; a regular file is needed", path, what, kind);
}

static rf_status open_input(const char *path, const char *what, FILE **f, rf_error *err)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return rf_fail(err, RF_EIO, "%s: cannot open the %s: %s", path, what, strerror(errno));
    const char *why = unreadable(fd);
    if (!why && fcntl(fd, F_SETFL, 0) != 0)
        why = strerror(errno);
    if (!why && !(*f = fdopen(fd, "rb")))
        why = strerror(errno);
    if (why) {
        close(fd);
        return rf_fail(err, RF_EIO, "%s: cannot read the %s: %s", path, what, why);
    }
    return RF_OK;
}

rf_status rf_read_text_file(const char *path, const char *what, size_t max_bytes, char **buf, size_t *len,
                            rf_error *err)
{
    *buf = NULL;
    *len = 0;
    FILE *f = NULL;
    rf_status st = open_input(path, what, &f, err);
    if (st != RF_OK)
        return st;
    long size = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    if (size < 0 || fseek(f, 0, SEEK_SET) != 0)
        size = (long)max_bytes; /* not seekable (a pipe): read up to the limit */
    size_t cap = (size_t)size < max_bytes ? (size_t)size + 1 : max_bytes + 1;
    char *b = malloc(cap + 1);
    if (!b) {
        fclose(f);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    size_t n = fread(b, 1, cap, f);
    int bad = ferror(f) || (n == cap && cap <= max_bytes); /* or it grew while we read it */
    fclose(f);
    if (bad)
        st = rf_fail(err, RF_EIO, "%s: cannot read the %s", path, what);
    else if (n > max_bytes)
        st = rf_fail(err, RF_EINVAL, "%s: the %s is larger than %zu bytes", path, what, max_bytes);
    if (st != RF_OK) {
        free(b);
        return st;
    }
    b[n] = '\0';
    *buf = b;
    *len = n;
    return RF_OK;
}
