/* Start-up recovery (job_manager_impl.h): every unfinished job of the store is re-queued, re-
 * attached to its Slurm arrays, or ended interrupted with a reason (its kind is gone, its spec
 * no longer valid, it took the daemon down too often); and the probe thread's sweep of the
 * shared files of deleted jobs. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>

#include "cluster_sweep.h"
#include "job_envelope.h"
#include "job_manager_impl.h"

#define JOB_MAX_CRASHES 3 /* abnormal daemon exits while running one job before giving up */

static void recover_one(void *user, long long id, const char *kind_name, json_t *spec,
                        long long owner, int priority, bool private_job, job_state state,
                        double created)
{
    job_manager *jm = user;
    assert(state == JOB_QUEUED || state == JOB_RUNNING); /* job_store_unfinished's rows */
    const job_kind *kind = kind_name ? job_manager_kind(jm, kind_name) : NULL;
    char reason[400];
    if (!kind) {
        snprintf(reason, sizeof reason, "job kind '%.40s' is not available after restart",
                 kind_name ? kind_name : "?");
        job_store_finish(jm->store, id, JOB_INTERRUPTED, 0, NULL, NULL, NULL, NULL, reason,
                         jm_now());
        return;
    }
    /* A Slurm job (its array ids are in the cluster column) re-attaches to its arrays. */
    json_t *cluster_state = job_store_get_cluster(jm->store, id);
    if (cluster_state && !jm->cfg.cluster.shared_dir[0]) {
        json_decref(cluster_state);
        job_store_finish(jm->store, id, JOB_INTERRUPTED, 0, NULL, NULL, NULL, NULL,
                         "a Slurm job, but the daemon restarted without --slurm-shared-dir; its "
                         "arrays were left alone",
                         jm_now());
        return;
    }
    /* A job that keeps taking the daemon down with it must not do so forever (a Slurm job runs
     * elsewhere: its thread only polls). */
    if (state == JOB_RUNNING && !cluster_state) {
        int crashes = job_store_bump_crashes(jm->store, id);
        if (crashes >= JOB_MAX_CRASHES) {
            snprintf(reason, sizeof reason,
                     "the daemon stopped abnormally %d times while running this job; not "
                     "re-queued again",
                     crashes);
            job_store_finish(jm->store, id, JOB_INTERRUPTED, 0, NULL, NULL, NULL, NULL, reason,
                             jm_now());
            return;
        }
    }
    void *params = NULL;
    aa_error err = {0};
    /* The stored spec is the kind's (the envelope lives in its own columns); a spec stored
     * before that split still carries it, so it is taken out here too. */
    job_envelope env;
    json_t *kind_spec = NULL;
    int prc = job_envelope_take(spec, &env, &kind_spec, &err);
    if (!prc)
        prc = kind->decode(kind_spec, &params, &err);
    json_decref(kind_spec);
    if (prc != AA_OK) {
        json_decref(cluster_state);
        snprintf(reason, sizeof reason, "spec no longer valid after restart: %s (%s)", err.message,
                 err.field);
        job_store_finish(jm->store, id, JOB_INTERRUPTED, 0, NULL, NULL, NULL, NULL, reason,
                         jm_now());
        return;
    }
    job *j = jm_job_new();
    if (!j) {
        json_decref(cluster_state);
        kind->free_params(params);
        job_store_finish(jm->store, id, JOB_INTERRUPTED, 0, NULL, NULL, NULL, NULL,
                         "out of memory at restart", jm_now());
        return;
    }
    j->jm = jm;
    j->id = id;
    j->kind = kind;
    j->params = params;
    j->spec = json_incref(spec);
    j->owner = owner;
    j->priority = priority;
    j->private_job = private_job || env.private_job;
    j->state = JOB_QUEUED;
    j->created = created;
    if (cluster_state) {
        /* Started by job_manager_create once recovery is over. */
        j->slurm = true;
        j->cluster_state = cluster_state;
        snprintf(j->reason, sizeof j->reason, "re-attached to its Slurm arrays at restart");
        j->next = jm->active;
        jm->active = j;
        return;
    }
    if (state == JOB_RUNNING)
        snprintf(j->reason, sizeof j->reason,
                 "was running when the daemon stopped; re-queued at restart");
    jm_queue_push(jm, j);
    j->next = jm->active;
    jm->active = j;
    /* A job that was running restarts from scratch: clear its stale live state. */
    job_store_finish(jm->store, id, JOB_QUEUED, 0, json_null(), NULL, NULL, NULL,
                     j->reason[0] ? j->reason : NULL, 0);
}

static bool job_known(void *user, long long id)
{
    job_manager *jm = user;
    return job_store_owner(jm->store, id, NULL, NULL, NULL);
}

/* The probe thread's housekeeping: the shared files of jobs that retention deleted. */
void jm_sweep_shared_dir(void *user)
{
    job_manager *jm = user;
    size_t removed = 0;
    aa_error err = {0};
    if (cluster_sweep_orphans(jm->cfg.cluster.shared_dir, job_known, jm, &removed, &err))
        fprintf(stderr, "aalabd: sweeping --slurm-shared-dir: %s\n", err.message);
    if (removed)
        fprintf(stderr, "aalabd: removed the shared files of %zu deleted job(s)\n", removed);
}

void jm_recover_jobs(job_manager *jm)
{
    job_store_unfinished(jm->store, recover_one, jm);
    pthread_mutex_lock(&jm->lock);
    for (job *j = jm->active; j; j = j->next) {
        if (j->slurm && j->state == JOB_QUEUED && !jm_slurm_start_locked(jm, j))
            fprintf(stderr, "aalabd: cannot start a thread for Slurm job %lld\n", j->id);
    }
    jm_schedule_locked(jm);
    pthread_mutex_unlock(&jm->lock);
}
