/* aalab health */
#include <string.h>

#include "commands.h"

#include "../exit_codes.h"
#include "view_util.h"

/* The daemon's "tcp" is how this request came, which on the socket is always false: it is
 * printed as request_over_tcp, beside tcp_listener (whether the dashboard is served at all). */
void health_print(FILE *out, const json_t *resp, bool csv)
{
    json_t *shown = json_object();
    const char *key;
    json_t *v;
    json_object_foreach((json_t *)resp, key, v)
    {
        json_object_set(shown, strcmp(key, "tcp") ? key : "request_over_tcp", v);
    }
    print_flat_as(out, shown ? shown : resp, csv);
    json_decref(shown);
}

int cmd_health(cli_session *s)
{
    return cli_show(s, "GET", "/v1/health", NULL, health_print);
}
