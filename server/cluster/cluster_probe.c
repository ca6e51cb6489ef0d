/* cluster_probe.h. */
#define _POSIX_C_SOURCE 200809L
#include "cluster_probe.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lock_held.h"
#include "slurm_commands.h"

struct cluster_probe {
    pthread_mutex_t lock;
    pthread_cond_t wake;
    pthread_t thread;
    bool has_thread, stopping;
    bool housekeeping_due; /* cluster_probe_housekeep_soon: run it at the next round */
    cluster_status status;
    cluster_housekeeping_fn housekeeping;
    void *user;
    double last_ping; /* monotonic seconds of the last scontrol ping */
};

/* Waits (p->lock held) up to seconds, or until stopped or housekeeping is due. */
static void wait_for_next_round(cluster_probe *p, double seconds)
{
    ASSERT_LOCK_HELD(&p->lock);
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    long long ns = (long long)until.tv_nsec + (long long)(seconds * 1e9);
    until.tv_sec += (time_t)(ns / 1000000000LL);
    until.tv_nsec = (long)(ns % 1000000000LL);
    while (!p->stopping && !p->housekeeping_due &&
           pthread_cond_timedwait(&p->wake, &p->lock, &until) == 0)
        ;
}

static void *probe_thread(void *arg)
{
    cluster_probe *p = arg;
    double last_housekeeping = -1e300;
    p->last_ping = -1e300;
    pthread_mutex_lock(&p->lock);
    while (!p->stopping) {
        pthread_mutex_unlock(&p->lock);
        double now = aa_monotonic_seconds();
        pthread_mutex_lock(&p->lock);
        bool due = p->housekeeping_due;
        p->housekeeping_due = false;
        pthread_mutex_unlock(&p->lock);
        if (p->housekeeping && (due || now - last_housekeeping >= CLUSTER_HOUSEKEEPING_INTERVAL)) {
            last_housekeeping = now;
            p->housekeeping(p->user);
        }
        if (due && now - p->last_ping < CLUSTER_PROBE_INTERVAL) {
            /* Woken for housekeeping only: the last answer is recent enough. */
            pthread_mutex_lock(&p->lock);
            wait_for_next_round(p, p->last_ping + CLUSTER_PROBE_INTERVAL - now);
            continue;
        }
        char message[200];
        bool up = slurm_ping(message, sizeof message);
        pthread_mutex_lock(&p->lock);
        p->last_ping = now;
        p->status.answering = up;
        snprintf(p->status.message, sizeof p->status.message, "%s%s",
                 up ? "" : "Slurm is configured but not answering: ", message);
        wait_for_next_round(p, CLUSTER_PROBE_INTERVAL);
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

cluster_probe *cluster_probe_start(bool configured, cluster_housekeeping_fn housekeeping,
                                   void *user, aa_error *err)
{
    cluster_probe *p = calloc(1, sizeof *p);
    if (!p) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    pthread_mutex_init(&p->lock, NULL);
    pthread_cond_init(&p->wake, NULL);
    p->status.configured = configured;
    p->housekeeping = housekeeping;
    p->user = user;
    p->status.answering = configured ? -1 : 0;
    snprintf(p->status.message, sizeof p->status.message, "%s",
             configured ? "Slurm is configured; the first scontrol ping has not answered yet"
                        : "Slurm is not configured (start aalabd with --slurm-shared-dir)");
    if (configured) {
        if (pthread_create(&p->thread, NULL, probe_thread, p)) {
            aa_error_set(err, AA_ENOMEM, "", "cannot start the Slurm probe thread");
            cluster_probe_stop(p);
            return NULL;
        }
        p->has_thread = true;
    }
    return p;
}

void cluster_probe_status(cluster_probe *p, cluster_status *out)
{
    pthread_mutex_lock(&p->lock);
    *out = p->status;
    pthread_mutex_unlock(&p->lock);
}

void cluster_probe_housekeep_soon(cluster_probe *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->lock);
    p->housekeeping_due = true;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->lock);
}

void cluster_probe_stop(cluster_probe *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->lock);
    p->stopping = true;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->lock);
    if (p->has_thread)
        pthread_join(p->thread, NULL);
    pthread_cond_destroy(&p->wake);
    pthread_mutex_destroy(&p->lock);
    free(p);
}
