#include "http_refusal.h"

#include <stdio.h>
#include <sys/socket.h>
#include <unistd.h>

void http_refuse(int fd, proto_wire_error e, const char *message)
{
    const proto_wire_row *row = proto_wire_row_of(e);
    int status = row->status, retry_after = row->retry_after;
    const char *code = row->code;
    char body[512], head[256], ra[32] = "";
    int bl =
        snprintf(body, sizeof body,
                 "{\"error\":{\"code\":\"%s\",\"message\":\"%s\",\"field\":\"\"}}", code, message);
    if (bl < 0 || bl >= (int)sizeof body)
        bl = 0;
    if (retry_after > 0)
        snprintf(ra, sizeof ra, "Retry-After: %d\r\n", retry_after);
    int hl = snprintf(head, sizeof head,
                      "HTTP/1.1 %d %s\r\nContent-Type: application/json\r\nContent-Length: %d\r\n"
                      "%sConnection: close\r\n\r\n",
                      status, proto_http_reason(status), bl, ra);
    char out[768];
    int n = snprintf(out, sizeof out, "%.*s%.*s", hl, head, bl, body);
    if (n > 0)
        (void)!send(fd, out, (size_t)(n < (int)sizeof out ? n : (int)sizeof out - 1),
                    MSG_DONTWAIT | MSG_NOSIGNAL);
    /* No read of the request: a peer we refuse gets nothing more from us. */
    shutdown(fd, SHUT_WR);
    close(fd);
}
