/* cluster_layout.h. */
#define _GNU_SOURCE
#include "cluster_layout.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int cluster_stage_dir(const char *shared_dir, long long job_id, int stage, char *buf, size_t cap)
{
    int n = snprintf(buf, cap, "%s/job-%lld/stage-%d", shared_dir, job_id, stage);
    return n < 0 || (size_t)n >= cap ? AA_ERANGE : AA_OK;
}

int cluster_shard_path(const char *stage_dir, const char *prefix, long index, const char *ext,
                       char *buf, size_t cap)
{
    int n = snprintf(buf, cap, "%s/%s-%ld.%s", stage_dir, prefix, index, ext);
    return n < 0 || (size_t)n >= cap ? AA_ERANGE : AA_OK;
}

int cluster_mkdirs(const char *path, aa_error *err)
{
    char buf[4096];
    if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf)
        return aa_error_set(err, AA_ERANGE, "", "path too long");
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = 0;
        if (mkdir(buf, 0775) && errno != EEXIST)
            return aa_error_set(err, AA_EINVAL, "", "cannot create %.120s: %s", buf,
                                strerror(errno));
        *p = '/';
    }
    if (mkdir(buf, 0775) && errno != EEXIST)
        return aa_error_set(err, AA_EINVAL, "", "cannot create %.120s: %s", buf, strerror(errno));
    return AA_OK;
}

int cluster_write_atomic(const char *path, const char *data, size_t len, int mode, aa_error *err)
{
    char tmp[4200], dir[4200];
    if (snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid()) >= (int)sizeof tmp)
        return aa_error_set(err, AA_ERANGE, "", "path too long");
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash)
        *slash = 0;
    else
        snprintf(dir, sizeof dir, ".");
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, mode);
    if (fd < 0)
        return aa_error_set(err, AA_EINVAL, "", "cannot write %.120s: %s", tmp, strerror(errno));
    size_t off = 0;
    while (off < len) {
        ssize_t w = write(fd, data + off, len - off);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            break;
        off += (size_t)w;
    }
    int e = off == len && !fsync(fd) ? 0 : errno ? errno : EIO;
    if (close(fd) && !e)
        e = errno;
    if (!e && rename(tmp, path))
        e = errno;
    if (e) {
        unlink(tmp);
        return aa_error_set(err, AA_EINVAL, "", "cannot write %.120s: %s", path, strerror(e));
    }
    int dfd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        fsync(dfd);
        close(dfd);
    }
    return AA_OK;
}

int cluster_write_json(const char *path, const json_t *value, aa_error *err)
{
    char *text = json_dumps(value, JSON_COMPACT | JSON_REAL_PRECISION(17));
    if (!text)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    size_t len = strlen(text);
    char *line = realloc(text, len + 2);
    if (!line) {
        free(text);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    line[len] = '\n';
    line[len + 1] = 0;
    int rc = cluster_write_atomic(path, line, len + 1, 0664, err);
    free(line);
    return rc;
}

json_t *cluster_read_json(const char *path)
{
    json_error_t e;
    return json_load_file(path, JSON_REJECT_DUPLICATES, &e);
}

void cluster_file_tail(const char *path, int lines, size_t max_bytes, char *buf, size_t cap)
{
    buf[0] = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return;
    char *data = malloc(max_bytes + 1);
    if (!data) {
        fclose(f);
        return;
    }
    size_t n = 0;
    if (!fseek(f, 0, SEEK_END)) {
        long size = ftell(f);
        long start = size > (long)max_bytes ? size - (long)max_bytes : 0;
        if (!fseek(f, start, SEEK_SET))
            n = fread(data, 1, max_bytes, f);
    }
    fclose(f);
    while (n > 0 && (data[n - 1] == '\n' || data[n - 1] == '\r'))
        n--;
    data[n] = 0;
    /* Start after the lines-th newline from the end. */
    size_t start = 0;
    int seen = 0;
    for (size_t i = n; i > 0; i--) {
        if (data[i - 1] == '\n' && ++seen == lines) {
            start = i;
            break;
        }
    }
    size_t len = 0;
    for (size_t i = start; i < n && len + 4 < cap; i++) {
        char c = data[i];
        if (c == '\r')
            continue;
        if (c == '\n') {
            memcpy(buf + len, " | ", 3);
            len += 3;
        } else {
            buf[len++] = (c >= 32 && c < 127) || (unsigned char)c >= 128 ? c : '?';
        }
    }
    buf[len] = 0;
    free(data);
}

int cluster_write_task(const char *path, const cluster_task *t, aa_error *err)
{
    json_t *o =
        json_pack("{s:s,s:I,s:s,s:O,s:i,s:I,s:O,s:O,s:s,s:s}", "format", "aalab-task/1", "job_id",
                  (json_int_t)t->job_id, "kind", t->kind, "spec", t->spec, "stage", t->stage,
                  "shard_index", (json_int_t)t->shard_index, "shard", t->shard, "prior",
                  t->prior ? t->prior : json_null(), "output", t->output, "trace", t->trace);
    if (!o)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    int rc = cluster_write_json(path, o, err);
    json_decref(o);
    return rc;
}

/* 'text' with embedded single quotes closed and escaped, for the script. */
static int shell_quote(const char *s, char *buf, size_t cap)
{
    size_t n = 0;
    if (cap < 3)
        return AA_ERANGE;
    buf[n++] = '\'';
    for (; *s; s++) {
        if (n + 5 >= cap)
            return AA_ERANGE;
        if (*s == '\'') {
            memcpy(buf + n, "'\\''", 4);
            n += 4;
        } else {
            buf[n++] = *s;
        }
    }
    buf[n++] = '\'';
    buf[n] = 0;
    return AA_OK;
}

int cluster_write_array_script(const char *stage_dir, const char *worker, aa_error *err)
{
    char qw[8400], qd[8400], path[4200], text[17000];
    if (shell_quote(worker, qw, sizeof qw) || shell_quote(stage_dir, qd, sizeof qd) ||
        snprintf(path, sizeof path, "%s/array.sh", stage_dir) >= (int)sizeof path)
        return aa_error_set(err, AA_ERANGE, "", "path too long");
    /* The task file is named by the array index; nothing else is decided on the node. */
    int n = snprintf(text, sizeof text,
                     "#!/bin/sh\n"
                     "# aalab: one shard per array element (written by aalabd)\n"
                     "exec %s %s/task-\"${SLURM_ARRAY_TASK_ID}\".json\n",
                     qw, qd);
    if (n < 0 || (size_t)n >= sizeof text)
        return aa_error_set(err, AA_ERANGE, "", "path too long");
    return cluster_write_atomic(path, text, (size_t)n, 0775, err);
}
