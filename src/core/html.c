/* html.c - HTML text escaping and embedded PNG figures (html.h). */
#include "core/html.h"

void rf_html_text(FILE *f, const char *s)
{
    for (; s && *s; s++) {
        switch (*s) {
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '&': fputs("&amp;", f); break;
        case '"': fputs("&quot;", f); break;
        default: fputc(*s, f);
        }
    }
}

/* n (1..3) bytes as 4 base64 characters, '=' padded. */
static void base64_group(FILE *f, const unsigned char *b, size_t n)
{
    static const char b64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    unsigned v = (unsigned)b[0] << 16 | (n > 1 ? (unsigned)b[1] << 8 : 0) | (n > 2 ? b[2] : 0);
    fputc(b64[v >> 18 & 63], f);
    fputc(b64[v >> 12 & 63], f);
    fputc(n > 1 ? b64[v >> 6 & 63] : '=', f);
    fputc(n > 2 ? b64[v & 63] : '=', f);
}

int rf_html_png(FILE *f, const char *path, const char *alt)
{
    FILE *in = fopen(path, "rb");
    if (!in)
        return 0;
    fputs("<img alt=\"", f);
    rf_html_text(f, alt);
    fputs("\" src=\"data:image/png;base64,", f);
    unsigned char buf[3 * 1024];
    size_t got, used = 0;
    while ((got = fread(buf + used, 1, sizeof buf - used, in)) > 0) {
        used += got;
        size_t whole = used - used % 3;
        for (size_t i = 0; i < whole; i += 3)
            base64_group(f, buf + i, 3);
        for (size_t i = whole; i < used; i++) /* a short read's tail waits for the next bytes */
            buf[i - whole] = buf[i];
        used -= whole;
    }
    if (used)
        base64_group(f, buf, used);
    fclose(in);
    fputs("\">\n", f);
    return 1;
}
