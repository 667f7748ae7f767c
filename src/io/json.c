/* JSON strings (psim_write_json_string, include/psim/psim.h). */
#include <stdio.h>

#include "psim/psim.h"

/* Length of the well-formed UTF-8 sequence at s (1-4), or 0 when it is
 * not one (a stray or missing continuation byte, an overlong form, a
 * surrogate, past U+10FFFF). */
static int utf8_len(const unsigned char *s)
{
    unsigned c = s[0], n = c >= 0xf0 ? 4 : c >= 0xe0 ? 3 : c >= 0xc0 ? 2 : 0;
    if (c < 0x80)
        return 1;
    if (n == 0 || c > 0xf4)
        return 0;
    unsigned cp = c & (0x7fu >> n);
    for (unsigned k = 1; k < n; k++) {
        if ((s[k] & 0xc0) != 0x80)
            return 0;
        cp = cp << 6 | (s[k] & 0x3fu);
    }
    static const unsigned least[5] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < least[n] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff))
        return 0;
    return (int)n;
}

/* s as a JSON string: quotes, backslashes and control characters escaped,
 * and a byte that is not part of well-formed UTF-8 (a file name in another
 * encoding) written as U+FFFD, so the file stays valid JSON. */
void psim_write_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    const unsigned char *p = (const unsigned char *)(s ? s : "");
    while (*p) {
        int n = utf8_len(p);
        if (n == 0) {
            fputs("\\ufffd", f);
            p++;
        } else if (*p == '"' || *p == '\\') {
            fprintf(f, "\\%c", *p++);
        } else if (*p < 0x20) {
            fprintf(f, "\\u%04x", *p++);
        } else {
            fwrite(p, 1, (size_t)n, f);
            p += n;
        }
    }
    fputc('"', f);
}
