/* traj_json_file.c - a run's JSON document into a file, whole or not at all
 * (trajectory.h: rf_traj_write_json_file): written as PATH.tmp, every write
 * and the close checked, renamed into place at the end.  A file left half
 * written by a full disk would be a truncated result.json that looks like a
 * finished run's. */
#include "rockfuzz/terrain.h"
#include "rockfuzz/trajectory.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

rf_status rf_traj_write_json_file(const char *path, const rf_traj_spec *s, const rf_traj_ensemble *e,
                                  const rf_traj_stats *st, size_t max_traj, rf_error *err)
{
    char tmp[4200];
    if ((size_t)snprintf(tmp, sizeof tmp, "%s.tmp", path) >= sizeof tmp)
        return rf_fail(err, RF_EINVAL, "%s: path too long", path);
    FILE *f = fopen(tmp, "w");
    if (!f)
        return rf_fail(err, RF_EIO, "cannot write %s: %s", tmp, strerror(errno));
    errno = 0; /* a failed write's cause, kept by ferror's stream */
    if (s->terrain)
        rf_terrain_write_json(f, s, e, st, max_traj);
    else
        rf_traj_write_json(f, s, e, st, max_traj);
    int bad = ferror(f) ? errno ? errno : EIO : 0;
    if (fclose(f) != 0 && !bad)
        bad = errno ? errno : EIO;
    if (!bad && rename(tmp, path) != 0)
        bad = errno ? errno : EIO;
    if (!bad)
        return RF_OK;
    unlink(tmp);
    return rf_fail(err, RF_EIO, "cannot write %s: %s (a file there is left as it was)", path, strerror(bad));
}
