#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "exit_codes.h"
#include "socket_path.h"

#include <sys/stat.h>
#include <unistd.h>

int cli_show(cli_session *s, const char *method, const char *path, const json_t *body,
             cli_view view)
{
    json_t *resp;
    int code = cli_call(s, method, path, body, &resp);
    if (code != EXIT_OK)
        return code;
    if (s->args->json)
        cli_print_json(s->out, resp);
    else
        view(s->out, resp, s->args->csv);
    json_decref(resp);
    return EXIT_OK;
}

void cli_print_json(FILE *out, const json_t *doc)
{
    json_dumpf(doc, out, JSON_INDENT(2) | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(17));
    fputc('\n', out);
}

void cli_print_error(FILE *err, long status, const char *body)
{
    json_t *doc = body ? json_loads(body, JSON_DECODE_ANY, NULL) : NULL;
    const char *code = NULL, *message = NULL, *field = NULL;
    json_t *e = json_object_get(doc, "error");
    if (json_is_object(e)) {
        code = json_string_value(json_object_get(e, "code"));
        message = json_string_value(json_object_get(e, "message"));
        field = json_string_value(json_object_get(e, "field"));
    }
    fprintf(err, "aalab: server answered %ld", status);
    if (code)
        fprintf(err, " %s", code);
    if (message)
        fprintf(err, ": %s", message);
    else if (!e && body && *body)
        fprintf(err, ": %.200s", body);
    if (field && *field)
        fprintf(err, " (field %s)", field);
    fputc('\n', err);
    json_decref(doc);
}

void cli_print_no_daemon(FILE *err, const char *socket, const char *tried)
{
    struct stat st;
    const char *why = "nothing accepts connections there (a stale socket?)";
    if (stat(socket, &st) != 0)
        why = errno == EACCES ? "permission denied on its directory" : "no such socket";
    else if (!S_ISSOCK(st.st_mode))
        why = "that file is not a socket";
    else if (access(socket, R_OK | W_OK) != 0)
        why = "permission denied (the shared daemon's socket is for the aalab group)";
    fprintf(err,
            "aalab: cannot reach the daemon at %s: %s\n"
            "aalab: socket paths tried: %s\n"
            "aalab: start a daemon of your own with 'aalabd' (it listens on\n"
            "       $XDG_RUNTIME_DIR/aalab/aalabd.sock), start the shared one with\n"
            "       'systemctl start aalabd.socket' (/run/aalab/aalabd.sock), or give its\n"
            "       path with --socket PATH or $AALAB_SOCKET\n",
            socket, why, tried);
}

static int exchange(cli_session *s, const char *method, const char *path, const json_t *body,
                    http_response *resp)
{
    char *text = NULL;
    if (body) {
        text = json_dumps(body, JSON_COMPACT | JSON_REAL_PRECISION(17));
        if (!text) {
            fprintf(s->err, "aalab: cannot encode the request\n");
            return EXIT_USAGE;
        }
    }
    char err[512];
    int rc =
        http_request(s->http, method, path, text, text ? strlen(text) : 0, resp, err, sizeof err);
    free(text);
    if (rc == HTTP_NO_DAEMON) {
        char tried[1024];
        socket_path_tried(s->args->socket_path, tried, sizeof tried);
        cli_print_no_daemon(s->err, http_client_socket(s->http), tried);
        return EXIT_NO_CONNECT;
    }
    if (rc) {
        fprintf(s->err, "aalab: cannot reach the daemon at %s\n", err);
        return EXIT_NO_CONNECT;
    }
    int code = exit_code_for_status(resp->status);
    if (code != EXIT_OK) {
        cli_print_error(s->err, resp->status, resp->body);
        if (resp->retry_after > 0)
            fprintf(s->err, "aalab: the daemon asks to retry after %ld s\n", resp->retry_after);
        if (s->args->json) { /* scripts get the error document on stdout too */
            json_t *doc = json_loads(resp->body, JSON_DECODE_ANY, NULL);
            if (doc)
                cli_print_json(s->out, doc);
            json_decref(doc);
        }
        http_response_free(resp);
    }
    return code;
}

int cli_call(cli_session *s, const char *method, const char *path, const json_t *body,
             json_t **result)
{
    if (result)
        *result = NULL;
    http_response resp;
    int code = exchange(s, method, path, body, &resp);
    if (code != EXIT_OK)
        return code;
    if (result) {
        json_error_t jerr;
        *result =
            resp.len ? json_loadb(resp.body, resp.len, JSON_DECODE_ANY, &jerr) : json_object();
        if (!*result) {
            fprintf(s->err, "aalab: the daemon sent invalid JSON (%s)\n", jerr.text);
            code = EXIT_SERVER_5XX;
        }
    }
    http_response_free(&resp);
    return code;
}

int cli_call_raw(cli_session *s, const char *method, const char *path, http_response *resp)
{
    return exchange(s, method, path, NULL, resp);
}

int cli_call_raw_body(cli_session *s, const char *method, const char *path, const json_t *body,
                      http_response *resp)
{
    return exchange(s, method, path, body, resp);
}

const char *fmt_number(char *buf, size_t cap, const json_t *v, int decimals)
{
    if (json_is_real(v) && decimals == FMT_FULL && isfinite(json_real_value(v))) {
        for (int digits = 6; digits <= 17; digits++) {
            snprintf(buf, cap, "%.*g", digits, json_real_value(v));
            if (strtod(buf, NULL) == json_real_value(v))
                break;
        }
        return buf;
    }
    if (json_is_integer(v) && decimals <= 0)
        snprintf(buf, cap, "%lld", (long long)json_integer_value(v));
    else if (json_is_integer(v)) /* same column format whether the server wrote 2 or 2.0 */
        snprintf(buf, cap, "%.*f", decimals, (double)json_integer_value(v));
    else if (json_is_real(v) && isfinite(json_real_value(v)))
        snprintf(buf, cap, "%.*f", decimals, json_real_value(v));
    else if (json_is_string(v))
        snprintf(buf, cap, "%s", json_string_value(v));
    else
        snprintf(buf, cap, "-");
    return buf;
}

const char *fmt_string(const json_t *v)
{
    return json_is_string(v) ? json_string_value(v) : NULL;
}

char *url_escape_segment(const char *s)
{
    size_t n = strlen(s);
    char *out = malloc(3 * n + 1);
    if (!out)
        return NULL;
    char *o = out;
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if ((*p >= 'A' && *p <= 'Z') || (*p >= 'a' && *p <= 'z') || (*p >= '0' && *p <= '9') ||
            *p == '-' || *p == '_' || *p == '.' || *p == '~')
            *o++ = (char)*p;
        else
            o += sprintf(o, "%%%02X", *p);
    }
    *o = '\0';
    return out;
}
