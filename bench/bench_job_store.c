/* Job list benchmark: GET /v1/jobs's store read (job_store_list, 500 newest of 10,000 jobs, from
 * the covering index) beside the list as it was read before (the same rows with their best
 * column, each best parsed as JSON to find its e2), on the same database in the same run.
 * The jobs are written in one transaction with the columns the store writes; each best is an
 * encoded pattern of BEST_SAMPLES samples with kernels_expanded (a few KB, as optimize jobs
 * store them), and every 1000th job has a 1 MB best. Prints p50/p99 of each and the ratio. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <jansson.h>
#include <sqlite3.h>

#include "aa_core.h"
#include "job_store.h"

#define JOBS 10000
#define LIMIT 500
#define RUNS 60
#define BEST_SAMPLES 64

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static char *best_text(int i, double e2)
{
    json_t *kernels = json_array(), *expanded = json_array();
    for (int k = 0; k < BEST_SAMPLES; k++) {
        double x = ((i * 31 + k * 17) % 1000) / 1000.0 - 0.5, y = ((k * 7) % 100) / 100.0 - 0.5;
        json_array_append_new(kernels, json_pack("[fff]", x, y, 1.0 / BEST_SAMPLES));
        json_array_append_new(expanded, json_pack("[fff]", x, y, 1.0 / BEST_SAMPLES));
    }
    json_t *best = json_pack("{s:{s:s,s:f,s:s,s:[o],s:[o]},s:f}", "pattern", "family", "P(1,1,64)",
                             "cost_spp", 64.0, "form", "kernels", "kernels", kernels,
                             "kernels_expanded", expanded, "e2", e2);
    if (i % 1000 == 0) {
        char *pad = malloc(1000001);
        memset(pad, 'x', 1000000);
        pad[1000000] = 0;
        json_object_set_new(best, "pad", json_string(pad));
        free(pad);
    }
    char *s = json_dumps(best, JSON_COMPACT);
    json_decref(best);
    return s;
}

static int fill(const char *path)
{
    sqlite3 *db;
    if (sqlite3_open(path, &db) != SQLITE_OK)
        return -1;
    sqlite3_exec(db, "BEGIN", NULL, NULL, NULL);
    sqlite3_stmt *q;
    int rc = sqlite3_prepare_v2(
        db,
        "INSERT INTO jobs(kind, owner_uid, state, progress, spec, best, trace, result, created, "
        "started, finished, best_e2, family, visibility, bytes) VALUES ('optimize', ?, 'done', "
        "1, '{\"kind\":\"optimize\",\"family\":\"P(1,1,64)\"}', ?, '[]', ?, ?, ?, ?, ?, "
        "'P(1,1,64)', ?, ?)",
        -1, &q, NULL);
    for (int i = 0; rc == SQLITE_OK && i < JOBS; i++) {
        double e2 = 0.2 + (i % 997) / 2000.0;
        char *best = best_text(i, e2);
        sqlite3_bind_int(q, 1, 1000 + i % 3);
        sqlite3_bind_text(q, 2, best, -1, SQLITE_TRANSIENT);
        sqlite3_bind_text(q, 3, best, -1, SQLITE_TRANSIENT);
        sqlite3_bind_double(q, 4, 1e9 + i);
        sqlite3_bind_double(q, 5, 1e9 + i);
        sqlite3_bind_double(q, 6, 1e9 + i + 1);
        sqlite3_bind_double(q, 7, e2);
        sqlite3_bind_text(q, 8, i % 50 ? "team" : "private", -1, SQLITE_STATIC);
        sqlite3_bind_int64(q, 9, 2 * (long long)strlen(best) + 40);
        free(best);
        rc = sqlite3_step(q) == SQLITE_DONE ? SQLITE_OK : SQLITE_ERROR;
        sqlite3_reset(q);
    }
    sqlite3_finalize(q);
    sqlite3_exec(db, rc == SQLITE_OK ? "COMMIT" : "ROLLBACK", NULL, NULL, NULL);
    sqlite3_close(db);
    return rc == SQLITE_OK ? 0 : -1;
}

/* The list as read before: row by row from the table, best parsed for its e2. */
static size_t old_list(sqlite3 *db)
{
    sqlite3_stmt *q;
    size_t n = 0;
    json_t *a = json_array();
    if (sqlite3_prepare_v2(db,
                           "SELECT id, kind, owner_uid, state, progress, created, started, "
                           "finished, reason, error, best FROM jobs ORDER BY id DESC LIMIT ?",
                           -1, &q, NULL) != SQLITE_OK)
        return 0;
    sqlite3_bind_int(q, 1, LIMIT);
    while (sqlite3_step(q) == SQLITE_ROW) {
        json_t *o = json_pack(
            "{s:I,s:s,s:I,s:s,s:f,s:f,s:f,s:f}", "id", (json_int_t)sqlite3_column_int64(q, 0),
            "kind", (const char *)sqlite3_column_text(q, 1), "owner_uid",
            (json_int_t)sqlite3_column_int64(q, 2), "state",
            (const char *)sqlite3_column_text(q, 3), "progress", sqlite3_column_double(q, 4),
            "created", sqlite3_column_double(q, 5), "started", sqlite3_column_double(q, 6),
            "finished", sqlite3_column_double(q, 7));
        json_t *best = json_loads((const char *)sqlite3_column_text(q, 10), 0, NULL);
        json_t *e2 = json_object_get(best, "e2");
        if (json_is_number(e2))
            json_object_set(o, "best_e2", e2);
        json_decref(best);
        json_array_append_new(a, o);
        n++;
    }
    sqlite3_finalize(q);
    char *text = json_dumps(a, JSON_COMPACT);
    free(text);
    json_decref(a);
    return n;
}

static size_t new_list(job_store *st)
{
    job_store_filter f = {.limit = LIMIT, .state = -1, .viewer = JOB_VIEWER_ALL};
    json_t *a = job_store_list(st, &f);
    size_t n = json_array_size(a);
    char *text = json_dumps(a, JSON_COMPACT);
    free(text);
    json_decref(a);
    return n;
}

static void report(const char *label, double *t, double baseline_p50)
{
    qsort(t, RUNS, sizeof *t, cmp_double);
    double p50 = t[RUNS / 2], p99 = t[(RUNS * 99) / 100];
    printf("%-44s p50 %8.2f ms  p99 %8.2f ms", label, p50 * 1e3, p99 * 1e3);
    if (baseline_p50 > 0)
        printf("  (%.1fx faster at p50)", baseline_p50 / p50);
    printf("\n");
}

int main(void)
{
    char dir[] = "/tmp/aalab-bench-store-XXXXXX";
    if (!mkdtemp(dir))
        return 1;
    aa_error err = {0};
    job_store *st = job_store_open(dir, &err);
    if (!st) {
        fprintf(stderr, "open: %s\n", err.message);
        return 1;
    }
    job_store_close(st);
    char path[128];
    snprintf(path, sizeof path, "%s/jobs.db", dir);
    double t0 = aa_monotonic_seconds();
    if (fill(path)) {
        fprintf(stderr, "fill failed\n");
        return 1;
    }
    st = job_store_open(dir, &err);
    sqlite3 *db;
    sqlite3_open_v2(path, &db, SQLITE_OPEN_READONLY, NULL);
    printf("bench_job_store: %d jobs written in %.1f s; list of the %d newest, %d runs each\n",
           JOBS, aa_monotonic_seconds() - t0, LIMIT, RUNS);
    static double t_old[RUNS], t_new[RUNS];
    size_t n_old = 0, n_new = 0;
    for (int r = 0; r < RUNS; r++) {
        double a = aa_monotonic_seconds();
        n_old = old_list(db);
        double b = aa_monotonic_seconds();
        n_new = new_list(st);
        double c = aa_monotonic_seconds();
        t_old[r] = b - a;
        t_new[r] = c - b;
    }
    report("before: rows + best parsed (baseline)", t_old, 0);
    qsort(t_old, RUNS, sizeof *t_old, cmp_double);
    report("job_store_list: covering index, no JSON", t_new, t_old[RUNS / 2]);
    printf("rows: %zu / %zu\n", n_old, n_new);
    sqlite3_close(db);
    job_store_close(st);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 && n_old == n_new ? 0 : 1;
}
