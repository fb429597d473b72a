/* fuzz_study.c - libFuzzer target for the study-file parser.
 *
 * Feeds arbitrary bytes to rf_study_load_buffer.  A load either succeeds
 * (and frees cleanly) or fails with a located message "NAME:LINE: ...";
 * anything else (crash, leak, sanitizer report, unlocated message) is a bug.
 * Build and run: docs/user-guide.md, section "Fuzzing". */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/study.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rf_study study;
    rf_error err;
    memset(&err, 0, sizeof err);
    rf_status st = rf_study_load_buffer("fuzz.yaml", (const char *)data, size, &study, &err);
    if (st == RF_OK) {
        rf_study_free(&study);
        return 0;
    }
    /* Every failure must be located in the file, except running out of memory. */
    if (st != RF_ENOMEM && strncmp(err.msg, "fuzz.yaml:", 10) != 0) {
        fprintf(stderr, "unlocated error message: %s\n", err.msg);
        abort();
    }
    rf_study_free(&study); /* must be safe after a failed load */
    return 0;
}
