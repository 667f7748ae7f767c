/* psim's lines on stderr, and names shown on a terminal: every control
 * byte a message holds (from a file name, an argument or the bytes of an
 * input) is written as an escape, so that a message is always one line
 * and never moves the cursor, colours the terminal or rings its bell. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "say.h"

/* The length of the UTF-8 sequence at s (at most n bytes) that may be
 * shown as it is: a printable ASCII byte or a valid multi-byte sequence
 * that is not a C1 control (U+0080..U+009F); 0 for a byte to escape. */
static size_t shown_as_is(const unsigned char *s, size_t n)
{
    if (s[0] >= 0x20 && s[0] < 0x7f)
        return 1;
    size_t len = s[0] >= 0xc2 && s[0] <= 0xdf   ? 2
                 : s[0] >= 0xe0 && s[0] <= 0xef ? 3
                 : s[0] >= 0xf0 && s[0] <= 0xf4 ? 4
                                                : 0;
    if (len == 0 || len > n || (s[0] == 0xc2 && s[1] < 0xa0))
        return 0;
    for (size_t k = 1; k < len; k++)
        if ((s[k] & 0xc0) != 0x80)
            return 0;
    return len;
}

size_t cli_escape(char *dst, size_t cap, const char *src)
{
    const unsigned char *s = (const unsigned char *)src;
    size_t n = strlen(src), used = 0;
    if (cap == 0)
        return 0;
    for (size_t k = 0; k < n;) {
        size_t len = shown_as_is(s + k, n - k);
        char esc[8];
        const char *piece = esc;
        size_t plen;
        if (len) {
            piece = (const char *)s + k;
            plen = len;
        } else {
            plen = s[k] == '\n' ? (size_t)snprintf(esc, sizeof esc, "\\n")
                   : s[k] == '\t' ? (size_t)snprintf(esc, sizeof esc, "\\t")
                   : s[k] == '\r' ? (size_t)snprintf(esc, sizeof esc, "\\r")
                                  : (size_t)snprintf(esc, sizeof esc, "\\x%02x", s[k]);
            len = 1;
        }
        if (used + plen >= cap)
            break;
        memcpy(dst + used, piece, plen);
        used += plen;
        k += len;
    }
    dst[used] = '\0';
    return used;
}

char *cli_shown(const char *name)
{
    size_t cap = 4 * strlen(name) + 1;
    char *out = malloc(cap);
    if (out)
        cli_escape(out, cap, name);
    return out;
}

void cli_err(const char *fmt, ...)
{
    char msg[4096], line[4 * sizeof msg + 2];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    size_t len = cli_escape(line, sizeof line - 1, msg);
    line[len++] = '\n';
    fwrite(line, 1, len, stderr);
    fflush(stderr);
}
