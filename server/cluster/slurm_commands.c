/* slurm_commands.h. */
#define _GNU_SOURCE
#include "slurm_commands.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cluster_command.h"

#define MAX_ARGS 96

/* "A,B,C" into buf; false when it does not fit. */
static bool join_ids(const long long *ids, size_t n, char *buf, size_t cap)
{
    size_t len = 0;
    buf[0] = 0;
    for (size_t i = 0; i < n; i++) {
        int w = snprintf(buf + len, cap - len, "%s%lld", i ? "," : "", ids[i]);
        if (w < 0 || (size_t)w >= cap - len)
            return false;
        len += (size_t)w;
    }
    return true;
}

/* Runs argv; on a failed start or nonzero exit fills err with the command's first stderr
 * line and returns AA_EINVAL. out stays valid (caller frees) when AA_OK or a nonzero exit. */
static int run(char **argv, cluster_output *out, aa_error *err)
{
    int rc = cluster_command_run(argv, SLURM_COMMAND_TIMEOUT, out, err);
    if (rc)
        return rc;
    if (out->timed_out)
        return aa_error_set(err, AA_EINVAL, "", "%s did not answer within %.0f s", argv[0],
                            SLURM_COMMAND_TIMEOUT);
    if (out->exit_code) {
        char line[160];
        cluster_first_line(out->err[0] ? out->err : out->out, line, sizeof line);
        return aa_error_set(err, AA_EINVAL, "", "%s failed (exit %d): %s", argv[0], out->exit_code,
                            line);
    }
    return AA_OK;
}

int slurm_sbatch(const slurm_submit *s, long long *job_id, aa_error *err)
{
    char name[160], output[4200], array[64], time[32], partition[200];
    char *argv[MAX_ARGS];
    int n = 0;
    argv[n++] = "sbatch";
    argv[n++] = "--parsable";
    snprintf(array, sizeof array, "--array=%s", s->array);
    argv[n++] = array;
    snprintf(name, sizeof name, "--job-name=%s", s->job_name);
    argv[n++] = name;
    if (snprintf(output, sizeof output, "--output=%s", s->output) >= (int)sizeof output)
        return aa_error_set(err, AA_EINVAL, "", "the log path is too long");
    argv[n++] = output;
    snprintf(time, sizeof time, "--time=%d", s->time_minutes);
    argv[n++] = time;
    if (s->partition && s->partition[0]) {
        snprintf(partition, sizeof partition, "--partition=%s", s->partition);
        argv[n++] = partition;
    }
    char *extra = s->extra_args ? strdup(s->extra_args) : NULL;
    if (s->extra_args && !extra)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    char *save = NULL;
    for (char *tok = extra ? strtok_r(extra, " \t\n", &save) : NULL; tok;
         tok = strtok_r(NULL, " \t\n", &save)) {
        if (n >= MAX_ARGS - 2) {
            free(extra);
            return aa_error_set(err, AA_EINVAL, "", "too many --slurm-sbatch-args");
        }
        argv[n++] = tok;
    }
    argv[n++] = (char *)s->script;
    argv[n] = NULL;
    cluster_output out;
    int rc = run(argv, &out, err);
    free(extra);
    if (!rc && slurm_parse_sbatch(out.out, job_id)) {
        char line[120];
        cluster_first_line(out.out, line, sizeof line);
        rc = aa_error_set(err, AA_EINVAL, "", "sbatch printed no job id: '%s'", line);
    }
    cluster_output_free(&out);
    return rc;
}

int slurm_squeue(const long long *ids, size_t n, slurm_queued **items, size_t *count, aa_error *err)
{
    *items = NULL;
    *count = 0;
    if (n == 0)
        return AA_OK;
    char list[4096];
    if (!join_ids(ids, n, list, sizeof list))
        return aa_error_set(err, AA_EINVAL, "", "too many arrays to ask squeue about");
    char *argv[] = {"squeue", "-h", "-r", "-j", list, "-o", "%i %T", NULL};
    cluster_output out;
    int rc = run(argv, &out, err);
    if (rc == AA_EINVAL && out.err && slurm_squeue_invalid_id(out.err)) {
        cluster_output_free(&out);
        return AA_OK; /* every one of them is gone from the controller */
    }
    if (!rc)
        rc = slurm_parse_squeue(out.out, items, count);
    cluster_output_free(&out);
    return rc == AA_ENOMEM ? aa_error_set(err, AA_ENOMEM, "", "out of memory") : rc;
}

int slurm_squeue_by_name(const char *name, long long *ids, size_t cap, aa_error *err)
{
    char uid[24];
    snprintf(uid, sizeof uid, "%u", (unsigned)getuid());
    char *argv[] = {"squeue", "-h", "-r", "-u", uid, "-n", (char *)name, "-o", "%i %T", NULL};
    cluster_output out;
    int rc = run(argv, &out, err);
    slurm_queued *q = NULL;
    size_t count = 0, n = 0;
    if (!rc)
        rc = slurm_parse_squeue(out.out, &q, &count);
    cluster_output_free(&out);
    if (rc)
        return rc == AA_ENOMEM ? aa_error_set(err, AA_ENOMEM, "", "out of memory") : rc;
    for (size_t k = 0; k < count; k++) {
        bool seen = false;
        for (size_t m = 0; m < n && m < cap; m++)
            seen |= ids[m] == q[k].job_id;
        if (!seen) {
            if (n < cap)
                ids[n] = q[k].job_id;
            n++;
        }
    }
    free(q);
    return (int)(n < cap ? n : cap);
}

int slurm_scancel(const long long *ids, size_t n, aa_error *err)
{
    if (n == 0)
        return AA_OK;
    char *argv[MAX_ARGS];
    char text[MAX_ARGS][24];
    size_t k = 0;
    argv[k++] = "scancel";
    int rc = AA_OK;
    for (size_t i = 0; i < n; i++) {
        snprintf(text[k], sizeof text[k], "%lld", ids[i]);
        argv[k] = text[k];
        k++;
        if (k == MAX_ARGS - 1 || i + 1 == n) {
            argv[k] = NULL;
            cluster_output out;
            int r = run(argv, &out, err);
            cluster_output_free(&out);
            if (r)
                rc = r;
            k = 1;
        }
    }
    return rc;
}

void slurm_describe_task(long long array_id, long index, char *buf, size_t cap)
{
    char job[48];
    snprintf(job, sizeof job, "%lld_%ld", array_id, index);
    char *show[] = {"scontrol", "show", "job", job, NULL};
    cluster_output out;
    aa_error err = {0};
    char state[64], exit_code[32], reason[96];
    if (!run(show, &out, &err) &&
        slurm_parse_scontrol_field(out.out, "JobState", state, sizeof state)) {
        if (!slurm_parse_scontrol_field(out.out, "ExitCode", exit_code, sizeof exit_code))
            snprintf(exit_code, sizeof exit_code, "?");
        if (!slurm_parse_scontrol_field(out.out, "Reason", reason, sizeof reason))
            snprintf(reason, sizeof reason, "None");
        snprintf(buf, cap, "state %s, exit code %s, reason %s", state, exit_code, reason);
        cluster_output_free(&out);
        return;
    }
    cluster_output_free(&out);
    /* The controller forgets finished jobs after MinJobAge: ask accounting, where it exists. */
    char *acct[] = {"sacct", "-n", "-P", "-j", job, "-o", "JobID,State,ExitCode", NULL};
    int rc = run(acct, &out, &err);
    if (!rc && slurm_parse_sacct(out.out, job, state, sizeof state, exit_code, sizeof exit_code))
        snprintf(buf, cap, "state %s, exit code %s (sacct)", state, exit_code);
    else if (out.err && slurm_accounting_disabled(out.err))
        snprintf(buf, cap,
                 "state unknown (no longer known to scontrol; accounting storage is "
                 "disabled)");
    else
        snprintf(buf, cap, "state unknown (neither scontrol nor sacct knows %s)", job);
    cluster_output_free(&out);
}

bool slurm_ping(char *message, size_t cap)
{
    char *argv[] = {"scontrol", "ping", NULL};
    cluster_output out;
    aa_error err = {0};
    int rc = cluster_command_run(argv, 15.0, &out, &err);
    if (rc) {
        snprintf(message, cap, "%s", err.message);
        return false;
    }
    char line[160];
    cluster_first_line(out.out[0] ? out.out : out.err, line, sizeof line);
    bool up = !out.timed_out && slurm_parse_ping_up(out.out);
    if (out.timed_out)
        snprintf(message, cap, "scontrol ping did not answer within 15 s");
    else
        snprintf(message, cap, "%s", line[0] ? line : "scontrol ping printed nothing");
    cluster_output_free(&out);
    return up;
}
