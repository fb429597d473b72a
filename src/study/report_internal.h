/* report_internal.h - helpers shared by the report writers (report_util.c). */
#ifndef ROCKFUZZ_REPORT_INTERNAL_H
#define ROCKFUZZ_REPORT_INTERNAL_H

#include <stddef.h>

#include "rockfuzz/tm.h"

/* A name made safe for a file name: [A-Za-z0-9_.-], others become '_'. */
void rp_safe_name(const char *name, char *buf, size_t size);

/* Output k is NaN at every level and at the nominal point (e.g. R_t of a normal impact). */
int rp_output_undefined(const rf_tm_result *res, size_t k);

#endif
