/* Following a job: the --wait loop shared by optimize and submit, and `aalab wait ID`. */
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include <math.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../exit_codes.h"
#include "../views/job_views.h"
#include "view_util.h"

void progress_line(char *buf, size_t cap, double fraction, const json_t *job, int width)
{
    if (!(fraction >= 0))
        fraction = 0;
    if (fraction > 1)
        fraction = 1;
    if (width < 1 || width > 200)
        width = 30;
    char bar[201];
    int filled = (int)lround(fraction * width);
    for (int i = 0; i < width; i++)
        bar[i] = i < filled ? '#' : '.';
    bar[width] = '\0';
    const json_t *state = json_object_get(job, "state");
    const json_t *e2 = job_best_e2(job);
    /* A paused job is running but waits for another user's job to take its turn. */
    bool paused = json_is_true(json_object_get(job, "paused"));
    int n = snprintf(buf, cap, "[%s] %3.0f%%  %s%s", bar, 100 * fraction,
                     json_is_string(state) ? json_string_value(state) : "",
                     paused ? " (paused: another user's turn)" : "");
    if (e2 && n > 0 && (size_t)n < cap)
        snprintf(buf + n, cap - (size_t)n, "  best E2 %.6f", json_number_value(e2));
}

static bool finished(const char *state)
{
    return strcmp(state, "done") == 0 || strcmp(state, "failed") == 0 ||
           strcmp(state, "cancelled") == 0 || strcmp(state, "interrupted") == 0;
}

static void sleep_seconds(double s)
{
    struct timespec ts = {(time_t)s, (long)((s - floor(s)) * 1e9)};
    nanosleep(&ts, NULL);
}

/* The finished job as `aalab job` shows it; nothing with -q (the id is already printed, the
 * exit code says how the job ended). */
static void print_finished(cli_session *s, const json_t *job)
{
    if (s->args->quiet)
        return;
    if (s->args->json)
        cli_print_json(s->out, job);
    else if (s->args->trace)
        job_trace_print(s->out, job, s->args->csv);
    else
        job_print_with(s->out, job, s->args->csv, s->args->full_pattern);
}

/* Polls GET /v1/jobs/ID until the job ends; a bar on stderr when stderr is a terminal. */
int job_wait(cli_session *s, const char *id)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/jobs/%s", id);
    bool tty = !s->args->quiet && isatty(fileno(s->err));
    json_t *job = NULL;
    const char *state = "";
    for (;;) {
        json_decref(job);
        int code = cli_call(s, "GET", path, NULL, &job);
        if (code != EXIT_OK)
            return code;
        state = json_string_value(json_object_get(job, "state"));
        if (!state)
            state = "";
        if (tty) {
            char line[160];
            progress_line(line, sizeof line, json_number_value(json_object_get(job, "progress")),
                          job, 30);
            fprintf(s->err, "\r%-78s", line);
            fflush(s->err);
        }
        if (finished(state))
            break;
        sleep_seconds(s->args->poll_s);
    }
    if (tty)
        fputc('\n', s->err);
    print_finished(s, job);
    int code = strcmp(state, "done") == 0 ? EXIT_OK : EXIT_JOB_FAILED;
    if (code != EXIT_OK)
        fprintf(s->err, "aalab: job %s ended %s\n", id, state);
    json_decref(job);
    return code;
}

int job_submitted(cli_session *s, json_t *resp)
{
    json_t *id = json_object_get(resp, "id");
    char job_id[80];
    if (json_is_integer(id))
        snprintf(job_id, sizeof job_id, "%lld", (long long)json_integer_value(id));
    else if (json_is_string(id) && job_id_valid(json_string_value(id)))
        snprintf(job_id, sizeof job_id, "%s", json_string_value(id));
    else {
        fprintf(s->err, "aalab: the daemon's answer has no valid job id\n");
        json_decref(resp);
        return EXIT_SERVER_5XX;
    }
    if (s->args->quiet) { /* for ID=$(aalab optimize -q ...) */
        fprintf(s->out, "%s\n", job_id);
        fflush(s->out);
    }
    if (s->args->wait) {
        json_decref(resp);
        return job_wait(s, job_id);
    }
    if (s->args->json && !s->args->quiet)
        cli_print_json(s->out, resp);
    else if (!s->args->quiet)
        fprintf(s->out, "job %s queued\n", job_id);
    json_decref(resp);
    return EXIT_OK;
}

int job_submit_built(cli_session *s, const char *name, job_request_builder build)
{
    json_t *req, *resp;
    char err[512];
    if (build(s->args, &req, err, sizeof err)) {
        fprintf(s->err, "aalab %s: %s\n", name, err);
        return EXIT_USAGE;
    }
    int code = cli_call(s, "POST", "/v1/jobs", req, &resp);
    json_decref(req);
    if (code != EXIT_OK)
        return code;
    return job_submitted(s, resp);
}
