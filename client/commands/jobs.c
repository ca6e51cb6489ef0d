/* aalab jobs [--state S] [--kind K] [--limit N] | aalab job ID [--trace] | aalab cancel ID */
#include "commands.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../exit_codes.h"
#include "../table.h"
#include "../views/job_views.h"
#include "../views/view_kv.h"
#include "../views/view_temporal.h"
#include "view_util.h"

void jobs_print(FILE *out, const json_t *resp, bool csv)
{
    const char *headers[] = {"id",    "kind",    "state", "progress", "family",
                             "label", "best_e2", "owner", "created"};
    table *t = table_new(9, headers);
    if (!t)
        return;
    size_t i;
    json_t *job;
    json_array_foreach(json_object_get(resp, "jobs"), i, job)
    {
        char id[32], owner[32], progress[32], e2[32], created[64];
        const json_t *p = json_object_get(job, "progress");
        if (json_is_number(p) && csv) /* a fraction, as the API has it */
            fmt_number(progress, sizeof progress, p, FMT_FULL);
        else if (json_is_number(p))
            snprintf(progress, sizeof progress, "%.0f%%", 100.0 * json_number_value(p));
        else
            snprintf(progress, sizeof progress, "-");
        const char *cells[] = {
            fmt_number(id, sizeof id, json_object_get(job, "id"), 0),
            fmt_string(json_object_get(job, "kind")),
            fmt_string(json_object_get(job, "state")),
            progress,
            fmt_string(json_object_get(job, "family")),
            fmt_string(json_object_get(job, "label")),
            fmt_number(e2, sizeof e2, job_best_e2(job), fmt_decimals(csv, 6)),
            fmt_number(owner, sizeof owner, json_object_get(job, "owner_uid"), 0),
            fmt_time(created, sizeof created, json_object_get(job, "created"))};
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
}

/* One submitted setting's value, short: a preset by its name, a pattern by its size, a long
 * list or object by its count. */
static void setting_text(char *buf, size_t cap, const json_t *v)
{
    const json_t *preset = json_object_get(v, "preset");
    const json_t *kernels = json_object_get(v, "kernels");
    if (json_is_string(preset) && json_object_size(v) == 1) {
        snprintf(buf, cap, "%s", json_string_value(preset));
        return;
    }
    if (json_is_array(kernels)) {
        snprintf(buf, cap, "pattern, %zu kernels", json_array_size(kernels));
        return;
    }
    if (json_is_array(json_object_get(v, "mirrored"))) {
        snprintf(buf, cap, "mirrored pattern, %zu samples",
                 json_array_size(json_object_get(v, "mirrored")));
        return;
    }
    char *text = json_dumps(v, JSON_COMPACT | JSON_ENCODE_ANY | JSON_REAL_PRECISION(6));
    if (text && strlen(text) <= 80)
        snprintf(buf, cap, "%s", text);
    else if (json_is_array(v))
        snprintf(buf, cap, "[%zu items]", json_array_size(v));
    else
        snprintf(buf, cap, "{%zu settings}", json_object_size(v));
    free(text);
}

/* "family P(16,16,4), seeds 2, max_seconds 2": the spec as submitted, less its kind (what it
 * left out took the daemon's defaults). */
static void settings_line(char *buf, size_t cap, const json_t *spec)
{
    size_t n = 0;
    buf[0] = '\0';
    const char *key;
    const json_t *v;
    json_object_foreach((json_t *)spec, key, v)
    {
        if (!strcmp(key, "kind") || n + 1 >= cap)
            continue;
        char value[96];
        setting_text(value, sizeof value, v);
        if (json_is_string(v))
            snprintf(value, sizeof value, "%s", json_string_value(v));
        int w = snprintf(buf + n, cap - n, "%s%s %s", n ? ", " : "", key, value);
        n = w < 0 ? n : n + (size_t)w < cap ? n + (size_t)w : cap - 1;
    }
    if (!n)
        snprintf(buf, cap, "defaults");
}

/* "queued 0.01 s, ran 2.05 s, paused 0.00 s": what is known of the job's times. */
static void timings_line(char *buf, size_t cap, const json_t *job)
{
    const json_t *c = json_object_get(job, "created"), *s = json_object_get(job, "started"),
                 *f = json_object_get(job, "finished"), *p = json_object_get(job, "paused_seconds");
    size_t n = 0;
    buf[0] = '\0';
    if (json_is_number(c) && json_is_number(s))
        n += (size_t)snprintf(buf + n, cap - n, "queued %.2f s",
                              json_number_value(s) - json_number_value(c));
    if (json_is_number(s) && json_is_number(f) && n < cap)
        n += (size_t)snprintf(buf + n, cap - n, "%sran %.2f s", n ? ", " : "",
                              json_number_value(f) - json_number_value(s));
    if (json_is_number(p) && n < cap)
        snprintf(buf + n, cap - n, "%spaused %.2f s", n ? ", " : "", json_number_value(p));
    if (!buf[0])
        snprintf(buf, cap, "not started");
}

/* The job's own members (job.json) as "key  value" lines: what the views below do not show,
 * then its submitted settings and its timings (issue 34: a job is a complete record). */
static void job_head(FILE *out, const json_t *job)
{
    static const char *const SHOWN_ELSEWHERE[] = {"result", "spec", "trace", "best", "error"};
    json_t *copy = json_deep_copy(job);
    for (size_t i = 0; i < sizeof SHOWN_ELSEWHERE / sizeof SHOWN_ELSEWHERE[0]; i++)
        json_object_del(copy, SHOWN_ELSEWHERE[i]);
    const json_t *progress = json_object_get(job, "progress");
    if (json_is_number(progress)) { /* a fraction on the wire, a percentage for people */
        char pct[96];
        snprintf(pct, sizeof pct, "%.0f%%", 100.0 * json_number_value(progress));
        /* A job that ended early: how long it ran says more than its 0 % (issue 34). */
        const char *state = json_string_value(json_object_get(job, "state"));
        const json_t *started = json_object_get(job, "started");
        const json_t *finished = json_object_get(job, "finished");
        if (state && strcmp(state, "done") != 0 && json_is_number(started) &&
            json_is_number(finished))
            snprintf(pct + strlen(pct), sizeof pct - strlen(pct), " (%s after %.1f s)", state,
                     json_number_value(finished) - json_number_value(started));
        json_object_set_new(copy, "progress", json_string(pct));
    }
    char line[512];
    const json_t *spec = json_object_get(job, "spec");
    if (json_is_object(spec)) {
        settings_line(line, sizeof line, spec);
        json_object_set_new(copy, "settings", json_string(line));
    }
    timings_line(line, sizeof line, job);
    json_object_del(copy, "paused_seconds");
    json_object_set_new(copy, "timings", json_string(line));
    print_flat(out, copy);
    json_decref(copy);
}

/* One line on the best pattern: family, cost, E2, kernel and sample counts. Its samples (1,024
 * rows for a P(16,16,4) pattern) only with --pattern. */
static void best_summary(FILE *out, const json_t *best)
{
    const json_t *pattern = json_object_get(best, "pattern");
    const json_t *kernels = json_object_get(pattern, "kernels_expanded");
    size_t samples = 0, k;
    json_t *kernel;
    json_array_foreach(kernels, k, kernel) samples += json_array_size(kernel);
    const json_t *cost = json_object_get(pattern, "cost_spp");
    if (!cost)
        cost = json_object_get(pattern, "samples_per_pixel");
    const char *form = json_string_value(json_object_get(pattern, "form"));
    char spp[32], e2[32];
    fprintf(out, "best pattern  %s, %s spp", view_str(json_object_get(pattern, "family")),
            fmt_number(spp, sizeof spp, cost, 2));
    if (form)
        fprintf(out, ", %s form, %zu kernels", form, json_array_size(kernels));
    fputc('\n', out);
    fputs("              ", out);
    if (json_is_number(json_object_get(best, "e2")))
        fprintf(out, "E2 %s, ", fmt_number(e2, sizeof e2, json_object_get(best, "e2"), 6));
    fprintf(out, "%zu samples ('aalab job ID --pattern' lists them)\n", samples);
}

void job_print_with(FILE *out, const json_t *job, bool csv, bool full_pattern)
{
    const json_t *result = json_object_get(job, "result");
    const job_view *view = job_view_find(json_string_value(json_object_get(job, "kind")));
    if (csv) {
        if (json_is_object(result))
            view->print(out, result, true);
        return;
    }
    /* A failed job's reason first, where it cannot scroll away. */
    const json_t *error = json_object_get(job, "error");
    if (error && !json_is_null(error)) {
        const char *msg = json_string_value(error);
        if (!msg && json_is_object(error))
            msg = json_string_value(json_object_get(error, "message"));
        fprintf(out, "error       %s\n", msg ? msg : "(see --json)");
    }
    job_head(out, job);
    if (json_is_object(result)) {
        fputc('\n', out);
        view->print(out, result, false);
    }
    const json_t *best = json_object_get(job, "best");
    const json_t *pattern = json_object_get(best, "pattern");
    /* An encoded pattern only (it has a form): animation's best names its pattern's family and
     * cost, which its view prints already. */
    if (json_is_object(pattern) && json_object_get(pattern, "form")) {
        fputc('\n', out);
        if (full_pattern)
            view_pattern(out, pattern, false);
        else
            best_summary(out, best);
    }
    /* temporal-optimize's best is a sequence: its offsets, the first 8 or all with --pattern. */
    if (json_is_object(json_object_get(pattern, "temporal"))) {
        fputc('\n', out);
        view_sequence(out, json_object_get(pattern, "temporal"), full_pattern);
    }
    const json_t *trace = json_object_get(job, "trace");
    if (json_array_size(trace) > 0) {
        const json_t *last = json_array_get(trace, json_array_size(trace) - 1);
        char sec[32], e2[32];
        fprintf(out, "\ntrace  %zu points, last at %s s with E2 %s ('aalab job ID --trace')\n",
                json_array_size(trace),
                fmt_number(sec, sizeof sec, json_object_get(last, "seconds"), fmt_decimals(csv, 2)),
                fmt_number(e2, sizeof e2, json_object_get(last, "best_e2"), fmt_decimals(csv, 6)));
    }
}

void job_print(FILE *out, const json_t *job, bool csv)
{
    job_print_with(out, job, csv, false);
}

void job_print_full(FILE *out, const json_t *job, bool csv)
{
    job_print_with(out, job, csv, true);
}

int jobs_query(const cli_args *a, char *buf, size_t cap)
{
    const char *names[] = {"state", "kind"};
    const char *values[] = {a->state, a->kind};
    size_t used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < 2; i++) {
        if (!values[i])
            continue;
        char *escaped = url_escape_segment(values[i]);
        if (!escaped)
            return -1;
        int n = snprintf(buf + used, cap - used, "%c%s=%s", used ? '&' : '?', names[i], escaped);
        free(escaped);
        if (n < 0 || (size_t)n >= cap - used)
            return -1;
        used += (size_t)n;
    }
    if (a->has_limit) {
        int n = snprintf(buf + used, cap - used, "%climit=%ld", used ? '&' : '?', a->limit);
        if (n < 0 || (size_t)n >= cap - used)
            return -1;
    }
    return 0;
}

int cmd_jobs(cli_session *s)
{
    char query[512], path[600];
    if (jobs_query(s->args, query, sizeof query)) {
        fprintf(s->err, "aalab jobs: filter too long\n");
        return EXIT_USAGE;
    }
    snprintf(path, sizeof path, "/v1/jobs%s", query);
    return cli_show(s, "GET", path, NULL, jobs_print);
}

void cancel_print(FILE *out, const char *id, const json_t *resp)
{
    const char *state = json_string_value(json_object_get(resp, "state"));
    if (json_is_true(json_object_get(resp, "cancel_requested")))
        fprintf(out,
                "job %s: cancelling was requested (state %s); it stops at its next check, "
                "'aalab wait %s' follows it\n",
                id, state ? state : "-", id);
    else
        fprintf(out, "job %s: %s\n", id, state ? state : "-");
}

/* aalab job ID --trace: the job's trace alone; for people, a sentence where a kind keeps none
 * (compare, animation, ... measure no best E2 against time) rather than a bare header. */
void job_trace_print(FILE *out, const json_t *job, bool csv)
{
    const json_t *trace = json_object_get(job, "trace");
    if (!csv && json_array_size(trace) == 0) {
        fprintf(out, "no trace: this %s job recorded no best E2 against run time\n",
                view_str(json_object_get(job, "kind")));
        return;
    }
    view_trace(out, trace, csv);
}

int cmd_job(cli_session *s)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/jobs/%s", s->args->target); /* [A-Za-z0-9_-] (args.c) */
    return cli_show(s, "GET", path, NULL,
                    s->args->trace          ? job_trace_print
                    : s->args->full_pattern ? job_print_full
                                            : job_print);
}

int cmd_cancel(cli_session *s)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/jobs/%s", s->args->target);
    json_t *resp;
    int code = cli_call(s, "DELETE", path, NULL, &resp);
    if (code != EXIT_OK)
        return code;
    if (s->args->json)
        cli_print_json(s->out, resp);
    else
        cancel_print(s->out, s->args->target, resp);
    json_decref(resp);
    return EXIT_OK;
}

int cmd_wait(cli_session *s)
{
    return job_wait(s, s->args->target);
}
