/* Where a shard run by aalab-worker reports (the shard_ctx of job_split.h): progress and trace
 * points go to the trace file, rewritten atomically at most every 2 s and at the end:
 * {"format":"aalab-shard-trace/1","started_unix":t0,"progress":0..1,"points":[{"seconds",
 *  "iterations","evaluations","best_e2"}]} (seconds since t0, counts of this shard).
 * A stop request (SIGTERM/SIGINT) or a trace file that cannot be written stops the shard. */
#ifndef AALAB_WORKER_REPORT_H
#define AALAB_WORKER_REPORT_H

#include <pthread.h>
#include <signal.h>
#include <stdbool.h>

#include <jansson.h>

#include "job_split.h"

typedef struct worker_report {
    const char *trace_path;
    double started_unix;         /* wall time of the start, for the files */
    double started_mono;         /* monotonic, for the 2 s cadence */
    volatile sig_atomic_t *stop; /* set by the signal handler */
    pthread_mutex_t lock;
    double progress;
    json_t *points;
    double last_append; /* seconds of the latest appended point */
    double last_write;  /* monotonic time of the latest trace write */
    int write_failed;   /* the trace could not be written: err holds why */
    aa_error err;
} worker_report;

void worker_report_init(worker_report *r, const char *trace_path, volatile sig_atomic_t *stop);
void worker_report_free(worker_report *r);
/* A shard_ctx reporting to r, with the given threads. */
shard_ctx worker_report_ctx(worker_report *r, int workers);
/* Writes the trace file now (at the start and at the end). */
int worker_report_write(worker_report *r, aa_error *err);

#endif
