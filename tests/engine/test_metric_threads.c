/* The engine is documented thread-safe (no global mutable state; one workspace per thread):
 * four threads evaluate the same pattern, filter and acuity concurrently and must reproduce the
 * single-threaded results bit for bit. Meaningful mostly under -DAALAB_TSAN=ON / ASan. POSIX
 * threads rather than C11 thrd_create: ThreadSanitizer does not intercept the latter. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>
#include <pthread.h>

#include "aa_metric.h"
#include "aa_pattern.h"

#define THREADS 4
#define ROUNDS 20

typedef struct job {
    const aa_pattern *pattern;
    const aa_metric_params *params;
    double e2[ROUNDS];
    double e1_sum[ROUNDS];
    int rc;
} job;

static void *worker(void *arg)
{
    job *j = arg;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    for (int r = 0; r < ROUNDS; r++) {
        aa_evaluation ev;
        aa_error err;
        int rc = aa_evaluate(j->pattern, j->params, &ev, &err);
        if (rc) {
            j->rc = rc;
            break;
        }
        j->e2[r] = ev.e2;
        aa_evaluation_free(&ev);
        /* the low-level call with a per-thread workspace, too */
        double sum = 0.0;
        for (size_t k = 0; k < j->pattern->kernel_count; k++) {
            double e = 0.0;
            const aa_kernel *ker = &j->pattern->kernels[k];
            aa_e1_at_angle(j->params->filter, ker->samples, ker->count, 0.1 * (r + 1), &ws, &e);
            sum += e;
        }
        j->e1_sum[r] = sum;
    }
    aa_metric_workspace_free(&ws);
    return NULL;
}

static void test_concurrent_evaluation(void **state)
{
    (void)state;
    aa_filter f;
    aa_acuity a;
    aa_filter_default(&f);
    aa_acuity_naiman(&a);
    aa_pattern p;
    aa_error err;
    assert_int_equal(aa_pattern_from_preset(&p, aa_preset_find("hasselgren-e"), &err), AA_OK);
    aa_metric_params mp = {.filter = &f, .acuity = &a, .lp = 3.0};
    job single = {.pattern = &p, .params = &mp};
    worker(&single);
    assert_int_equal(single.rc, 0);
    job jobs[THREADS];
    pthread_t th[THREADS];
    for (int i = 0; i < THREADS; i++) {
        jobs[i] = (job){.pattern = &p, .params = &mp};
        assert_int_equal(pthread_create(&th[i], NULL, worker, &jobs[i]), 0);
    }
    for (int i = 0; i < THREADS; i++)
        pthread_join(th[i], NULL);
    for (int i = 0; i < THREADS; i++) {
        assert_int_equal(jobs[i].rc, 0);
        assert_memory_equal(jobs[i].e2, single.e2, sizeof single.e2);
        assert_memory_equal(jobs[i].e1_sum, single.e1_sum, sizeof single.e1_sum);
    }
    aa_pattern_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_concurrent_evaluation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
