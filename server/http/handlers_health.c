/* GET /v1/health: version, uptime, workers, queue, jobs by state, caches, Slurm. */
#include <stdio.h>
#include <string.h>

#include "aalab_version.h"
#include "handlers.h"

#include "eval_cache.h"
#include "job_manager.h"

void handle_health(api_context *ctx, const api_request *req, api_response *resp)
{
    job_manager_stats st;
    /* Only what the caller may see is counted (root on the socket sees every job). */
    long long viewer = req->caller.admin      ? JOB_VIEWER_ALL
                       : req->caller.uid >= 0 ? req->caller.uid
                                              : -2;
    job_manager_stats_get(api_context_jobs(ctx), viewer, &st);
    json_t *by_state = json_object();
    for (int i = 0; i < JOB_STATE_COUNT; i++)
        json_object_set_new(by_state, job_state_name((job_state)i), json_integer(st.by_state[i]));
    eval_cache_stats cs;
    eval_cache_stats_get(api_context_eval_cache(ctx), &cs);
    json_t *kinds = json_array();
    size_t kind_count;
    const job_kind *const *table = job_kinds_table(&kind_count);
    for (size_t k = 0; k < kind_count; k++)
        if (job_manager_kind(api_context_jobs(ctx), table[k]->name))
            json_array_append_new(kinds, json_string(table[k]->name));
    json_t *o = json_pack(
        "{s:s,s:s,s:f,s:{s:i,s:i},s:{s:i,s:i,s:i},s:o,s:o,s:{s:I,s:I,s:I,s:I,s:I},s:b,s:b}",
        "status", "ok", "version", aalab_version, "uptime_seconds", api_context_uptime(ctx),
        "workers", "count", st.workers, "busy", st.busy, "queue", "length", st.queued, "capacity",
        st.queue_size, "running", st.running, "jobs", by_state, "job_kinds", kinds, "eval_cache",
        "entries", (json_int_t)cs.entries, "capacity", (json_int_t)cs.capacity, "bytes",
        (json_int_t)cs.bytes, "hits", (json_int_t)cs.hits, "misses", (json_int_t)cs.misses,
        "render", api_context_tiles(ctx) != NULL, "tcp", req->via_tcp);
    /* Sharing: workers held by paused jobs are free for other users' jobs. */
    const aalab_config *cfg = api_context_config(ctx);
    json_object_set_new(json_object_get(o, "workers"), "paused", json_integer(st.paused));
    json_object_set_new(o, "sharing",
                        json_pack("{s:I,s:f,s:f,s:I,s:I}", "user_workers",
                                  (json_int_t)cfg->user_workers, "job_slice_seconds",
                                  cfg->job_slice, "max_job_seconds", cfg->max_job_seconds,
                                  "user_evaluates", (json_int_t)cfg->user_evaluates, "user_renders",
                                  (json_int_t)cfg->user_renders));
    /* The Slurm executor, from the probe thread's last scontrol ping (never asked here). */
    cluster_status slurm;
    job_manager_slurm_status(api_context_jobs(ctx), &slurm);
    json_object_set_new(o, "slurm",
                        json_pack("{s:b,s:o,s:s}", "configured", slurm.configured, "answering",
                                  slurm.configured && slurm.answering >= 0
                                      ? json_boolean(slurm.answering == 1)
                                      : json_null(),
                                  "message", slurm.message));
    /* "tcp" says how this request came; tcp_listener whether the daemon listens on TCP at all
     * (--tcp or socket activation), so a socket client sees the dashboard is on. */
    json_object_set_new(o, "tcp_listener", json_boolean(cfg->tcp_port > 0));
    /* Where the dashboard is, so `aalab token` can print its URL (--tcp; a socket-activated
     * listener is not known here). */
    if (o && cfg->tcp_port > 0) {
        char url[128];
        snprintf(url, sizeof url, "http://%s:%d/",
                 strchr(cfg->tcp_host, ':') ? "[::1]" : cfg->tcp_host, cfg->tcp_port);
        json_object_set_new(o, "dashboard", json_string(url));
    }
    api_reply_json(resp, 200, o);
    resp->cache_control = "no-store";
}
