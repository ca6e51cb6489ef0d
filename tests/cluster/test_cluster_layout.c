/* Shared-dir layout (atomic writes, TASK.json, array.sh, log tail) and the trace merge. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "cluster_layout.h"
#include "cluster_trace.h"

static void test_task_and_script(void **state)
{
    (void)state;
    char root[] = "/tmp/aalab-layout-XXXXXX";
    assert_non_null(mkdtemp(root));
    char dir[4096];
    assert_int_equal(cluster_stage_dir(root, 42, 1, dir, sizeof dir), AA_OK);
    aa_error err = {0};
    assert_int_equal(cluster_mkdirs(dir, &err), AA_OK);
    char task[4200];
    assert_int_equal(cluster_shard_path(dir, "task", 3, "json", task, sizeof task), AA_OK);
    json_t *spec = json_pack("{s:f}", "seconds", 0.1);
    json_t *shard = json_pack("{s:i}", "index", 3);
    cluster_task t = {.job_id = 42,
                      .kind = "sleep",
                      .spec = spec,
                      .stage = 1,
                      .shard_index = 3,
                      .shard = shard,
                      .prior = NULL,
                      .output = "/x/output-3.json",
                      .trace = "/x/trace-3.json"};
    assert_int_equal(cluster_write_task(task, &t, &err), AA_OK);
    json_t *back = cluster_read_json(task);
    assert_non_null(back);
    assert_string_equal(json_string_value(json_object_get(back, "format")), "aalab-task/1");
    assert_int_equal(json_integer_value(json_object_get(back, "job_id")), 42);
    assert_int_equal(json_integer_value(json_object_get(back, "shard_index")), 3);
    assert_true(json_is_null(json_object_get(back, "prior")));
    assert_true(json_equal(json_object_get(back, "spec"), spec));
    json_decref(back);
    json_decref(spec);
    json_decref(shard);
    assert_int_equal(cluster_write_array_script(dir, "/opt/it's/aalab-worker", &err), AA_OK);
    char path[4200], text[1024];
    snprintf(path, sizeof path, "%s/array.sh", dir);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = 0;
    fclose(f);
    assert_non_null(strstr(text, "exec '/opt/it'\\''s/aalab-worker' '"));
    assert_non_null(strstr(text, "/task-\"${SLURM_ARRAY_TASK_ID}\".json"));
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_true(st.st_mode & S_IXUSR);

    /* Log tail: the last lines, newlines shown as " | ". */
    snprintf(path, sizeof path, "%s/log-3.out", dir);
    f = fopen(path, "w");
    for (int i = 0; i < 20; i++)
        fprintf(f, "line %d\n", i);
    fclose(f);
    char tail[256];
    cluster_file_tail(path, 3, 4096, tail, sizeof tail);
    assert_string_equal(tail, "line 17 | line 18 | line 19");
    cluster_file_tail("/nonexistent/log", 3, 4096, tail, sizeof tail);
    assert_string_equal(tail, "");
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
    assert_int_equal(system(cmd), 0);
}

static void test_trace_merge(void **state)
{
    (void)state;
    /* Shard 0 starts 1 s after submission, shard 1 after 3 s. */
    json_t *a =
        json_pack("{s:f,s:[{s:f,s:i,s:i,s:f},{s:f,s:i,s:i,s:f}]}", "started_unix", 101.0, "points",
                  "seconds", 0.0, "iterations", 0, "evaluations", 0, "best_e2", 0.5, "seconds", 4.0,
                  "iterations", 100, "evaluations", 200, "best_e2", 0.3);
    json_t *b = json_pack("{s:f,s:[{s:f,s:i,s:i,s:f},{s:f,s:i,s:i,s:f}]}", "started_unix", 103.0,
                          "points", "seconds", 0.0, "iterations", 0, "evaluations", 0, "best_e2",
                          0.4, "seconds", 1.0, "iterations", 50, "evaluations", 60, "best_e2", 0.6);
    json_t *traces[] = {a, NULL, b};
    json_t *m = cluster_trace_merge(traces, 3, 100.0);
    assert_non_null(m);
    /* t=1 best 0.5; t=3 best 0.4 (shard 1); t=4 no improvement; t=5 best 0.3 with counts
     * 100+50 and 200+60. */
    assert_int_equal(json_array_size(m), 3);
    double want_t[] = {1.0, 3.0, 5.0}, want_e2[] = {0.5, 0.4, 0.3};
    for (size_t i = 0; i < 3; i++) {
        json_t *p = json_array_get(m, i);
        assert_float_equal(json_real_value(json_object_get(p, "seconds")), want_t[i], 1e-9);
        assert_float_equal(json_real_value(json_object_get(p, "best_e2")), want_e2[i], 1e-12);
    }
    json_t *last = json_array_get(m, 2);
    assert_int_equal(json_integer_value(json_object_get(last, "iterations")), 150);
    assert_int_equal(json_integer_value(json_object_get(last, "evaluations")), 260);
    json_decref(m);
    json_decref(a);
    json_decref(b);
    m = cluster_trace_merge(NULL, 0, 0);
    assert_int_equal(json_array_size(m), 0);
    json_decref(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_task_and_script),
        cmocka_unit_test(test_trace_merge),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
