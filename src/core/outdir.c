/* outdir.c - the output folder rule (core/outdir.h). */
#include "core/outdir.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

static int is_marker(const char *name, const char *const *markers, size_t n)
{
    for (size_t k = 0; k < n; k++)
        if (!strcmp(name, markers[k]))
            return 1;
    return 0;
}

/* "a, b or c" */
static void marker_list(const char *const *markers, size_t n, char *buf, size_t size)
{
    size_t len = 0;
    buf[0] = '\0';
    for (size_t k = 0; k < n && len < size; k++)
        len += (size_t)snprintf(buf + len, size - len, "%s%s", k == 0 ? "" : k + 1 == n ? " or " : ", ", markers[k]);
}

rf_status rf_check_out_dir(const char *dir, int force, const char *const *markers, size_t n_markers, rf_error *err)
{
    struct stat sb;
    if (stat(dir, &sb) != 0)
        return errno == ENOENT ? RF_OK : rf_fail(err, RF_EIO, "--out %s: %s", dir, strerror(errno));
    if (!S_ISDIR(sb.st_mode))
        return rf_fail(err, RF_EINVAL, "--out %s: exists and is not a folder", dir);
    DIR *d = opendir(dir);
    if (!d)
        return rf_fail(err, RF_EIO, "--out %s: cannot list the folder: %s", dir, strerror(errno));
    size_t others = 0, found = 0;
    char example[256] = "", list[256];
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        if (is_marker(e->d_name, markers, n_markers))
            found++;
        else if (others++ == 0)
            snprintf(example, sizeof example, "%s", e->d_name);
    }
    closedir(d);
    if (others == 0 || found > 0 || force)
        return RF_OK;
    marker_list(markers, n_markers, list, sizeof list);
    return rf_fail(err, RF_EINVAL,
                   "--out %s: the folder is not empty (%zu entr%s, e.g. '%s') and holds no rockfuzz run (no %s); "
                   "rockfuzz would overwrite files there. Choose a new folder, or pass --force to write into it "
                   "anyway", dir, others, others == 1 ? "y" : "ies", example, list);
}
