/* aalab token [--label TEXT] | aalab token list | aalab token revoke ID: bearer tokens for the
 * daemon's TCP listener (the dashboard), issued over the Unix socket to the calling user. */
#include "commands.h"

#include <stdio.h>
#include <string.h>

#include "../exit_codes.h"
#include "../table.h"
#include "view_util.h"

void token_issued_print(FILE *out, const json_t *resp, const char *dashboard)
{
    const char *token = fmt_string(json_object_get(resp, "token"));
    char id[32];
    fprintf(out, "token %s (id %s; shown once, revoke with 'aalab token revoke %s')\n", token,
            fmt_number(id, sizeof id, json_object_get(resp, "id"), 0), id);
    if (dashboard)
        fprintf(out, "dashboard: %s#token=%s\n", dashboard, token);
}

void tokens_print(FILE *out, const json_t *resp, bool csv)
{
    const char *headers[] = {"id", "uid", "label", "created"};
    table *t = table_new(4, headers);
    if (!t)
        return;
    size_t i;
    json_t *tok;
    json_array_foreach(list_member(resp, "tokens"), i, tok)
    {
        char id[32], uid[32], created[64];
        const char *cells[] = {fmt_number(id, sizeof id, json_object_get(tok, "id"), 0),
                               fmt_number(uid, sizeof uid, json_object_get(tok, "uid"), 0),
                               fmt_string(json_object_get(tok, "label")),
                               fmt_time(created, sizeof created, json_object_get(tok, "created"))};
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
}

static int token_issue(cli_session *s)
{
    json_t *body = json_object();
    if (s->args->label)
        json_object_set_new(body, "label", json_string(s->args->label));
    json_t *resp = NULL;
    int code = cli_call(s, "POST", "/v1/tokens", body, &resp);
    json_decref(body);
    if (code != EXIT_OK)
        return code;
    if (s->args->json) {
        cli_print_json(s->out, resp);
    } else {
        /* The dashboard URL only if the daemon reports a TCP listener. */
        json_t *health = NULL;
        const char *dashboard = NULL;
        if (cli_call(s, "GET", "/v1/health", NULL, &health) == EXIT_OK)
            dashboard = json_string_value(json_object_get(health, "dashboard"));
        token_issued_print(s->out, resp, dashboard);
        json_decref(health);
    }
    json_decref(resp);
    return EXIT_OK;
}

int cmd_token(cli_session *s)
{
    const char *sub = s->args->target;
    if (!sub)
        return token_issue(s);
    json_t *resp = NULL;
    int code;
    if (!strcmp(sub, "list")) {
        code = cli_call(s, "GET", "/v1/tokens", NULL, &resp);
        if (code == EXIT_OK && !s->args->json)
            tokens_print(s->out, resp, s->args->csv);
    } else {
        char path[128];
        snprintf(path, sizeof path, "/v1/tokens/%s", s->args->target2); /* checked in args.c */
        code = cli_call(s, "DELETE", path, NULL, &resp);
        if (code == EXIT_OK && !s->args->json)
            fprintf(s->out, "token %s revoked\n", s->args->target2);
    }
    if (code == EXIT_OK && s->args->json)
        cli_print_json(s->out, resp);
    json_decref(resp);
    return code;
}
