/* Jobs with executor "slurm" (job_manager_impl.h): each runs on a thread of its own that drives
 * its Slurm arrays through cluster_driver.h and holds no worker; its checks, progress reports and
 * array ids go to the job here. Submission asks jm_slurm_refusal first. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>

#include "cluster_driver.h"
#include "job_kind_names.h"
#include "job_manager_impl.h"

static cluster_stop slurm_check(void *user)
{
    job_ctx *ctx = user;
    pthread_mutex_lock(ctx->lock);
    jm_yield_point_locked(ctx); /* holds no worker: this only enforces --max-job-seconds */
    const job *j = ctx->job;
    cluster_stop s = j->cancel_requested || j->over_time ? CLUSTER_CANCEL
                     : ctx->jm->stopping                 ? CLUSTER_DETACH
                                                         : CLUSTER_GO;
    pthread_mutex_unlock(ctx->lock);
    return s;
}

static void slurm_report(void *user, double progress, const json_t *best, const json_t *trace)
{
    job_ctx *ctx = user;
    json_t *b = best ? json_deep_copy(best) : NULL;
    json_t *t = trace ? json_deep_copy(trace) : NULL;
    pthread_mutex_lock(ctx->lock);
    job_live *l = ctx->live;
    l->progress = progress < 0 ? 0 : progress > 1 ? 1 : progress;
    if (b) {
        json_decref(l->best);
        l->best = b;
    }
    if (t) {
        /* The merged trace is rebuilt from the shards' files each poll: replace it whole. */
        json_decref(l->trace);
        l->trace = t;
        l->have_pending = false;
        if (json_array_size(t) == l->flushed_trace_len)
            l->flushed_trace_len = (size_t)-1;
    }
    if (jm_now() - l->last_flush >= 5.0)
        job_ctx_flush_locked(ctx);
    pthread_mutex_unlock(ctx->lock);
}

static void slurm_save(void *user, const json_t *state)
{
    job_ctx *ctx = user;
    if (job_store_set_cluster(ctx->store, ctx->id, state))
        fprintf(stderr, "aalabd: job %lld: cannot store its Slurm array ids\n", ctx->id);
}

/* One thread per Slurm job: runs the driver until the job ends, is cancelled or the daemon
 * stops (then the arrays keep running). */
static void *slurm_thread(void *arg)
{
    job *j = arg;
    job_manager *jm = j->jm;
    job_store_set_state(jm->store, j->id, JOB_RUNNING, j->started, j->reason[0] ? j->reason : NULL);
    struct job_ctx ctx = job_ctx_of(jm, j);
    cluster_job cj = {.id = j->id,
                      .kind = j->kind,
                      .params = j->params,
                      .spec = j->spec,
                      .state = j->cluster_state};
    cluster_job_io io = {
        .check = slurm_check, .report = slurm_report, .save = slurm_save, .user = &ctx};
    void *typed = NULL;
    json_t *result = NULL;
    aa_error err = {0};
    char failure[1200];
    int rc = cluster_driver_run(&jm->cfg.cluster, &cj, &io, &typed, failure, sizeof failure, &err);
    if (rc == AA_OK && !(result = j->kind->encode_result(typed)))
        rc = aa_error_set(&err, AA_ENOMEM, "", "out of memory");
    if (typed)
        j->kind->free_result(typed);
    jm_finish_job(jm, j, rc, result, &err, failure);
    pthread_mutex_lock(&jm->lock);
    jm->slurm_jobs--;
    if (--jm->threads == 0)
        pthread_cond_broadcast(&jm->idle);
    pthread_mutex_unlock(&jm->lock);
    return NULL;
}

/* Starts a Slurm job's thread (lock held). false when no thread could start. */
bool jm_slurm_start_locked(job_manager *jm, job *j)
{
    ASSERT_LOCK_HELD(&jm->lock);
    assert(j->slurm && j->state == JOB_QUEUED); /* edge queued -> running (a Slurm thread) */
    j->state = JOB_RUNNING;
    j->started = jm_now();
    if (jm_start_detached(slurm_thread, j))
        return false;
    jm->running++;
    jm->threads++;
    jm->slurm_jobs++;
    return true;
}

/* Why a job with executor "slurm" cannot be taken now (AA_EINVAL for a kind without a split,
 * JM_ESLURM), or AA_OK. Reads the probe's last answer: never waits for Slurm. */
int jm_slurm_refusal(job_manager *jm, const job_kind *kind, aa_error *err)
{
    if (!kind->split) {
        char can[160];
        job_kind_names_join(can, sizeof can, false, true, " and ");
        return aa_error_set(err, AA_EINVAL, "executor", "kind %s cannot run on Slurm (%s can)",
                            kind->name, can);
    }
    cluster_status st;
    cluster_probe_status(jm->probe, &st);
    if (!st.configured)
        return aa_error_set(err, JM_ESLURM, "executor",
                            "Slurm is not configured: this daemon runs without --slurm-shared-dir");
    if (st.answering != 1)
        return aa_error_set(err, JM_ESLURM, "executor", "%s", st.message);
    return AA_OK;
}
