/* report_internal.h - helpers shared by report.c and report_plot.c. */
#ifndef ROCKFUZZ_REPORT_INTERNAL_H
#define ROCKFUZZ_REPORT_INTERNAL_H

#include <stddef.h>

/* A name made safe for a file name: [A-Za-z0-9_.-], others become '_'. */
void rp_safe_name(const char *name, char *buf, size_t size);

#endif
