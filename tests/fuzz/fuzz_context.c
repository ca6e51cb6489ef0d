/* The daemon context used by fuzz_request_handler: api_context_create() on embedded defaults
 * with a fresh temporary state directory and web directory, no listeners. Jobs are accepted
 * into a small queue; a single worker runs them (sleep jobs are cheap, optimisations are
 * bounded by their own max_seconds); synchronous renders are limited to tiny tiles. Created once
 * per fuzzing process; destroyed, and its directory removed, at exit. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "aa_core.h"
#include "api_context.h"
#include "token_store.h"
#include "config.h"
#include "fuzz_context.h"

static void write_file(const char *dir, const char *name, const char *text)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static char root[32];
static api_context *opened;

void fuzz_context_close(void)
{
    if (!opened)
        return;
    api_context_destroy(opened);
    opened = NULL;
    char cmd[sizeof root + 16];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
    if (system(cmd) != 0)
        fprintf(stderr, "fuzz_context: could not remove %s\n", root);
}

api_context *fuzz_context_open(void)
{
    static bool registered;
    snprintf(root, sizeof root, "/tmp/aalab-fuzz-XXXXXX");
    if (!mkdtemp(root)) {
        perror("mkdtemp");
        abort();
    }
    aalab_config cfg;
    config_defaults(&cfg);
    snprintf(cfg.state_dir, sizeof cfg.state_dir, "%s/state", root);
    snprintf(cfg.web_dir, sizeof cfg.web_dir, "%s/web", root);
    snprintf(cfg.socket_path, sizeof cfg.socket_path, "%s/unused.sock", root);
    cfg.tcp_host[0] = '\0';
    cfg.workers = 1;
    cfg.queue_size = 8;
    cfg.user_quota = 8;
    cfg.tile_bytes = 16u << 20;
    cfg.test_kinds = true;
    /* POST /v1/render runs synchronously in api_handle(): at the daemon's limits one render
     * takes seconds under ASan and starves the fuzzer (7 exec/s). Tiny tiles and a short
     * reference budget keep every render path (decode, render, budget exceeded, PNG, store)
     * reachable at a per-input cost of milliseconds. */
    cfg.render_max_pixels = 64;
    cfg.render_seconds = 0.02;
    char web[4200];
    snprintf(web, sizeof web, "%s/web", root);
    if (mkdir(web, 0700) != 0)
        abort();
    write_file(web, "index.html", "<!doctype html><title>fuzz</title>\n");
    write_file(root, "secret.txt", "outside the web dir\n");
    aa_error err;
    memset(&err, 0, sizeof err);
    api_context *ctx = api_context_create(&cfg, &err);
    if (!ctx) {
        fprintf(stderr, "api_context_create: %s (%s)\n", err.message, err.field);
        abort();
    }
    opened = ctx;
    if (!registered)
        atexit(fuzz_context_close);
    registered = true;
    return ctx;
}

const char *fuzz_context_token(api_context *ctx)
{
    /* Issued once per context (uid 1000, as a Unix-socket peer would get it) and kept. */
    static api_context *issued_for;
    static char token[160];
    if (issued_for != ctx) {
        json_t *out = NULL;
        token[0] = 0;
        if (token_store_issue(api_context_tokens(ctx), 1000, "fuzz", 32, &out, NULL) == AA_OK)
            snprintf(token, sizeof token, "%s", json_string_value(json_object_get(out, "token")));
        json_decref(out);
        issued_for = ctx;
    }
    return token[0] ? token : NULL;
}
