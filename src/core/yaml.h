/* yaml.h - typed, located access to a libfyaml document, for every file
 * rockfuzz reads (study files, trajectory files): each failure becomes
 * "file:line: field = value: reason".  Core layer: includes only status.h. */
#ifndef ROCKFUZZ_CORE_YAML_H
#define ROCKFUZZ_CORE_YAML_H

#include "rockfuzz/status.h"

#include <libfyaml.h>
#include <stddef.h>

typedef struct {
    const char *file;  /* name used in messages */
    const char *dir;   /* base of relative paths */
    rf_error *err;
    struct fy_node *last_key;  /* locates messages about a missing value */
} yr_ctx;

/* 1-based line of a node (0 if unknown). */
int yr_line(struct fy_node *n);

/* "file:line: path = value: reason" with the node's text as value. */
rf_status yr_fail(yr_ctx *c, struct fy_node *n, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Same, prefixing the message already in c->err (from a constructor). */
rf_status yr_prefix(yr_ctx *c, struct fy_node *n, const char *path);

/* Typed accessors: each fails with a located message on a type mismatch. */
rf_status yr_mapping(yr_ctx *c, struct fy_node *n, const char *path);
rf_status yr_sequence(yr_ctx *c, struct fy_node *n, const char *path, size_t min, size_t max,
                      size_t *count);
rf_status yr_number(yr_ctx *c, struct fy_node *n, const char *path, double *v);
rf_status yr_integer(yr_ctx *c, struct fy_node *n, const char *path, long long min, long long max,
                     long long *v);
rf_status yr_bool(yr_ctx *c, struct fy_node *n, const char *path, int *v);
/* A scalar as a string (plain or quoted); *s points into the document, len set. */
rf_status yr_string(yr_ctx *c, struct fy_node *n, const char *path, const char **s, size_t *len);
/* A short word (an enum's name) into buf; one longer than size - 1 becomes "", which no name
   table holds, so that the caller's parse fails and it reports its own located message. */
rf_status yr_word(yr_ctx *c, struct fy_node *n, const char *path, char *buf, size_t size);
/* Malloc'ed NUL-terminated copy of a string scalar. */
rf_status yr_string_dup(yr_ctx *c, struct fy_node *n, const char *path, char **out);
/* A sequence of numbers [min..max] long into v (caller-sized for max). */
rf_status yr_numbers(yr_ctx *c, struct fy_node *n, const char *path, size_t min, size_t max,
                     double *v, size_t *count);

/* snprintf for field paths: truncation is accepted (paths are bounded by key lengths). */
void yr_pathf(char *buf, size_t size, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Iterate a mapping's pairs; checks that keys are scalars and unique.
 * Returns RF_OK with *key and *val set, or RF_OK with *key == NULL at the end. */
typedef struct {
    struct fy_node *map;
    void *it;
    size_t index;
    char key[256];
} yr_iter;
rf_status yr_next(yr_ctx *c, yr_iter *it, const char *path, const char **key, struct fy_node **keynode,
                  struct fy_node **val);

/* The text must be UTF-8 without NUL bytes (checked before libfyaml sees it:
 * libfyaml 0.7.12 loops forever on some invalid bytes). */
rf_status yr_check_text(const char *name, const char *buf, size_t len, rf_error *err);

/* Exactly one YAML document parsed from buf (checked with yr_check_text
 * first, and for flow collections nested deeper than 64 levels, refused
 * before libfyaml spends memory on them); `what` names the kind of file in
 * messages ("study file").  Invalid
 * YAML, no document or a second one is a located error.  Free with
 * yr_doc_free (also after a failure). */
typedef struct {
    struct fy_diag *diag;
    struct fy_parser *parser;
    struct fy_document *doc;
} yr_doc;
rf_status yr_doc_load(yr_doc *d, const char *name, const char *buf, size_t len, const char *what, rf_error *err);
void yr_doc_free(yr_doc *d);

char *yr_strdup(const char *s);
char *yr_strndup(const char *s, size_t len);

#endif
