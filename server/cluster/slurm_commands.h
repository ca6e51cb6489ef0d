/* The Slurm commands the executor runs (found on PATH; SLURM_CONF from the environment), each
 * through cluster_command (no shell, bounded time) and parsed with slurm_parse. They block the
 * caller for up to SLURM_COMMAND_TIMEOUT seconds: Slurm job threads and the probe only. */
#ifndef AALAB_SLURM_COMMANDS_H
#define AALAB_SLURM_COMMANDS_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_core.h"
#include "slurm_parse.h"

#define SLURM_COMMAND_TIMEOUT 30.0

typedef struct slurm_submit {
    const char *script;     /* array.sh */
    const char *job_name;   /* aalab-<id>-s<stage> */
    const char *output;     /* log path with %a */
    const char *array;      /* "0-7" or "3" */
    int time_minutes;       /* --time */
    const char *partition;  /* "" or NULL: the cluster's default */
    const char *extra_args; /* split on blanks, no shell; may be NULL */
} slurm_submit;

/* sbatch --parsable ...: the new array's job id. err carries sbatch's first line on failure. */
int slurm_sbatch(const slurm_submit *s, long long *job_id, aa_error *err);
/* squeue -h -r -j ID,... -o '%i %T': what is still queued or running of those jobs (ids the
 * controller forgot give an empty list). AA_EINVAL when squeue failed (err says why): the
 * caller must then not conclude that anything left the queue. */
int slurm_squeue(const long long *ids, size_t n, slurm_queued **items, size_t *count,
                 aa_error *err);
/* squeue -h -r -u <this uid> -n NAME -o '%i %T': the arrays of that job name still known to
 * the controller (their distinct job ids into ids, at most cap; returns how many, or a
 * negative code when squeue failed). */
int slurm_squeue_by_name(const char *name, long long *ids, size_t cap, aa_error *err);
/* scancel ID... */
int slurm_scancel(const long long *ids, size_t n, aa_error *err);
/* Slurm's account of one array element for a failure message: "state FAILED, exit code 1:0,
 * reason NonZeroExitCode" from scontrol show job, else from sacct where accounting exists,
 * else "state unknown (...)". Never fails. */
void slurm_describe_task(long long array_id, long index, char *buf, size_t cap);
/* scontrol ping: true when a controller answers UP; message says what was seen. */
bool slurm_ping(char *message, size_t cap);

#endif
