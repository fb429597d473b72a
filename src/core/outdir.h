/* outdir.h - the rule for an output folder (--out DIR) that every command
 * writing one follows: it must be missing, empty, already hold a rockfuzz
 * result of that kind (one of its marker files), or be accepted with --force,
 * so that rockfuzz never overwrites a user's own files.  Core layer. */
#ifndef ROCKFUZZ_CORE_OUTDIR_H
#define ROCKFUZZ_CORE_OUTDIR_H

#include "rockfuzz/status.h"

#include <stddef.h>

rf_status rf_check_out_dir(const char *dir, int force, const char *const *markers, size_t n_markers,
                           rf_error *err);

#endif
