/* cluster_driver.h. */
#define _POSIX_C_SOURCE 200809L
#include "cluster_driver.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cluster_layout.h"
#include "cluster_trace.h"
#include "job_split.h"
#include "slurm_commands.h"

#define CANCEL_WAIT_SECONDS 60.0 /* how long a cancel waits for squeue to list none */
#define LOG_TAIL_LINES 8
#define LOG_TAIL_BYTES 4096
/* A shard out of the queue without an output is declared lost only after this many polls: a
 * shared filesystem (NFS attribute and lookup caches) may show a file written on a node a
 * little after the task has left the queue. */
#define LOST_AFTER_POLLS 3

/* One stage being run: its shards, their outputs and the part of the state that is the
 * stage's ({"shards": n, "arrays": [id...], "shard_array": [id per shard], "retried": [0|1]}). */
typedef struct stage_run {
    int stage;
    size_t n;
    char dir[CLUSTER_PATH_MAX];
    json_t **outputs;      /* outputs[i]: shard i's output once it has one */
    double *missing_since; /* monotonic time shard i was first seen gone without output, 0 */
    bool *trace_final;     /* shard i's trace was read after its output appeared */
    json_t *st;            /* borrowed from the driver's state */
} stage_run;

typedef struct driver {
    const cluster_config *cfg;
    const cluster_job *job;
    const job_split *split;
    const cluster_job_io *io;
    json_t *state;     /* owned */
    json_t *task_spec; /* the spec without "kind" */
    json_t *best;      /* best finished shard's {"pattern","e2"} so far, over all stages */
    double best_e2;
    json_t *traces;     /* trace file JSON of every shard seen, in stage then shard order */
    size_t trace_base;  /* index in traces of the current stage's shard 0 */
    size_t done_before; /* stages finished before the current one */
} driver;

static double now_unix(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

size_t cluster_state_arrays(const json_t *state, long long *ids, size_t cap)
{
    size_t count = 0, s, k;
    json_t *stage, *id;
    json_array_foreach(json_object_get(state, "stages"), s, stage)
    {
        json_array_foreach(json_object_get(stage, "arrays"), k, id)
        {
            if (count < cap)
                ids[count] = json_integer_value(id);
            count++;
        }
    }
    return count;
}

/* scancel of every array of the job, then wait (bounded) until squeue lists none of them. */
static void cancel_all(driver *d)
{
    long long ids[512];
    size_t n = cluster_state_arrays(d->state, ids, 512);
    if (n > 512)
        n = 512;
    aa_error err = {0};
    if (slurm_scancel(ids, n, &err))
        fprintf(stderr, "aalabd: job %lld: %s\n", d->job->id, err.message);
    double until = aa_monotonic_seconds() + CANCEL_WAIT_SECONDS;
    while (n && aa_monotonic_seconds() < until) {
        slurm_queued *q = NULL;
        size_t count = 0;
        int rc = slurm_squeue(ids, n, &q, &count, &err);
        free(q);
        if (!rc && count == 0)
            return;
        struct timespec t = {0, 250 * 1000 * 1000};
        nanosleep(&t, NULL);
    }
    if (n)
        fprintf(stderr,
                "aalabd: job %lld: its arrays are still listed by squeue %.0f s after "
                "scancel\n",
                d->job->id, CANCEL_WAIT_SECONDS);
}

/* Sleeps one poll interval in short steps; returns the first stop request seen. */
static cluster_stop pause_poll(driver *d)
{
    double until = aa_monotonic_seconds() + d->cfg->poll_seconds;
    for (;;) {
        cluster_stop s = d->io->check(d->io->user);
        if (s != CLUSTER_GO)
            return s;
        double left = until - aa_monotonic_seconds();
        if (left <= 0)
            return CLUSTER_GO;
        double step = left < 0.1 ? left : 0.1;
        struct timespec t = {0, (long)(step * 1e9)};
        nanosleep(&t, NULL);
    }
}

static void save(driver *d)
{
    if (d->io->save)
        d->io->save(d->io->user, d->state);
}

static void job_name(const driver *d, int stage, char *buf, size_t cap)
{
    snprintf(buf, cap, "aalab-%lld-s%d", d->job->id, stage);
}

/* sbatch --array=<array> for this stage; records the array id as the one running shards
 * idx[0..count). */
static int submit(driver *d, stage_run *r, const char *array, const size_t *idx, size_t count,
                  aa_error *err)
{
    char name[64], log[CLUSTER_PATH_MAX + 32], script[CLUSTER_PATH_MAX + 16];
    job_name(d, r->stage, name, sizeof name);
    snprintf(log, sizeof log, "%s/log-%%a.out", r->dir);
    snprintf(script, sizeof script, "%s/array.sh", r->dir);
    slurm_submit s = {.script = script,
                      .job_name = name,
                      .output = log,
                      .array = array,
                      .time_minutes = d->cfg->time_limit_minutes,
                      .partition = d->cfg->partition,
                      .extra_args = d->cfg->sbatch_args};
    long long id;
    int rc = slurm_sbatch(&s, &id, err);
    if (rc)
        return rc == AA_ENOMEM ? rc : (err->code = CLUSTER_ESLURM);
    json_array_append_new(json_object_get(r->st, "arrays"), json_integer(id));
    json_t *sa = json_object_get(r->st, "shard_array");
    for (size_t k = 0; k < count; k++)
        json_array_set_new(sa, idx[k], json_integer(id));
    save(d);
    return AA_OK;
}

/* Writes the tasks and array.sh of a new stage. */
static int write_stage(driver *d, stage_run *r, const json_t *shards, const json_t *prior,
                       aa_error *err)
{
    int rc = cluster_mkdirs(r->dir, err);
    for (size_t i = 0; !rc && i < r->n; i++) {
        char task[CLUSTER_PATH_MAX + 32], out[CLUSTER_PATH_MAX + 32], trace[CLUSTER_PATH_MAX + 32];
        cluster_shard_path(r->dir, "task", (long)i, "json", task, sizeof task);
        cluster_shard_path(r->dir, "output", (long)i, "json", out, sizeof out);
        cluster_shard_path(r->dir, "trace", (long)i, "json", trace, sizeof trace);
        /* Leftovers of an earlier daemon's run of this id (a reused state dir) must not pass
         * for this job's outputs. */
        unlink(out);
        unlink(trace);
        cluster_task t = {.job_id = d->job->id,
                          .kind = d->job->kind->name,
                          .spec = d->task_spec,
                          .stage = r->stage,
                          .shard_index = (long)i,
                          .shard = json_array_get(shards, i),
                          .prior = prior,
                          .output = out,
                          .trace = trace};
        rc = cluster_write_task(task, &t, err);
    }
    if (!rc)
        rc = cluster_write_array_script(r->dir, d->cfg->worker, err);
    return rc;
}

static json_t *read_output(driver *d, stage_run *r, size_t i);

/* One array of the shards without an output ("0-7", or "1,5" after a crash between the save
 * of a stage and its sbatch). */
static int submit_missing(driver *d, stage_run *r, aa_error *err)
{
    size_t *idx = malloc(r->n * sizeof *idx);
    char *array = malloc(r->n * 12 + 16);
    if (!idx || !array) {
        free(idx);
        free(array);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    size_t count = 0, len = 0;
    for (size_t i = 0; i < r->n; i++) {
        json_t *o = read_output(d, r, i);
        if (!o) {
            idx[count++] = i;
            len += (size_t)sprintf(array + len, "%s%zu", len ? "," : "", i);
        }
        json_decref(o);
    }
    if (count == r->n)
        sprintf(array, "0-%zu", r->n - 1);
    int rc = count ? submit(d, r, array, idx, count, err) : AA_OK;
    free(idx);
    free(array);
    return rc;
}

/* A stage saved without an array id: the daemon stopped between the save and sbatch's
 * answer. The array may exist: adopt it by its job name, else submit what has no output. */
static int adopt_or_submit(driver *d, stage_run *r, aa_error *err)
{
    char name[64];
    job_name(d, r->stage, name, sizeof name);
    long long ids[8];
    int found = slurm_squeue_by_name(name, ids, 8, err);
    if (found < 0)
        return found;
    if (found == 0)
        return submit_missing(d, r, err);
    json_t *sa = json_object_get(r->st, "shard_array");
    for (int k = 0; k < found; k++)
        json_array_append_new(json_object_get(r->st, "arrays"), json_integer(ids[k]));
    for (size_t i = 0; i < r->n; i++)
        json_array_set_new(sa, i, json_integer(ids[0]));
    fprintf(stderr, "aalabd: job %lld: adopted Slurm array %lld (%s) found by name\n", d->job->id,
            ids[0], name);
    save(d);
    return AA_OK;
}

/* Shard i's output if its file is there and is this job's; NULL otherwise. */
static json_t *read_output(driver *d, stage_run *r, size_t i)
{
    char path[CLUSTER_PATH_MAX + 32];
    cluster_shard_path(r->dir, "output", (long)i, "json", path, sizeof path);
    json_t *o = cluster_read_json(path);
    if (!o)
        return NULL; /* not there yet (the worker renames it into place whole) */
    const char *format = NULL, *host = NULL;
    json_int_t job_id = -1, stage = -1, index = -1;
    double started, finished;
    json_t *output = NULL;
    json_error_t e;
    e.text[0] = 0;
    if (json_unpack_ex(o, &e, 0, "{s:s,s:I,s:I,s:I,s:s,s:F,s:F,s:o!}", "format", &format, "job_id",
                       &job_id, "stage", &stage, "shard_index", &index, "host", &host,
                       "started_unix", &started, "finished_unix", &finished, "output", &output) ||
        strcmp(format, "aalab-shard-output/1") || job_id != d->job->id || stage != r->stage ||
        index != (json_int_t)i) {
        /* Not this shard's output: it counts as missing (and the shard, once out of the queue,
         * as failed); say why once per poll in the journal. */
        fprintf(stderr, "aalabd: job %lld: %s is not this shard's output (%s)\n", d->job->id, path,
                e.text[0] ? e.text : "format, job_id, stage or shard_index differ");
        json_decref(o);
        return NULL;
    }
    json_incref(output);
    json_decref(o);
    return output;
}

static void note_best(driver *d, int stage, const json_t *output)
{
    if (!d->split->best_of_output)
        return;
    json_t *b = d->split->best_of_output(d->job->params, stage, output);
    json_t *e2 = json_object_get(b, "e2");
    if (b && json_is_number(e2) && (!d->best || json_number_value(e2) < d->best_e2)) {
        json_decref(d->best);
        d->best = b;
        d->best_e2 = json_number_value(e2);
        return;
    }
    json_decref(b);
}

static void refresh_traces(driver *d, stage_run *r)
{
    for (size_t i = 0; i < r->n; i++) {
        if (r->trace_final[i])
            continue; /* the worker writes its last trace before its output */
        r->trace_final[i] = r->outputs[i] != NULL;
        char path[CLUSTER_PATH_MAX + 32];
        cluster_shard_path(r->dir, "trace", (long)i, "json", path, sizeof path);
        json_t *t = cluster_read_json(path);
        if (t)
            json_array_set_new(d->traces, d->trace_base + i, t);
    }
}

static void report(driver *d, stage_run *r, size_t done)
{
    /* The same per-stage shares as the local executor (job_split.h). */
    double base, span;
    job_split_stage_span(d->split, (int)d->done_before, &base, &span);
    double progress = base + span * (r->n ? (double)done / (double)r->n : 0);
    refresh_traces(d, r);
    size_t n = json_array_size(d->traces);
    json_t **list = calloc(n ? n : 1, sizeof *list);
    json_t *trace = NULL;
    if (list) {
        for (size_t i = 0; i < n; i++)
            list[i] = json_array_get(d->traces, i);
        trace = cluster_trace_merge(list, n,
                                    json_number_value(json_object_get(d->state, "submitted_unix")));
        free(list);
    }
    d->io->report(d->io->user, progress, d->best, trace);
    json_decref(trace);
}

static bool queued(const slurm_queued *q, size_t count, long long array, size_t index)
{
    for (size_t k = 0; k < count; k++)
        if (q[k].job_id == array && (q[k].index < 0 || q[k].index == (long)index))
            return true;
    return false;
}

/* Shard i left the queue without an output: resubmit it once, else fail the job. */
static int shard_lost(driver *d, stage_run *r, size_t i, char *failure, size_t cap, aa_error *err)
{
    json_t *retried = json_object_get(r->st, "retried");
    long long array = json_integer_value(json_array_get(json_object_get(r->st, "shard_array"), i));
    if (!json_integer_value(json_array_get(retried, i))) {
        fprintf(stderr,
                "aalabd: job %lld: shard %zu of stage %d (Slurm %lld_%zu) ended without "
                "output; retrying it once\n",
                d->job->id, i, r->stage, array, i);
        json_array_set_new(retried, i, json_integer(1));
        char one[32];
        snprintf(one, sizeof one, "%zu", i);
        return submit(d, r, one, &i, 1, err);
    }
    char slurm[200], log[CLUSTER_PATH_MAX + 32], tail[1024];
    slurm_describe_task(array, (long)i, slurm, sizeof slurm);
    cluster_shard_path(r->dir, "log", (long)i, "out", log, sizeof log);
    cluster_file_tail(log, LOG_TAIL_LINES, LOG_TAIL_BYTES, tail, sizeof tail);
    snprintf(failure, cap,
             "shard %zu of stage %d failed twice (Slurm job %lld_%zu: %s); last lines of %s: %s", i,
             r->stage, array, i, slurm, log, tail[0] ? tail : "(empty or missing)");
    return aa_error_set(err, CLUSTER_ESHARD, "executor",
                        "shard %zu of stage %d failed twice (%.60s)", i, r->stage, slurm);
}

/* Polls one stage until every shard has its output. */
static int run_stage(driver *d, stage_run *r, char *failure, size_t cap, aa_error *err)
{
    for (;;) {
        cluster_stop stop = d->io->check(d->io->user);
        if (stop == CLUSTER_CANCEL) {
            cancel_all(d);
            return AA_ECANCELED;
        }
        if (stop == CLUSTER_DETACH)
            return CLUSTER_EDETACHED;
        /* squeue first, then the outputs: a task writes its output before it leaves the
         * queue, so one absent from this squeue and without an output now never will. */
        json_t *arrays = json_object_get(r->st, "arrays");
        size_t na = json_array_size(arrays);
        long long ids[256];
        for (size_t k = 0; k < na && k < 256; k++)
            ids[k] = json_integer_value(json_array_get(arrays, k));
        slurm_queued *q = NULL;
        size_t count = 0;
        aa_error qerr = {0};
        bool queue_known = !slurm_squeue(ids, na < 256 ? na : 256, &q, &count, &qerr);
        if (!queue_known)
            fprintf(stderr, "aalabd: job %lld: %s (will ask again)\n", d->job->id, qerr.message);
        size_t done = 0;
        for (size_t i = 0; i < r->n; i++) {
            if (!r->outputs[i] && (r->outputs[i] = read_output(d, r, i)))
                note_best(d, r->stage, r->outputs[i]);
            done += r->outputs[i] != NULL;
        }
        int rc = AA_OK;
        json_t *sa = json_object_get(r->st, "shard_array");
        double now = aa_monotonic_seconds(), grace = LOST_AFTER_POLLS * d->cfg->poll_seconds;
        for (size_t i = 0; queue_known && !rc && i < r->n; i++) {
            if (r->outputs[i] || queued(q, count, json_integer_value(json_array_get(sa, i)), i)) {
                r->missing_since[i] = 0;
            } else if (!r->missing_since[i]) {
                r->missing_since[i] = now;
            } else if (now - r->missing_since[i] >= grace) {
                r->missing_since[i] = 0;
                rc = shard_lost(d, r, i, failure, cap, err);
            }
        }
        free(q);
        report(d, r, done);
        if (rc)
            return rc;
        if (done == r->n)
            return AA_OK;
        stop = pause_poll(d);
        if (stop != CLUSTER_GO)
            continue; /* handled at the top */
    }
}

static json_t *new_stage_state(size_t n)
{
    json_t *sa = json_array(), *re = json_array();
    for (size_t i = 0; i < n; i++) {
        json_array_append_new(sa, json_integer(0));
        json_array_append_new(re, json_integer(0));
    }
    return json_pack("{s:I,s:[],s:o,s:o}", "shards", (json_int_t)n, "arrays", "shard_array", sa,
                     "retried", re);
}

/* Checks that a stored stage state has the shape the driver writes. */
static bool stage_state_ok(const json_t *st, size_t n)
{
    return json_is_object(st) &&
           json_integer_value(json_object_get(st, "shards")) == (json_int_t)n &&
           json_is_array(json_object_get(st, "arrays")) &&
           json_array_size(json_object_get(st, "shard_array")) == n &&
           json_array_size(json_object_get(st, "retried")) == n;
}

int cluster_driver_run(const cluster_config *cfg, const cluster_job *job, const cluster_job_io *io,
                       void **result, char *failure, size_t failure_cap, aa_error *err)
{
    *result = NULL;
    if (failure_cap)
        failure[0] = 0;
    if (!job->kind->split)
        return aa_error_set(err, AA_EINVAL, "executor", "kind %s cannot run on Slurm",
                            job->kind->name);
    driver d = {.cfg = cfg,
                .job = job,
                .split = job->kind->split,
                .io = io,
                .best_e2 = INFINITY,
                .traces = json_array()};
    d.state = job->state ? json_deep_copy(job->state)
                         : json_pack("{s:s,s:[]}", "executor", "slurm", "stages");
    d.task_spec = json_deep_copy(job->spec);
    if (!d.state || !d.task_spec || !d.traces ||
        !json_is_array(json_object_get(d.state, "stages"))) {
        json_decref(d.state);
        json_decref(d.task_spec);
        json_decref(d.traces);
        return aa_error_set(err, job->state ? AA_EINVAL : AA_ENOMEM, "",
                            job->state ? "the stored Slurm state is malformed" : "out of memory");
    }
    json_object_del(d.task_spec, "kind");
    json_object_del(d.task_spec, "executor");
    size_t max_tasks = cfg->max_tasks > 0 ? (size_t)cfg->max_tasks : CLUSTER_DEFAULT_MAX_TASKS;
    json_t *prior = NULL, *merged = NULL;
    size_t most = 0;
    int rc = AA_OK;
    for (int s = 0; !rc && s < d.split->stages; s++) {
        json_t *shards = NULL;
        stage_run r = {.stage = s};
        rc = d.split->plan(job->params, s, prior, max_tasks, &shards, err);
        if (!rc && (r.n = json_array_size(shards)) == 0)
            rc = aa_error_set(err, AA_EINVAL, "", "the plan of stage %d has no shards", s);
        if (!rc && cluster_stage_dir(cfg->shared_dir, job->id, s, r.dir, sizeof r.dir))
            rc = aa_error_set(err, AA_ERANGE, "", "--slurm-shared-dir is too long");
        if (!rc && (!(r.outputs = calloc(r.n, sizeof *r.outputs)) ||
                    !(r.missing_since = calloc(r.n, sizeof *r.missing_since)) ||
                    !(r.trace_final = calloc(r.n, sizeof *r.trace_final))))
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
        for (size_t i = 0; !rc && i < r.n; i++)
            json_array_append_new(d.traces, json_null());
        json_t *stages = json_object_get(d.state, "stages");
        if (!rc && (size_t)s < json_array_size(stages)) {
            /* Re-attach: the arrays of this stage were submitted by an earlier run. */
            r.st = json_array_get(stages, (size_t)s);
            if (!stage_state_ok(r.st, r.n))
                rc = aa_error_set(err, AA_EINVAL, "",
                                  "the stored Slurm state of stage %d does not match its plan", s);
            else if (json_array_size(json_object_get(r.st, "arrays")) == 0)
                rc = adopt_or_submit(&d, &r, err);
        } else if (!rc) {
            r.st = new_stage_state(r.n);
            if (!r.st || json_array_append_new(stages, r.st))
                rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
            if (!rc)
                rc = write_stage(&d, &r, shards, prior, err);
            /* Saved before sbatch: a stop in between re-attaches by the array's job name. */
            if (!rc) {
                if (!json_object_get(d.state, "submitted_unix"))
                    json_object_set_new(d.state, "submitted_unix", json_real(now_unix()));
                save(&d);
                rc = submit_missing(&d, &r, err);
            }
        }
        if (!rc)
            rc = run_stage(&d, &r, failure, failure_cap, err);
        if (!rc) {
            merged = NULL;
            rc = d.split->merge(job->params, s, r.outputs, r.n, prior, &merged, err);
        }
        if (!rc) {
            json_decref(prior);
            prior = merged;
            if (r.n > most)
                most = r.n;
            d.done_before++;
            d.trace_base += r.n;
        }
        for (size_t i = 0; r.outputs && i < r.n; i++)
            json_decref(r.outputs[i]);
        free(r.outputs);
        free(r.missing_since);
        free(r.trace_final);
        json_decref(shards);
    }
    if (!rc)
        rc = d.split->finish(job->params, prior, "slurm", most, result, err);
    /* A failed job (a shard failed twice, a retry sbatch refused, a merge error) must not leave
     * its other shards running or starting. A cancel has done this already; a daemon shutdown
     * leaves them running on purpose. */
    if (rc && rc != AA_ECANCELED && rc != CLUSTER_EDETACHED)
        cancel_all(&d);
    json_decref(prior);
    json_decref(d.state);
    json_decref(d.task_spec);
    json_decref(d.best);
    json_decref(d.traces);
    return rc;
}
