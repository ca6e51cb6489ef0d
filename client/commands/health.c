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
    return cli_show(s, "GET", "/v1/health", NULL, health_print);
}
