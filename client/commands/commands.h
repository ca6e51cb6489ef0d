/* One file per command. cmd_* run a command and return its exit code; the *_request builders and
 * *_print formatters are pure so the unit tests can check them without a daemon. */
#ifndef AALAB_COMMANDS_H
#define AALAB_COMMANDS_H

#include <stdbool.h>
#include <stdio.h>

#include <jansson.h>

#include "../args.h"
#include "../cli.h"

int cmd_eval(cli_session *s);
int cmd_presets(cli_session *s);
int cmd_optimize(cli_session *s);
int cmd_submit(cli_session *s);
int cmd_jobs(cli_session *s);
int cmd_job(cli_session *s);
int cmd_cancel(cli_session *s);
int cmd_render(cli_session *s);
int cmd_predict(cli_session *s);
int cmd_analyze(cli_session *s);
int cmd_export(cli_session *s);
int cmd_health(cli_session *s);
int cmd_filters(cli_session *s);
int cmd_acuity(cli_session *s);
int cmd_enumerate(cli_session *s);
int cmd_token(cli_session *s);
int cmd_wait(cli_session *s);
int cmd_convert(cli_session *s);
void cmd_help(FILE *out, const char *command); /* command NULL: overview */

/* Request bodies. Return 0 with *req (new reference), or -1 with err (a usage error). */
int eval_request(const cli_args *a, json_t **req, char *err, size_t errcap);
int optimize_request(const cli_args *a, json_t **req, char *err, size_t errcap);
int render_request(const cli_args *a, json_t **req, char *err, size_t errcap);
/* predict: --pattern A,B,... as "patterns", the scene by name (an object with --angle). */
int predict_request(const cli_args *a, json_t **req, char *err, size_t errcap);
/* analyze: the pattern as eval takes it, --metrics a,b as "metrics", --radius, --pcf-bins. */
int analyze_request(const cli_args *a, json_t **req, char *err, size_t errcap);
/* The figures as "key  value" lines, then the radial spectrum; with csv, the radial spectrum
 * (annulus,frequencies,power,anisotropy_db) as CSV. */
void analyze_print(FILE *out, const json_t *resp, bool csv);
/* submit: the spec file (or stdin) as it is, checked to be an object with a kind. */
int submit_request(const cli_args *a, json_t **req, char *err, size_t errcap);
/* --filter NAME[:B=..,C=..] | JSON; --acuity NAME | FILE.json | JSON. */
int filter_argument(const char *arg, json_t **filter, char *err, size_t errcap);
int acuity_argument(const char *arg, json_t **acuity, char *err, size_t errcap);
int angles_argument(const char *arg, json_t **angles, char *err, size_t errcap);

/* After POST /v1/jobs (resp stolen): prints the id, or follows the job with --wait. */
int job_submitted(cli_session *s, json_t *resp);
/* Builds a job spec with build(), POSTs it to /v1/jobs and reports it (waits with --wait);
 * name is the command for messages. */
typedef int (*job_request_builder)(const cli_args *a, json_t **req, char *err, size_t errcap);
int job_submit_built(cli_session *s, const char *name, job_request_builder build);
/* Polls GET /v1/jobs/ID until it ends (a bar on stderr when it is a terminal), then prints the
 * job as `aalab job` does (nothing with -q); exit 0 if done, 5 if failed/cancelled/interrupted. */
int job_wait(cli_session *s, const char *id);

/* convert: pattern (the wire form, not a job reference) in an export format, written by the
 * codec as the daemon's POST /v1/patterns/export writes it. 0 with *text (malloc'd, *len
 * bytes), or -1 with err. */
int convert_text(const json_t *pattern, const char *format, char **text, size_t *len, char *err,
                 size_t errcap);

/* Writes len bytes to path, or to out when path is NULL or "-"; returns an exit code. */
int write_output(FILE *out, FILE *err, const char *path, const char *data, size_t len);
/* write_output to the command's -o (or stdout), then "wrote FILE (N bytes)" on stderr for a file
 * without --json (export, convert). Returns the exit code. */
int write_command_output(cli_session *s, const char *data, size_t len);

/* Human-readable views of the daemon's answers; with csv, their table as RFC 4180 CSV (a
 * "key  value" listing as two columns key,value). */
void eval_print(FILE *out, const json_t *resp, bool detail, bool csv);
void presets_print(FILE *out, const json_t *resp, bool csv);
void jobs_print(FILE *out, const json_t *resp, bool csv);
/* One job: its state, its kind's view of the result (views/job_views.h), its best pattern
 * and a trace summary; with csv only the kind's main table. */
void job_print(FILE *out, const json_t *job, bool csv);
/* The same with every sample of the best pattern (aalab job ID --pattern); job_print gives a
 * one-line summary of it. */
void job_print_full(FILE *out, const json_t *job, bool csv);
/* aalab job ID --trace: the trace table, or a sentence saying the job has none. */
void job_trace_print(FILE *out, const json_t *job, bool csv);
void job_print_with(FILE *out, const json_t *job, bool csv, bool full_pattern);
/* The query of GET /v1/jobs for --state, --kind and --limit ("" when none; values escaped). */
int jobs_query(const cli_args *a, char *buf, size_t cap);
/* The line for DELETE /v1/jobs/ID's answer. */
void cancel_print(FILE *out, const char *id, const json_t *resp);
void render_print(FILE *out, const json_t *resp);
/* One row per pattern (predicted RMSE, locked share, costliest angle), then the scene's edges. */
void predict_print(FILE *out, const json_t *resp, bool csv);
/* Rows whose pattern the daemon names not (a job's, a file's) take the argument as typed,
 * "job:8", instead of a row number. */
void predict_name_rows(json_t *resp, const char *pattern_list);
void health_print(FILE *out, const json_t *resp, bool csv);
void filters_print(FILE *out, const json_t *resp, bool csv);
void acuity_print(FILE *out, const json_t *resp, bool csv);
void enumerate_print(FILE *out, const json_t *resp, bool csv);
/* The new token, and the dashboard URL carrying it when dashboard is not NULL. */
void token_issued_print(FILE *out, const json_t *resp, const char *dashboard);
void tokens_print(FILE *out, const json_t *resp, bool csv);
/* "[#######.....]  58%  best E2 0.3712" into buf, width columns of bar. */
void progress_line(char *buf, size_t cap, double fraction, const json_t *job, int width);

#endif
