/* aalab jobs | aalab job ID | aalab cancel ID */
#include "commands.h"

#include <stdio.h>

#include "../exit_codes.h"
#include "../table.h"
#include "view_util.h"

static const json_t *first_of(const json_t *obj, const char *a, const char *b)
{
    const json_t *v = json_object_get(obj, a);
    return v ? v : json_object_get(obj, b);
}

void jobs_print(FILE *out, const json_t *resp)
{
    const char *headers[] = {"id", "kind", "state", "progress", "owner", "best_e2", "created"};
    table *t = table_new(7, headers);
    if (!t)
        return;
    size_t i;
    json_t *job;
    json_array_foreach(list_member(resp, "jobs"), i, job)
    {
        char id[32], owner[32], progress[32], e2[32], created[64];
        const json_t *p = json_object_get(job, "progress");
        if (json_is_number(p))
            snprintf(progress, sizeof progress, "%.0f%%", 100.0 * json_number_value(p));
        else
            snprintf(progress, sizeof progress, "-");
        const char *cells[] = {
            fmt_number(id, sizeof id, json_object_get(job, "id"), 0),
            fmt_string(json_object_get(job, "kind")),
            fmt_string(json_object_get(job, "state")),
            progress,
            fmt_number(owner, sizeof owner, first_of(job, "owner", "owner_uid"), 0),
            fmt_number(e2, sizeof e2, job_best_e2(job), 6),
            fmt_time(created, sizeof created, first_of(job, "created", "created_at"))};
        table_add_row(t, cells);
    }
    table_print(t, out);
    table_free(t);
}

void job_print(FILE *out, const json_t *job)
{
    json_t *copy = json_deep_copy(job);
    /* The trace is long: summarise it instead of listing it. */
    const json_t *trace = json_object_get(job, "trace");
    json_object_del(copy, "trace");
    print_flat(out, copy);
    json_decref(copy);
    if (json_is_array(trace) && json_array_size(trace) > 0) {
        const json_t *last = json_array_get(trace, json_array_size(trace) - 1);
        char sec[32], e2[32];
        fprintf(out, "trace  %zu points, last at %s s with E2 %s\n", json_array_size(trace),
                fmt_number(sec, sizeof sec, json_object_get(last, "seconds"), 2),
                fmt_number(e2, sizeof e2, json_object_get(last, "best_e2"), 6));
    }
}

int cmd_jobs(cli_session *s)
{
    json_t *resp;
    int code = cli_call(s, "GET", "/v1/jobs", NULL, &resp);
    if (code != EXIT_OK)
        return code;
    if (s->args->json)
        cli_print_json(s->out, resp);
    else
        jobs_print(s->out, resp);
    json_decref(resp);
    return EXIT_OK;
}

static int job_call(cli_session *s, const char *method)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/jobs/%s", s->args->target); /* [A-Za-z0-9_-] (args.c) */
    json_t *resp;
    int code = cli_call(s, method, path, NULL, &resp);
    if (code != EXIT_OK)
        return code;
    if (s->args->json)
        cli_print_json(s->out, resp);
    else if (method[0] == 'D')
        fprintf(s->out, "job %s: %s\n", s->args->target,
                json_is_string(json_object_get(resp, "state"))
                    ? json_string_value(json_object_get(resp, "state"))
                    : "cancel requested");
    else
        job_print(s->out, resp);
    json_decref(resp);
    return EXIT_OK;
}

int cmd_job(cli_session *s)
{
    return job_call(s, "GET");
}

int cmd_cancel(cli_session *s)
{
    return job_call(s, "DELETE");
}
