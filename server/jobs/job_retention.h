/* Retention: a thread that deletes finished, unpinned jobs older than keep_days, once at start
 * and then every job_retention_period(keep_days) seconds; keep_days <= 0 turns it off. */
#ifndef AALAB_JOB_RETENTION_H
#define AALAB_JOB_RETENTION_H

#include "aa_core.h"
#include "job_store.h"

typedef struct job_retention job_retention;

/* min(1 h, keep_days / 4): a job outlives its keep_days by at most a quarter of it. */
double job_retention_period(double keep_days);
job_retention *job_retention_start(job_store *st, double keep_days, aa_error *err);
/* Stops and joins the thread; NULL is fine. */
void job_retention_stop(job_retention *r);
/* Jobs deleted so far. */
long long job_retention_deleted(job_retention *r);

#endif
