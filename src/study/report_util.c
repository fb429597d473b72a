/* report_util.c - small helpers shared by the report writers (report.c,
 * report_plot.c, report_html.c), kept apart so that those files never call
 * into each other for them. */
#include "study/report_internal.h"

#include <math.h>
#include <stdio.h>

int rp_output_undefined(const rf_tm_result *res, size_t k)
{
    for (size_t j = 0; j <= res->levels; j++)
        if (!isnan(res->lo[k * (res->levels + 1) + j]) || !isnan(res->hi[k * (res->levels + 1) + j]))
            return 0;
    return isnan(res->nominal[k]);
}

void rp_safe_name(const char *name, char *buf, size_t size)
{
    size_t k = 0;
    for (; name[k] && k + 1 < size && k < 80; k++) {
        char ch = name[k];
        int ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_' ||
                 ch == '-' || (ch == '.' && k > 0);
        buf[k] = ok ? ch : '_';
    }
    buf[k] = '\0';
    if (k == 0)
        snprintf(buf, size, "_");
}
