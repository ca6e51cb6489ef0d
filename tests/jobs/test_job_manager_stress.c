/* Worker pool + job store under concurrent use (the ThreadSanitizer target of tests/tsan.sh, and
 * a plain unit test otherwise): 4 client threads submit short sleep jobs, cancel some (queued and
 * running), read and list jobs and stats while 3 workers run them; then every job must be in a
 * final state with a consistent record, and a reopened manager must see the same states. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>
#include <jansson.h>
#include <pthread.h>

#include "job_manager.h"

#define CLIENTS 4
#define JOBS_PER_CLIENT 40

typedef struct client {
    job_manager *jm;
    int index;
    long long ids[JOBS_PER_CLIENT];
    int submitted;
    int refused; /* queue full / quota */
} client;

static void nap_ms(long ms)
{
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

static const char *state_of(job_manager *jm, long long id, char *buf, size_t cap)
{
    json_t *j = job_manager_get(jm, id);
    snprintf(buf, cap, "%s", j ? json_string_value(json_object_get(j, "state")) : "(none)");
    json_decref(j);
    return buf;
}

static void *client_main(void *arg)
{
    client *c = arg;
    for (int i = 0; i < JOBS_PER_CLIENT; i++) {
        /* Mostly instant jobs, some 50 ms ones that are still running when cancelled. */
        json_t *spec = json_pack("{s:s, s:f}", "kind", "sleep", "seconds", i % 4 == 0 ? 0.05 : 0.0);
        long long id = 0;
        aa_error err;
        memset(&err, 0, sizeof err);
        int rc = job_manager_submit(c->jm, spec, 1000 + c->index, &id, &err);
        json_decref(spec);
        if (rc == JM_EQUEUE_FULL || rc == JM_EQUOTA) {
            c->refused++;
            nap_ms(2);
            continue;
        }
        assert_int_equal(rc, JM_OK);
        c->ids[c->submitted++] = id;
        if (i % 3 == 0) {
            const char *st = NULL;
            rc = job_manager_cancel(c->jm, id, 1000 + c->index, &st, NULL);
            assert_true(rc == JM_OK || rc == JM_EFINISHED);
        }
        if (i % 5 == 0) { /* another user may not cancel it */
            const char *st = NULL;
            rc = job_manager_cancel(c->jm, id, 5, &st, NULL);
            assert_true(rc == JM_EFORBIDDEN || rc == JM_EFINISHED);
        }
        char buf[32];
        state_of(c->jm, id, buf, sizeof buf);
        if (i % 7 == 0) {
            job_store_filter f = {.limit = 50, .state = -1, .viewer = JOB_VIEWER_ALL};
            json_t *l = job_manager_list(c->jm, &f);
            assert_non_null(l);
            json_decref(l);
            job_manager_stats s;
            job_manager_stats_get(c->jm, JOB_VIEWER_ALL, &s);
            assert_true(s.busy >= 0 && s.busy <= s.workers);
        }
    }
    return NULL;
}

static bool is_final(const char *s)
{
    return !strcmp(s, "done") || !strcmp(s, "cancelled") || !strcmp(s, "failed");
}

static void test_concurrent_submit_cancel_get(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-jmstress-XXXXXX";
    assert_non_null(mkdtemp(dir));
    job_manager_config cfg = {
        .workers = 3, .queue_size = 32, .user_quota = 24, .tiles = NULL, .test_kinds = true};
    aa_error err;
    memset(&err, 0, sizeof err);
    job_manager *jm = job_manager_create(dir, &cfg, &err);
    assert_non_null(jm);

    client cl[CLIENTS];
    pthread_t th[CLIENTS];
    for (int i = 0; i < CLIENTS; i++) {
        memset(&cl[i], 0, sizeof cl[i]);
        cl[i].jm = jm;
        cl[i].index = i;
        assert_int_equal(pthread_create(&th[i], NULL, client_main, &cl[i]), 0);
    }
    for (int i = 0; i < CLIENTS; i++)
        pthread_join(th[i], NULL);

    /* Everything settles within a few seconds. */
    int total = 0;
    char buf[32];
    for (int i = 0; i < CLIENTS; i++) {
        for (int k = 0; k < cl[i].submitted; k++) {
            int waited = 0;
            while (!is_final(state_of(jm, cl[i].ids[k], buf, sizeof buf)) && waited < 10000) {
                nap_ms(5);
                waited += 5;
            }
            assert_true(is_final(buf));
            total++;
        }
    }
    assert_true(total > 0);
    job_manager_stats s;
    job_manager_stats_get(jm, JOB_VIEWER_ALL, &s);
    assert_int_equal(s.queued, 0);
    assert_int_equal(s.running, 0);
    job_manager_destroy(jm);

    /* Reopen: the same final states from the store. */
    jm = job_manager_create(dir, &cfg, &err);
    assert_non_null(jm);
    for (int i = 0; i < CLIENTS; i++) {
        for (int k = 0; k < cl[i].submitted; k++)
            assert_true(is_final(state_of(jm, cl[i].ids[k], buf, sizeof buf)));
    }
    job_manager_destroy(jm);
    printf("jobs: %d run or cancelled by %d workers, %d refused (queue/quota)\n", total,
           cfg.workers, cl[0].refused + cl[1].refused + cl[2].refused + cl[3].refused);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

/* Shutdown while jobs are queued and running: no deadlock, no race, running jobs written back. */
static void test_shutdown_under_load(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-jmstress-XXXXXX";
    assert_non_null(mkdtemp(dir));
    job_manager_config cfg = {
        .workers = 2, .queue_size = 64, .user_quota = 64, .tiles = NULL, .test_kinds = true};
    aa_error err;
    memset(&err, 0, sizeof err);
    job_manager *jm = job_manager_create(dir, &cfg, &err);
    assert_non_null(jm);
    long long ids[20];
    for (int i = 0; i < 20; i++) {
        json_t *spec = json_pack("{s:s, s:f}", "kind", "sleep", "seconds", 5.0);
        assert_int_equal(job_manager_submit(jm, spec, 1000, &ids[i], &err), JM_OK);
        json_decref(spec);
    }
    nap_ms(50);
    job_manager_shutdown(jm);
    job_manager_destroy(jm);
    jm = job_manager_create(dir, &cfg, &err);
    assert_non_null(jm);
    char buf[32];
    for (int i = 0; i < 20; i++) {
        const char *st = state_of(jm, ids[i], buf, sizeof buf);
        assert_true(!strcmp(st, "queued") || !strcmp(st, "running") || !strcmp(st, "interrupted"));
        const char *after = NULL;
        job_manager_cancel(jm, ids[i], 1000, &after, NULL);
    }
    job_manager_destroy(jm);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_concurrent_submit_cancel_get),
        cmocka_unit_test(test_shutdown_under_load),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
