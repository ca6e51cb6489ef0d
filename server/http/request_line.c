#include "request_line.h"

#include <string.h>

static int is_space(char c)
{
    return c == ' ' || c == '\t';
}

/* A method is an RFC 9110 token: visible ASCII except separators. */
static int is_tchar(unsigned char c)
{
    return c > 32 && c < 127 && !strchr("\"(),/:;<=>?@[\\]{}", c);
}

request_line_verdict request_line_check(const char *buf, size_t n)
{
    size_t i = 0;
    while (i < n && (buf[i] == '\r' || buf[i] == '\n')) /* empty lines before it are allowed */
        i++;
    const char *line = buf + i;
    const char *nl = memchr(line, '\n', n - i);
    if (!nl)
        return REQUEST_LINE_INCOMPLETE;
    size_t len = (size_t)(nl - line);
    if (len && line[len - 1] == '\r')
        len--;
    /* Words separated by runs of blanks: METHOD TARGET VERSION (a target with blanks in it is
     * libmicrohttpd's to judge, so only the first and the last word are looked at). */
    size_t words = 0;
    for (size_t p = 0; p < len;) {
        while (p < len && is_space(line[p]))
            p++;
        if (p == len)
            break;
        size_t start = p;
        while (p < len && !is_space(line[p]))
            p++;
        if (words++ == 0) {
            for (size_t k = start; k < p; k++)
                if (!is_tchar((unsigned char)line[k]))
                    return REQUEST_LINE_BAD;
        }
    }
    if (words < 3)
        return REQUEST_LINE_BAD; /* also HTTP/0.9's "GET /path": no version */
    size_t e = len;
    while (e && is_space(line[e - 1]))
        e--;
    size_t st = e;
    while (st && !is_space(line[st - 1]))
        st--;
    const char *v = line + st;
    size_t vl = e - st;
    if (vl != 8 || memcmp(v, "HTTP/", 5) || v[6] != '.' || v[5] < '0' || v[5] > '9' || v[7] < '0' ||
        v[7] > '9')
        return REQUEST_LINE_BAD;
    return v[5] == '1' ? REQUEST_LINE_OK : REQUEST_LINE_BAD_VERSION;
}
