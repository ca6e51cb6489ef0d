/* The job store's insides, shared by job_store.c (connections), job_store_schema.c,
 * job_store_write.c and job_store_read.c. */
#ifndef AALAB_JOB_STORE_IMPL_H
#define AALAB_JOB_STORE_IMPL_H

#include <pthread.h>
#include <stdatomic.h>

#include <sqlite3.h>

#include "job_store.h"

#define JOB_STORE_READERS 3

typedef struct job_store_reader {
    sqlite3 *db;
    pthread_mutex_t lock;
} job_store_reader;

struct job_store {
    sqlite3 *db;          /* the write connection */
    pthread_mutex_t lock; /* the store mutex: guards db */
    bool sync_full;       /* current PRAGMA synchronous of db (under lock) */
    long long user_quota; /* 0 = unlimited; set before use */
    job_store_reader readers[JOB_STORE_READERS];
    atomic_uint next_reader;
};

/* Creates the schema, or migrates one of an older version (ALTER TABLE + backfill). */
int job_store_schema_init(sqlite3 *db, aa_error *err);

/* A read connection, locked; release with job_store_reader_release. */
job_store_reader *job_store_reader_acquire(job_store *st);
void job_store_reader_release(job_store_reader *r);
/* Switches the write connection between synchronous=FULL (state changes) and NORMAL
 * (progress). Caller holds st->lock. */
void job_store_sync(job_store *st, bool full);

job_state job_state_from_name(const char *n);

/* Columns every job object shows, in this order (job_store_read.c row_summary). */
#define JOB_SUMMARY_COLUMNS                                                                        \
    "id, kind, owner_uid, state, progress, created, started, finished, reason, error, best_e2, "   \
    "family, visibility, pinned, bytes, label"
#define JOB_SUMMARY_COUNT 16
/* A job's spec: in job_specs since the list columns came (so rewriting best or trace does not
 * rewrite the spec too), in jobs.spec for rows written before. */
#define JOB_SPEC_EXPR                                                                              \
    "coalesce((SELECT s.spec FROM job_specs s WHERE s.job_id = jobs.id), jobs.spec)"

#endif
