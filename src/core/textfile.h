/* textfile.h - reading a whole input file (study file, trajectory file)
 * safely: a regular file, or a pipe that has a writer (e.g. `<(generate)`);
 * a directory, a device, or a FIFO nobody writes to is refused instead of
 * read or waited on forever, and a file over the size limit is refused
 * before it is parsed.  Core layer: includes only status.h. */
#ifndef ROCKFUZZ_CORE_TEXTFILE_H
#define ROCKFUZZ_CORE_TEXTFILE_H

#include "rockfuzz/status.h"

#include <stddef.h>

/* A pipe given as an input file must deliver within this. */
#define RF_PIPE_WAIT_MS 5000

/* The whole file into a malloc'ed, NUL-terminated *buf of *len bytes (the
 * caller frees it); `what` names the kind of file in messages ("study
 * file").  Files larger than max_bytes are refused. */
rf_status rf_read_text_file(const char *path, const char *what, size_t max_bytes, char **buf, size_t *len,
                            rf_error *err);

/* A file read by another library (GDAL) or read and appended (a cache) must
 * be a regular file: a directory, a FIFO or a device is refused without
 * opening it (opening a FIFO blocks; /dev/zero never ends). */
rf_status rf_require_regular_file(const char *path, const char *what, rf_error *err);

#endif
