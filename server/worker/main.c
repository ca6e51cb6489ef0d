/* aalab-worker TASK.json: runs one shard of a job (job_split.h) with the engine and no daemon,
 * on a cluster node of a Slurm job array, and writes its output and trace atomically where the
 * task says (docs/cluster.md). Exit codes: see usage(). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "aalab_version.h"
#include "cluster_layout.h"
#include "job_kind_names.h"
#include "job_split.h"
#include "worker_report.h"
#include "worker_task.h"

/* sysexits.h values: what Slurm's accounting and the daemon's driver read. */
enum {
    EXIT_DONE = 0,
    EXIT_USAGE = 64,     /* EX_USAGE */
    EXIT_DATAERR = 65,   /* EX_DATAERR: task file unreadable or invalid */
    EXIT_SOFTWARE = 70,  /* EX_SOFTWARE: the computation failed */
    EXIT_CANTCREAT = 73, /* EX_CANTCREAT: output or trace cannot be written */
    EXIT_TEMPFAIL = 75,  /* EX_TEMPFAIL: stopped by SIGTERM/SIGINT, no output written */
};

static volatile sig_atomic_t stop_requested;

static void on_stop_signal(int sig)
{
    (void)sig;
    stop_requested = 1;
}

static void usage(FILE *f)
{
    char kinds[160]; /* from the kind table: the kinds that split */
    job_kind_names_join(kinds, sizeof kinds, false, true, ", ");
    fprintf(f,
            "usage: aalab-worker TASK.json\n"
            "       aalab-worker --help | --version\n"
            "Runs one shard of an aalab job (%s) described by\n",
            kinds);
    fputs("TASK.json (format aalab-task/1) and writes the shard's output and trace files named\n"
          "in it atomically (temporary file in the same directory, fsync, rename). Threads:\n"
          "$SLURM_CPUS_PER_TASK, or 1.\n"
          "\n"
          "Exit codes:\n"
          "  0   the output file is written\n"
          "  64  usage error (no task file, unknown option)\n"
          "  65  the task file is unreadable or invalid (the message names the field)\n"
          "  70  the computation failed (message on stderr)\n"
          "  73  the output or trace file cannot be written\n"
          "  75  stopped by SIGTERM or SIGINT (scancel, time limit); no output written\n",
          f);
}

static int threads_from_env(void)
{
    const char *s = getenv("SLURM_CPUS_PER_TASK");
    char *end;
    errno = 0;
    long n = s ? strtol(s, &end, 10) : 1;
    if (!s || errno || end == s || *end || n < 1)
        return 1;
    return n > 64 ? 64 : (int)n;
}

static void complain(const char *what, const aa_error *err)
{
    if (err->field[0])
        fprintf(stderr, "aalab-worker: %s: field \"%s\": %s\n", what, err->field, err->message);
    else
        fprintf(stderr, "aalab-worker: %s: %s\n", what, err->message);
}

static json_t *output_file(const worker_task *t, const worker_report *rep, double finished,
                           json_t *output)
{
    char host[256] = "";
    if (gethostname(host, sizeof host - 1))
        snprintf(host, sizeof host, "unknown");
    return json_pack("{s:s,s:I,s:i,s:I,s:s,s:o,s:o,s:O}", "format", "aalab-shard-output/1",
                     "job_id", (json_int_t)t->job_id, "stage", t->stage, "shard_index",
                     (json_int_t)t->shard_index, "host", host, "started_unix",
                     json_real(rep->started_unix), "finished_unix", json_real(finished), "output",
                     output);
}

static int run(const worker_task *t)
{
    worker_report rep;
    worker_report_init(&rep, t->trace, &stop_requested);
    aa_error err = {0};
    /* Written first: an unwritable directory fails before any work. */
    if (worker_report_write(&rep, &err)) {
        complain("trace", &err);
        worker_report_free(&rep);
        return EXIT_CANTCREAT;
    }
    shard_ctx ctx = worker_report_ctx(&rep, threads_from_env());
    json_t *output = NULL;
    int rc =
        t->kind->split->run_shard(t->params, t->stage, t->shard, t->prior, &ctx, &output, &err);
    int code = EXIT_DONE;
    if (rep.write_failed) {
        complain("trace", &rep.err);
        code = EXIT_CANTCREAT;
    } else if (stop_requested) {
        fputs("aalab-worker: stopped by a signal; no output written\n", stderr);
        code = EXIT_TEMPFAIL;
    } else if (rc) {
        complain("the shard failed", &err);
        code = EXIT_SOFTWARE;
    }
    if (code == EXIT_DONE) {
        rep.progress = 1;
        if (worker_report_write(&rep, &err)) {
            complain("trace", &err);
            code = EXIT_CANTCREAT;
        }
    }
    if (code == EXIT_DONE) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        json_t *file = output_file(t, &rep, (double)ts.tv_sec + ts.tv_nsec * 1e-9, output);
        if (!file) {
            fputs("aalab-worker: out of memory\n", stderr);
            code = EXIT_SOFTWARE;
        } else if (stop_requested) {
            fputs("aalab-worker: stopped by a signal; no output written\n", stderr);
            code = EXIT_TEMPFAIL;
        } else if (cluster_write_json(t->output, file, &err)) {
            complain("output", &err);
            code = EXIT_CANTCREAT;
        }
        json_decref(file);
    }
    json_decref(output);
    worker_report_free(&rep);
    return code;
}

int main(int argc, char **argv)
{
    if (argc == 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        usage(stdout);
        return EXIT_DONE;
    }
    if (argc == 2 && !strcmp(argv[1], "--version")) {
        printf("aalab-worker %s\n", aalab_version_full);
        return EXIT_DONE;
    }
    if (argc != 2 || argv[1][0] == '-') {
        usage(stderr);
        return EXIT_USAGE;
    }
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    worker_task task;
    aa_error err = {0};
    if (worker_task_load(argv[1], &task, &err)) {
        complain(argv[1], &err);
        return EXIT_DATAERR;
    }
    int code = run(&task);
    worker_task_free(&task);
    return code;
}
