/* slurm_parse.h. */
#define _GNU_SOURCE
#include "slurm_parse.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

int slurm_parse_sbatch(const char *out, long long *job_id)
{
    while (*out && isspace((unsigned char)*out))
        out++;
    char *end;
    long long v = strtoll(out, &end, 10);
    if (end == out || v <= 0 || (*end && *end != ';' && !isspace((unsigned char)*end)))
        return AA_EINVAL;
    *job_id = v;
    return AA_OK;
}

typedef struct list {
    slurm_queued *v;
    size_t n, cap;
} list;

static int push(list *l, long long id, long index, const char *state, size_t state_len)
{
    if (l->n == l->cap) {
        size_t cap = l->cap ? l->cap * 2 : 32;
        slurm_queued *v = realloc(l->v, cap * sizeof *v);
        if (!v)
            return AA_ENOMEM;
        l->v = v;
        l->cap = cap;
    }
    slurm_queued *q = &l->v[l->n++];
    q->job_id = id;
    q->index = index;
    if (state_len >= sizeof q->state)
        state_len = sizeof q->state - 1;
    memcpy(q->state, state, state_len);
    q->state[state_len] = 0;
    return AA_OK;
}

/* "4-7,9%2" up to ']': pushes each index. Returns AA_OK, AA_ENOMEM or AA_EINVAL. */
static int push_ranges(list *l, long long id, const char *p, const char *state, size_t slen)
{
    /* A range so large is not ours (we submit at most --slurm-max-tasks): refuse to expand it. */
    const long max_expand = 1000000;
    long expanded = 0;
    for (;;) {
        char *end;
        long a = strtol(p, &end, 10);
        if (end == p || a < 0)
            return AA_EINVAL;
        long b = a;
        p = end;
        if (*p == '-') {
            b = strtol(p + 1, &end, 10);
            if (end == p + 1 || b < a)
                return AA_EINVAL;
            p = end;
        }
        if (*p == ':') { /* step: 1-9:2 */
            long step = strtol(p + 1, &end, 10);
            if (end == p + 1 || step < 1)
                return AA_EINVAL;
            p = end;
            for (long i = a; i <= b; i += step) {
                if (++expanded > max_expand || push(l, id, i, state, slen))
                    return AA_EINVAL;
            }
        } else {
            for (long i = a; i <= b; i++) {
                if (++expanded > max_expand)
                    return AA_EINVAL;
                if (push(l, id, i, state, slen))
                    return AA_ENOMEM;
            }
        }
        if (*p == '%') { /* the concurrency limit, not an index */
            strtol(p + 1, &end, 10);
            p = end;
        }
        if (*p == ',') {
            p++;
            continue;
        }
        return *p == ']' ? AA_OK : AA_EINVAL;
    }
}

int slurm_parse_squeue(const char *out, slurm_queued **items, size_t *count)
{
    list l = {0};
    const char *line = out;
    while (line && *line) {
        const char *eol = strchr(line, '\n');
        size_t len = eol ? (size_t)(eol - line) : strlen(line);
        const char *p = line, *end = line + len;
        while (p < end && isspace((unsigned char)*p))
            p++;
        const char *id_end = p;
        while (id_end < end && !isspace((unsigned char)*id_end))
            id_end++;
        const char *st = id_end;
        while (st < end && isspace((unsigned char)*st))
            st++;
        size_t slen = 0;
        while (st + slen < end && !isspace((unsigned char)st[slen]))
            slen++;
        char *e;
        long long id = p < id_end ? strtoll(p, &e, 10) : 0;
        if (id > 0 && slen > 0) {
            int rc = AA_OK;
            if (e == id_end) {
                rc = push(&l, id, -1, st, slen);
            } else if (*e == '_' && e[1] == '[') {
                size_t before = l.n;
                rc = push_ranges(&l, id, e + 2, st, slen);
                if (rc == AA_EINVAL)
                    l.n = before; /* skip the malformed line */
            } else if (*e == '_') {
                char *e2;
                long idx = strtol(e + 1, &e2, 10);
                if (e2 == id_end && idx >= 0)
                    rc = push(&l, id, idx, st, slen);
            }
            if (rc == AA_ENOMEM) {
                free(l.v);
                return AA_ENOMEM;
            }
        }
        line = eol ? eol + 1 : NULL;
    }
    *items = l.v;
    *count = l.n;
    return AA_OK;
}

bool slurm_squeue_invalid_id(const char *err_text)
{
    return err_text && strcasestr(err_text, "Invalid job id");
}

bool slurm_parse_scontrol_field(const char *out, const char *key, char *buf, size_t cap)
{
    size_t klen = strlen(key);
    for (const char *p = out; p && *p; p++) {
        /* A record ends at an empty line: read the first only. */
        if (p[0] == '\n' && p[1] == '\n')
            return false;
        if ((p == out || isspace((unsigned char)p[-1])) && !strncmp(p, key, klen) &&
            p[klen] == '=') {
            const char *v = p + klen + 1;
            size_t n = strcspn(v, " \t\r\n");
            if (n >= cap)
                n = cap - 1;
            memcpy(buf, v, n);
            buf[n] = 0;
            return true;
        }
    }
    return false;
}

static void copy_field(const char *s, size_t n, char *buf, size_t cap)
{
    if (n >= cap)
        n = cap - 1;
    memcpy(buf, s, n);
    buf[n] = 0;
}

bool slurm_parse_sacct(const char *out, const char *job, char *state, size_t state_cap,
                       char *exit_code, size_t exit_cap)
{
    size_t jlen = strlen(job);
    for (const char *line = out; line && *line;) {
        const char *eol = strchr(line, '\n');
        size_t len = eol ? (size_t)(eol - line) : strlen(line);
        const char *bar = memchr(line, '|', len);
        if (bar && (size_t)(bar - line) == jlen && !strncmp(line, job, jlen)) {
            const char *s = bar + 1;
            const char *bar2 = memchr(s, '|', len - (size_t)(s - line));
            if (bar2) {
                copy_field(s, (size_t)(bar2 - s), state, state_cap);
                const char *x = bar2 + 1;
                size_t xl = len - (size_t)(x - line);
                const char *bar3 = memchr(x, '|', xl);
                copy_field(x, bar3 ? (size_t)(bar3 - x) : xl, exit_code, exit_cap);
                /* "CANCELLED by 0" keeps its first word only. */
                state[strcspn(state, " ")] = 0;
                return true;
            }
        }
        line = eol ? eol + 1 : NULL;
    }
    return false;
}

bool slurm_accounting_disabled(const char *text)
{
    return text && strcasestr(text, "accounting storage is disabled");
}

bool slurm_parse_ping_up(const char *out)
{
    return out && strstr(out, " is UP");
}
