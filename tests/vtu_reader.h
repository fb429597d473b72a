/* vtu_reader.h - an independent reader of the binary .vtu files rockfuzz
 * writes, for the tests: it parses the XML header (attributes of the Piece
 * and of each DataArray), checks the appended block's layout (encoding raw,
 * a UInt64 byte count before every array, the arrays in offset order, the
 * block ending where the file says) and decodes an array to doubles. */
#ifndef ROCKFUZZ_TEST_VTU_READER_H
#define ROCKFUZZ_TEST_VTU_READER_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    char *bytes;       /* the whole file */
    size_t size;
    size_t header_len; /* bytes before the '_' that starts the raw data */
    const char *data;  /* after the '_' */
    long points, cells;
} vtu_file;

static inline int vtu_open(const char *path, vtu_file *f)
{
    memset(f, 0, sizeof *f);
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return 0;
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    f->bytes = malloc((size_t)n + 1);
    if (!f->bytes || fread(f->bytes, 1, (size_t)n, fp) != (size_t)n) {
        fclose(fp);
        return 0;
    }
    fclose(fp);
    f->bytes[n] = 0;
    f->size = (size_t)n;
    const char *app = strstr(f->bytes, "<AppendedData encoding=\"raw\">");
    const char *us = app ? strchr(app, '_') : NULL;
    if (!us || !strstr(f->bytes, "header_type=\"UInt64\"") || !strstr(f->bytes, "byte_order=\"LittleEndian\""))
        return 0;
    f->header_len = (size_t)(us - f->bytes);
    f->data = us + 1;
    const char *piece = strstr(f->bytes, "<Piece ");
    if (!piece || sscanf(strstr(piece, "NumberOfPoints=\""), "NumberOfPoints=\"%ld\"", &f->points) != 1 ||
        sscanf(strstr(piece, "NumberOfCells=\""), "NumberOfCells=\"%ld\"", &f->cells) != 1)
        return 0;
    return 1;
}

static inline void vtu_close(vtu_file *f)
{
    free(f->bytes);
    memset(f, 0, sizeof *f);
}

/* The DataArray named name: its values as doubles (*n of them, *ncomp per
 * tuple); NULL if absent or malformed. */
static inline double *vtu_array(const vtu_file *f, const char *name, size_t *n, int *ncomp)
{
    char key[128], type[32];
    *n = 0, *ncomp = 0;
    snprintf(key, sizeof key, "Name=\"%s\"", name);
    const char *p = strstr(f->bytes, key);
    if (!p || (size_t)(p - f->bytes) > f->header_len)
        return NULL;
    const char *tag = p;
    while (tag > f->bytes && strncmp(tag, "<DataArray", 10))
        tag--;
    const char *end = strchr(tag, '>');
    const char *t = strstr(tag, "type=\""), *c = strstr(tag, "NumberOfComponents=\""), *o = strstr(tag, "offset=\"");
    unsigned long long off;
    if (!t || !c || !o || t > end || c > end || o > end || !strstr(tag, "format=\"appended\"") ||
        sscanf(t, "type=\"%31[^\"]\"", type) != 1 || sscanf(c, "NumberOfComponents=\"%d\"", ncomp) != 1 ||
        sscanf(o, "offset=\"%llu\"", &off) != 1)
        return NULL;
    const int f32 = !strcmp(type, "Float32");
    const size_t size = !strcmp(type, "Float64") ? 8 : f32 || !strcmp(type, "Int32") ? 4 : !strcmp(type, "UInt8") ? 1 : 0;
    uint64_t bytes;
    if (!size || (size_t)(f->data - f->bytes) + off + 8 > f->size)
        return NULL;
    memcpy(&bytes, f->data + off, 8);
    if (bytes % size || (size_t)(f->data - f->bytes) + off + 8 + bytes > f->size)
        return NULL;
    *n = (size_t)(bytes / size);
    double *x = malloc((*n ? *n : 1) * sizeof *x);
    const char *d = f->data + off + 8;
    for (size_t i = 0; x && i < *n; i++) {
        if (size == 8)
            memcpy(&x[i], d + 8 * i, 8);
        else if (f32) {
            float v;
            memcpy(&v, d + 4 * i, 4);
            x[i] = v;
        } else if (size == 4) {
            int32_t v;
            memcpy(&v, d + 4 * i, 4);
            x[i] = v;
        } else
            x[i] = (unsigned char)d[i];
    }
    return x;
}

/* 1 if the header's arrays, in their order, tile the appended block exactly
 * (each offset = the previous one + 8 + its byte count) and the block ends
 * with the closing tags. */
static inline int vtu_layout_ok(const vtu_file *f)
{
    unsigned long long expect = 0, off;
    const char *p = f->bytes;
    while ((p = strstr(p, "<DataArray")) && (size_t)(p - f->bytes) < f->header_len) {
        const char *o = strstr(p, "offset=\"");
        if (!o || sscanf(o, "offset=\"%llu\"", &off) != 1 || off != expect)
            return 0;
        uint64_t bytes;
        if ((size_t)(f->data - f->bytes) + off + 8 > f->size)
            return 0;
        memcpy(&bytes, f->data + off, 8);
        expect = off + 8 + bytes;
        p++;
    }
    const char *tail = "\n</AppendedData>\n</VTKFile>\n";
    return (size_t)(f->data - f->bytes) + expect + strlen(tail) == f->size && !memcmp(f->data + expect, tail, strlen(tail));
}

/* FNV-1a over n bytes from h: the solver's state hash, computed here again. */
static inline uint64_t vtu_fnv1a(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 1099511628211ULL;
    return h;
}
#define VTU_FNV_SEED 1469598103934665603ULL

#endif
