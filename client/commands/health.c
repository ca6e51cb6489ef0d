/* aalab health */
#include "commands.h"

#include "../exit_codes.h"
#include "view_util.h"

void health_print(FILE *out, const json_t *resp, bool csv)
{
    print_flat_as(out, resp, csv);
}

int cmd_health(cli_session *s)
{
    json_t *resp;
    int code = cli_call(s, "GET", "/v1/health", NULL, &resp);
    if (code != EXIT_OK)
        return code;
    if (s->args->json)
        cli_print_json(s->out, resp);
    else
        health_print(s->out, resp, s->args->csv);
    json_decref(resp);
    return EXIT_OK;
}
