/* study_internal.h - helpers shared by the study parser files (study.c,
 * study_model.c): walking a libfyaml document with errors that name the
 * file, line, field path and value. */
#ifndef ROCKFUZZ_STUDY_INTERNAL_H
#define ROCKFUZZ_STUDY_INTERNAL_H

#include "rockfuzz/study.h"

#include <libfyaml.h>

typedef struct {
    const char *file;  /* name used in messages */
    const char *dir;   /* base of relative paths */
    rf_error *err;
    struct fy_node *last_key;  /* locates messages about a missing value */
} sp_ctx;

/* 1-based line of a node (0 if unknown). */
int sp_line(struct fy_node *n);

/* "file:line: path = value: reason" with the node's text as value. */
rf_status sp_fail(sp_ctx *c, struct fy_node *n, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Same, prefixing the message already in c->err (from a constructor). */
rf_status sp_prefix(sp_ctx *c, struct fy_node *n, const char *path);

/* Typed accessors: each fails with a located message on a type mismatch. */
rf_status sp_mapping(sp_ctx *c, struct fy_node *n, const char *path);
rf_status sp_sequence(sp_ctx *c, struct fy_node *n, const char *path, size_t min, size_t max,
                      size_t *count);
rf_status sp_number(sp_ctx *c, struct fy_node *n, const char *path, double *v);
rf_status sp_integer(sp_ctx *c, struct fy_node *n, const char *path, long long min, long long max,
                     long long *v);
rf_status sp_bool(sp_ctx *c, struct fy_node *n, const char *path, int *v);
/* A scalar as a string (plain or quoted); *s points into the document, len set. */
rf_status sp_string(sp_ctx *c, struct fy_node *n, const char *path, const char **s, size_t *len);
/* A short word (an enum's name) into buf; one longer than size - 1 becomes "", which no name
   table holds, so that the caller's parse fails and it reports its own located message. */
rf_status sp_word(sp_ctx *c, struct fy_node *n, const char *path, char *buf, size_t size);
/* Malloc'ed NUL-terminated copy of a string scalar. */
rf_status sp_string_dup(sp_ctx *c, struct fy_node *n, const char *path, char **out);
/* A sequence of numbers [min..max] long into v (caller-sized for max). */
rf_status sp_numbers(sp_ctx *c, struct fy_node *n, const char *path, size_t min, size_t max,
                     double *v, size_t *count);

/* snprintf for field paths: truncation is accepted (paths are bounded by key lengths). */
void sp_pathf(char *buf, size_t size, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Iterate a mapping's pairs; checks that keys are scalars and unique.
 * Returns RF_OK with *key and *val set, or RF_OK with *key == NULL at the end. */
typedef struct {
    struct fy_node *map;
    void *it;
    size_t index;
    char key[256];
} sp_iter;
rf_status sp_next(sp_ctx *c, sp_iter *it, const char *path, const char **key, struct fy_node **keynode,
                  struct fy_node **val);

/* Build the model of `model:`; study->params are already parsed. */
rf_status sp_parse_model(sp_ctx *c, struct fy_node *n, rf_study *study);

/* The text must be UTF-8 without NUL bytes (checked before libfyaml sees it:
 * libfyaml 0.7.12 loops forever on some invalid bytes); study.c. */
rf_status sp_check_text(const char *name, const char *buf, size_t len, rf_error *err);

/* The trajectory model block (src/trajectory/traj_study.c). */
rf_status rf_traj_study_parse(sp_ctx *c, struct fy_node *n, rf_study *study);
/* A trajectory study's Monte Carlo rerun at the nominal point, written to
 * DIR/nominal/ (traj_study_report.c); RF_OK and nothing for other models. */
rf_status rf_traj_study_nominal(const char *dir, const rf_study *s, int threads, int plots, rf_error *err);

char *sp_strdup(const char *s);
char *sp_strndup(const char *s, size_t len);

#endif
