/* The job manager's public API (job_manager.h): create and destroy, submission with its
 * admission checks, and get, list, cancel, purge and stats over the store and the live jobs.
 * Scheduling, Slurm jobs and start-up recovery are in job_schedule.c, job_slurm.c and
 * job_recovery.c (job_manager_impl.h). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "job_envelope.h"
#include "job_kind_names.h"
#include "job_manager_impl.h"
#include "wire_error.h"

job *jm_job_new(void)
{
    job *j = calloc(1, sizeof *j);
    if (!j)
        return NULL;
    if (job_live_init(&j->live) != AA_OK || pthread_cond_init(&j->resume, NULL)) {
        job_live_clear(&j->live);
        free(j);
        return NULL;
    }
    atomic_init(&j->paused_ns, 0);
    return j;
}

void jm_job_free(job *j)
{
    if (!j)
        return;
    if (j->params && j->kind && j->kind->free_params)
        j->kind->free_params(j->params);
    json_decref(j->spec);
    json_decref(j->cluster_state);
    job_live_clear(&j->live);
    pthread_cond_destroy(&j->resume);
    free(j);
}

static int owner_load(job_manager *jm, long long owner)
{
    ASSERT_LOCK_HELD(&jm->lock);
    int n = 0;
    for (job *j = jm->active; j; j = j->next)
        n += j->owner == owner;
    return n;
}

job_manager *job_manager_create(const char *state_dir, const job_manager_config *cfg, aa_error *err)
{
    job_manager *jm = calloc(1, sizeof *jm);
    if (!jm) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    jm->cfg = *cfg;
    if (jm->cfg.workers < 1)
        jm->cfg.workers = 1;
    pthread_mutex_init(&jm->lock, NULL);
    pthread_mutex_init(&jm->counts_lock, NULL);
    for (size_t i = 0; i < sizeof jm->counts / sizeof jm->counts[0]; i++)
        jm->counts[i].at = -1e300;
    pthread_cond_init(&jm->idle, NULL);
    jm->store = job_store_open(state_dir, err);
    if (!jm->store) {
        job_manager_destroy(jm);
        return NULL;
    }
    if (jm->cfg.user_workers < 1)
        jm->cfg.user_workers = jm->cfg.workers / 2 > 1 ? jm->cfg.workers / 2 : 1;
    if (!(jm->cfg.slice_seconds > 0))
        jm->cfg.slice_seconds = 60;
    if (!(jm->cfg.max_job_seconds > 0))
        jm->cfg.max_job_seconds = 86400;
    job_store_set_user_quota(jm->store, jm->cfg.user_store_bytes);
    jm->probe =
        cluster_probe_start(jm->cfg.cluster.shared_dir[0] != 0, jm_sweep_shared_dir, jm, err);
    if (!jm->probe) {
        job_manager_destroy(jm);
        return NULL;
    }
    jm_recover_jobs(jm);
    return jm;
}

void job_manager_shutdown(job_manager *jm)
{
    pthread_mutex_lock(&jm->lock);
    jm->stopping = true;
    for (job *j = jm->active; j; j = j->next)
        if (j->paused || j->unstored)
            pthread_cond_signal(&j->resume);
    while (jm->threads > 0)
        pthread_cond_wait(&jm->idle, &jm->lock);
    pthread_mutex_unlock(&jm->lock);
}

void job_manager_destroy(job_manager *jm)
{
    if (!jm)
        return;
    job_manager_shutdown(jm);
    /* Jobs still queued stay queued in the store; only memory is released. */
    while (jm->active) {
        job *j = jm->active;
        jm->active = j->next;
        jm_job_free(j);
    }
    free(jm->queue);
    free(jm->snapshot);
    job_store_close(jm->store);
    cluster_probe_stop(jm->probe);
    pthread_cond_destroy(&jm->idle);
    pthread_mutex_destroy(&jm->counts_lock);
    pthread_mutex_destroy(&jm->lock);
    free(jm);
}

const job_kind *job_manager_kind(const job_manager *jm, const char *name)
{
    const job_kind *k = job_kind_find(name);
    return k && (!k->test_only || jm->cfg.test_kinds) ? k : NULL;
}

void job_manager_kind_names(const job_manager *jm, char *buf, size_t cap)
{
    job_kind_names_join(buf, cap, jm->cfg.test_kinds, false, ", ");
}

int job_manager_submit(job_manager *jm, const json_t *spec, long long owner, long long *id,
                       aa_error *err)
{
    const json_t *kind_j = json_object_get(spec, "kind");
    if (!kind_j)
        return aa_error_set(err, AA_EINVAL, "kind", "a job needs a kind");
    if (!json_is_string(kind_j))
        return aa_error_set(err, AA_EINVAL, "kind", "kind must be a string");
    const char *kind_name = json_string_value(kind_j);
    const job_kind *kind = job_manager_kind(jm, kind_name);
    if (!kind || strlen(kind_name) != json_string_length(kind_j)) {
        char names[256];
        job_manager_kind_names(jm, names, sizeof names);
        return aa_error_set(err, AA_EINVAL, "kind", "unknown job kind \"%.40s\"; known kinds: %s",
                            kind_name, names);
    }
    job_envelope env;
    json_t *kind_spec = NULL;
    int rc = job_envelope_take(spec, &env, &kind_spec, err);
    if (rc)
        return rc;
    if (env.slurm) {
        rc = jm_slurm_refusal(jm, kind, err);
        if (rc) {
            json_decref(kind_spec);
            return rc;
        }
    }
    void *params = NULL;
    rc = kind->decode(kind_spec, &params, err);
    double whole = !rc && kind->max_seconds ? kind->max_seconds(params) : 0;
    if (whole > jm->cfg.max_job_seconds) {
        kind->free_params(params);
        const json_t *asked = json_object_get(kind_spec, "max_seconds");
        double per = json_is_number(asked) ? json_number_value(asked) : whole;
        /* Kinds that spend max_seconds per seed or stage (table3) say what it adds up to, so
         * that a 0.5 refused under a ceiling of 3 makes sense. */
        if (per < whole)
            rc = aa_error_set(err, AA_ERANGE, "max_seconds",
                              "max_seconds %g makes this %s job's whole budget %g s (it is spent "
                              "per seed and stage), over this daemon's --max-job-seconds %.0f",
                              per, kind->name, whole, jm->cfg.max_job_seconds);
        else
            rc = aa_error_set(err, AA_ERANGE, "max_seconds",
                              "must be at most %.0f (this daemon's --max-job-seconds)",
                              jm->cfg.max_job_seconds);
    }
    /* Stored as submitted, less the envelope (which has columns of its own). */
    json_t *stored = rc ? NULL : json_pack("{s:s}", "kind", kind->name);
    if (stored && json_object_update(stored, kind_spec)) {
        json_decref(stored);
        stored = NULL;
    }
    json_decref(kind_spec);
    if (rc)
        return rc < 0 ? rc : AA_EINVAL;
    job *j = stored ? jm_job_new() : NULL;
    if (!j) {
        kind->free_params(params);
        json_decref(stored);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    j->jm = jm;
    j->kind = kind;
    j->params = params;
    j->spec = stored;
    j->owner = owner;
    j->priority = env.priority;
    j->private_job = env.private_job;
    j->state = JOB_QUEUED;
    j->created = jm_now();
    j->slurm = env.slurm;

    /* Admission under the lock; the store insert (an fsync) outside it, so workers reporting
     * progress never wait for a disk. The job joins the active list first (id 0, invisible
     * to lookups) so it counts against the quota and the queue bound meanwhile. */
    pthread_mutex_lock(&jm->lock);
    if (jm->stopping) {
        rc = aa_error_set(err, JM_EQUEUE_FULL, "", "the daemon is shutting down");
    } else if (j->slurm && jm->slurm_jobs >= JM_SLURM_JOBS_MAX) {
        rc = aa_error_set(err, JM_EQUEUE_FULL, "", "%d Slurm jobs are running (the limit)",
                          JM_SLURM_JOBS_MAX);
    } else if (!j->slurm && (int)(jm->q_len + jm->admitting) >= jm->cfg.queue_size) {
        rc = aa_error_set(err, JM_EQUEUE_FULL, "", "the job queue is full (%d queued)",
                          (int)jm->q_len);
    } else if (owner >= 0 && owner_load(jm, owner) >= jm->cfg.user_quota) {
        rc = aa_error_set(err, JM_EQUOTA, "",
                          "uid %lld already has %d queued or running jobs (the limit)", owner,
                          jm->cfg.user_quota);
    } else {
        j->next = jm->active;
        jm->active = j;
        jm->admitting++;
    }
    pthread_mutex_unlock(&jm->lock);
    if (rc) {
        jm_job_free(j);
        return rc;
    }
    long long new_id = 0;
    job_store_new rec = {.kind = kind->name,
                         .spec = j->spec,
                         .owner = owner,
                         .created = j->created,
                         .visibility = job_envelope_visibility(&env),
                         .pinned = env.pinned,
                         .priority = env.priority,
                         .label = env.label,
                         .family = kind->spec_family ? kind->spec_family(params) : NULL};
    rc = job_store_insert(jm->store, &rec, &new_id, err); /* its codes are answered as they are */
    /* A restart must know a Slurm job as one even before its first array is submitted. */
    json_t *marker = j->slurm ? json_pack("{s:s,s:[]}", "executor", "slurm", "stages") : NULL;
    if (!rc && j->slurm && (!marker || job_store_set_cluster(jm->store, new_id, marker)))
        rc = aa_error_set(err, JM_ESTORE, "", "cannot store the job's executor");
    json_decref(marker);
    pthread_mutex_lock(&jm->lock);
    jm->admitting--;
    if (!rc && j->slurm) {
        j->id = new_id;
        if (!jm_slurm_start_locked(jm, j))
            rc = aa_error_set(err, AA_ENOMEM, "", "cannot start a thread for the Slurm job");
    } else if (!rc && jm_queue_push(jm, j) != AA_OK) {
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    if (rc) {
        jm_active_remove(jm, j);
    } else {
        j->id = new_id;
        *id = new_id;
        jm_schedule_locked(jm);
    }
    pthread_mutex_unlock(&jm->lock);
    if (new_id > 0 && (rc == AA_ENOMEM || rc == JM_ESTORE))
        job_store_finish(jm->store, new_id, JOB_FAILED, 0, NULL, NULL, NULL, NULL, "out of memory",
                         jm_now());
    if (!rc)
        j = NULL;
    jm_job_free(j);
    return rc;
}

/* Overlays the live state of an active job on its stored record. Caller holds the lock. */
static void overlay_live(json_t *o, const job *j)
{
    ASSERT_LOCK_HELD(&j->jm->lock);
    json_object_set_new(o, "state", json_string(job_state_name(j->state)));
    json_object_set_new(o, "progress", json_real(j->live.progress));
    /* Copies, never shared references: jansson's reference counts are not meant to be
     * touched from two threads (the worker keeps updating live.best). */
    if (j->live.best) {
        json_object_set_new(o, "best", json_deep_copy(j->live.best));
        json_t *e2 = json_is_object(j->live.best) ? json_object_get(j->live.best, "e2") : NULL;
        if (json_is_number(e2))
            json_object_set_new(o, "best_e2", json_real(json_number_value(e2)));
    }
    if (json_object_get(o, "trace"))
        json_object_set_new(o, "trace", json_deep_copy(j->live.trace));
    if (j->cancel_requested)
        json_object_set_new(o, "cancel_requested", json_true());
    if (j->unstored) { /* its end as the store will have it once it can be written */
        json_object_set_new(o, "finished", json_real(j->finished));
        json_object_set_new(o, "reason", json_string(j->reason));
        json_object_set_new(o, "error",
                            json_pack("{s:s,s:s,s:s}", "code",
                                      proto_wire_row_of(WIRE_STORE_UNAVAILABLE)->code, "message",
                                      j->reason, "field", ""));
    }
    if (j->paused) /* gave its worker to another user's job; resumes where it stopped */
        json_object_set_new(o, "paused", json_true());
    if (j->state == JOB_RUNNING) {
        json_object_set_new(o, "started", json_real(j->started));
        /* Why a job runs longer than its budget: the turns it gave to other users so far. */
        double paused = (double)atomic_load(&j->paused_ns) * 1e-9 +
                        (j->paused ? aa_monotonic_seconds() - j->paused_since : 0);
        json_object_set_new(o, "paused_seconds", json_real(paused));
    }
}

json_t *job_manager_get(job_manager *jm, long long id)
{
    json_t *o = job_store_get(jm->store, id, true);
    if (!o)
        return NULL;
    json_t *cluster = job_store_get_cluster(jm->store, id);
    json_object_set_new(o, "executor", json_string(cluster ? "slurm" : "local"));
    json_decref(cluster);
    pthread_mutex_lock(&jm->lock);
    job *j = jm_active_find(jm, id);
    if (j)
        overlay_live(o, j);
    pthread_mutex_unlock(&jm->lock);
    return o;
}

json_t *job_manager_list(job_manager *jm, const job_store_filter *filter)
{
    json_t *a = job_store_list(jm->store, filter);
    pthread_mutex_lock(&jm->lock);
    size_t i;
    json_t *o;
    json_array_foreach(a, i, o)
    {
        job *j = jm_active_find(jm, json_integer_value(json_object_get(o, "id")));
        if (j)
            overlay_live(o, j);
    }
    pthread_mutex_unlock(&jm->lock);
    return a;
}

int job_manager_cancel(job_manager *jm, long long id, long long caller, const char **state_out,
                       aa_error *err)
{
    pthread_mutex_lock(&jm->lock);
    job *j = jm_active_find(jm, id);
    if (!j) {
        pthread_mutex_unlock(&jm->lock);
        json_t *o = job_store_get(jm->store, id, false);
        int rc = o ? aa_error_set(err, JM_EFINISHED, "", "job %lld has already finished", id)
                   : aa_error_set(err, JM_ENOENT, "id", JOB_MSG_NOT_FOUND, id);
        json_decref(o);
        return rc;
    }
    if (caller != 0 && !(j->owner < 0 || (caller >= 0 && caller == j->owner))) {
        pthread_mutex_unlock(&jm->lock);
        return aa_error_set(err, JM_EFORBIDDEN, "", "only the job's owner or root may cancel it");
    }
    if (j->unstored || j->cancelling) {
        pthread_mutex_unlock(&jm->lock);
        return aa_error_set(err, JM_EFINISHED, "", "job %lld has already finished", id);
    }
    if (j->state == JOB_QUEUED) {
        /* Out of the queue while the store is written outside the lock; back in it if the
         * store cannot be written (503), so it is never lost from both. */
        jm_queue_remove(jm, j);
        j->cancelling = true;
        pthread_mutex_unlock(&jm->lock);
        int rc = job_store_finish(jm->store, id, JOB_CANCELLED, 0, NULL, NULL, NULL, NULL,
                                  "cancelled by request before it ran", jm_now());
        pthread_mutex_lock(&jm->lock);
        j->cancelling = false;
        if (rc != AA_OK) {
            rc = jm_queue_push(jm, j);
            if (rc == AA_OK)
                jm_schedule_locked(jm);
            else
                jm_active_remove(jm, j); /* out of memory: the next start runs it */
            pthread_mutex_unlock(&jm->lock);
            if (rc != AA_OK)
                jm_job_free(j);
            return aa_error_set(err, JM_ESTORE, "", JOB_MSG_UNWRITABLE, id);
        }
        jm_active_remove(jm, j);
        pthread_mutex_unlock(&jm->lock);
        jm_job_free(j);
        *state_out = "cancelled";
        return JM_OK;
    }
    j->cancel_requested = true;
    if (j->paused)
        pthread_cond_signal(&j->resume);
    pthread_mutex_unlock(&jm->lock);
    *state_out = "running";
    return JM_OK;
}

json_t *job_manager_best_pattern(job_manager *jm, long long id, const char **why)
{
    json_t *o = job_manager_get(jm, id);
    if (!o) {
        *why = "no such job";
        return NULL;
    }
    /* A job's best is {"pattern", "e2"} (job_kind.h); a finished job's result knows its best
     * through its kind's row. */
    const json_t *p = json_object_get(json_object_get(o, "best"), "pattern");
    const job_kind *kind = job_kind_find(json_string_value(json_object_get(o, "kind")));
    json_t *result = json_object_get(o, "result");
    double e2;
    /* Only an encoded pattern (it has a form): animation's best names its pattern's family and
     * cost only. */
    json_t *out = json_is_object(p) && json_object_get(p, "form") ? json_deep_copy(p) : NULL;
    if (!out && kind && kind->best_of && json_is_object(result))
        out = kind->best_of(result, &e2);
    json_decref(o);
    if (!out)
        *why = "the job has no pattern (yet)";
    return out;
}

void job_manager_stats_get(job_manager *jm, long long viewer, job_manager_stats *out)
{
    memset(out, 0, sizeof *out);
    /* Counting by state scans the table: refresh at most every COUNTS_MAX_AGE seconds per
     * viewer so health probes stay cheap with a long job history. */
    double now = jm_now();
    size_t n = sizeof jm->counts / sizeof jm->counts[0], slot = n, oldest = 0;
    pthread_mutex_lock(&jm->counts_lock);
    for (size_t i = 0; i < n; i++) {
        if (jm->counts[i].viewer == viewer && jm->counts[i].at > -1e299)
            slot = i;
        if (jm->counts[i].at < jm->counts[oldest].at)
            oldest = i;
    }
    if (slot == n) {
        slot = oldest;
        jm->counts[slot].viewer = viewer;
        jm->counts[slot].at = -1e300;
    }
    if (now - jm->counts[slot].at > COUNTS_MAX_AGE || now < jm->counts[slot].at) {
        job_store_counts_visible(jm->store, viewer, jm->counts[slot].counts);
        jm->counts[slot].at = now;
    }
    memcpy(out->by_state, jm->counts[slot].counts, sizeof out->by_state);
    pthread_mutex_unlock(&jm->counts_lock);
    pthread_mutex_lock(&jm->lock);
    out->workers = jm->cfg.workers;
    out->busy = jm->busy;
    /* Queue and running counts as the viewer sees them: another user's private job is not
     * there for them (issue 35, point 9). */
    out->queued = viewer == JOB_VIEWER_ALL ? (int)jm->q_len : (int)out->by_state[JOB_QUEUED];
    out->running = viewer == JOB_VIEWER_ALL ? jm->running : (int)out->by_state[JOB_RUNNING];
    for (job *j = jm->active; j; j = j->next)
        out->paused += j->paused;
    out->queue_size = jm->cfg.queue_size;
    pthread_mutex_unlock(&jm->lock);
}

job_store *job_manager_store(job_manager *jm)
{
    return jm->store;
}

int job_manager_purge(job_manager *jm, long long id, long long caller, aa_error *err)
{
    pthread_mutex_lock(&jm->lock);
    job *j = jm_active_find(jm, id);
    long long owner = -1;
    job_state state = JOB_DONE;
    bool found = j != NULL, unstored = j && j->unstored;
    if (j) {
        owner = j->owner;
        state = j->state;
    }
    pthread_mutex_unlock(&jm->lock);
    if (!found && !job_store_owner(jm->store, id, &owner, &state, NULL))
        return aa_error_set(err, JM_ENOENT, "id", JOB_MSG_NOT_FOUND, id);
    if (caller != 0 && !(owner < 0 || (caller >= 0 && caller == owner)))
        return aa_error_set(err, JM_EFORBIDDEN, "", "only the job's owner or root may purge it");
    if (unstored) /* its end is not in the store yet: the store cannot be written */
        return aa_error_set(err, JM_ESTORE, "", JOB_MSG_UNWRITABLE, id);
    if (found && state != JOB_QUEUED)
        return aa_error_set(err, JM_EACTIVE, "", JOB_MSG_RUNNING, id);
    if (found) {
        /* Cancelled first. Its owner was checked above, so the refusals left are JM_ENOENT and
         * JM_ESTORE, and JM_EFINISHED, after which the record is deleted all the same. */
        const char *ignored;
        int rc = job_manager_cancel(jm, id, caller, &ignored, err);
        if (rc != JM_OK && rc != JM_EFINISHED)
            return rc;
    }
    /* A queued job that started meanwhile is still "running" in the store: refused. The store's
     * codes (JOB_STORE_ENOENT, _EACTIVE, a failed write) are answered from their rows. */
    int rc = job_store_delete(jm->store, id, err);
    /* Its shared files (possibly many, on a network file system) go in the probe thread's sweep,
     * not in this HTTP handler. */
    if (rc == AA_OK)
        cluster_probe_housekeep_soon(jm->probe);
    return rc;
}

void job_manager_slurm_status(job_manager *jm, cluster_status *out)
{
    cluster_probe_status(jm->probe, out);
}
