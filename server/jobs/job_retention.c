/* The retention sweeper (job_retention.h). */
#define _POSIX_C_SOURCE 200809L
#include "job_retention.h"

#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <time.h>

struct job_retention {
    job_store *st;
    double keep_seconds, period;
    pthread_mutex_t lock;
    pthread_cond_t wake; /* CLOCK_MONOTONIC */
    bool stopping;
    bool running; /* keep_days <= 0: retention off, no thread */
    long long deleted;
    pthread_t thread;
};

double job_retention_period(double keep_days)
{
    double quarter = keep_days * 86400.0 / 4.0;
    return quarter < 3600.0 ? quarter : 3600.0;
}

static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static void *sweeper(void *arg)
{
    job_retention *r = arg;
    pthread_mutex_lock(&r->lock);
    while (!r->stopping) {
        pthread_mutex_unlock(&r->lock);
        long long n = 0;
        job_store_sweep(r->st, wall_now() - r->keep_seconds, &n);
        pthread_mutex_lock(&r->lock);
        r->deleted += n;
        struct timespec until;
        clock_gettime(CLOCK_MONOTONIC, &until);
        double whole = floor(r->period);
        until.tv_sec += (time_t)whole;
        until.tv_nsec += (long)((r->period - whole) * 1e9);
        if (until.tv_nsec >= 1000000000L) {
            until.tv_sec++;
            until.tv_nsec -= 1000000000L;
        }
        while (!r->stopping && pthread_cond_timedwait(&r->wake, &r->lock, &until) == 0)
            ;
    }
    pthread_mutex_unlock(&r->lock);
    return NULL;
}

job_retention *job_retention_start(job_store *st, double keep_days, aa_error *err)
{
    job_retention *r = calloc(1, sizeof *r);
    if (!r) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    r->st = st;
    r->keep_seconds = keep_days * 86400.0;
    r->period = job_retention_period(keep_days);
    if (r->period < 0.01)
        r->period = 0.01;
    pthread_mutex_init(&r->lock, NULL);
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_cond_init(&r->wake, &ca);
    pthread_condattr_destroy(&ca);
    if (keep_days <= 0)
        return r;
    if (pthread_create(&r->thread, NULL, sweeper, r) != 0) {
        aa_error_set(err, AA_ENOMEM, "keep_days", "cannot start the retention thread");
        pthread_cond_destroy(&r->wake);
        pthread_mutex_destroy(&r->lock);
        free(r);
        return NULL;
    }
    r->running = true;
    return r;
}

void job_retention_stop(job_retention *r)
{
    if (!r)
        return;
    pthread_mutex_lock(&r->lock);
    r->stopping = true;
    pthread_cond_signal(&r->wake);
    pthread_mutex_unlock(&r->lock);
    if (r->running)
        pthread_join(r->thread, NULL);
    pthread_cond_destroy(&r->wake);
    pthread_mutex_destroy(&r->lock);
    free(r);
}

long long job_retention_deleted(job_retention *r)
{
    pthread_mutex_lock(&r->lock);
    long long n = r->deleted;
    pthread_mutex_unlock(&r->lock);
    return n;
}
