/* Parsers of Slurm command output, pure functions on text (tests feed them canned output). */
#ifndef AALAB_SLURM_PARSE_H
#define AALAB_SLURM_PARSE_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_core.h"

/* sbatch --parsable prints "JOBID" or "JOBID;CLUSTER". AA_EINVAL when it is neither. */
int slurm_parse_sbatch(const char *out, long long *job_id);

/* One line of `squeue -h -r -o '%i %T'`: an array element ("123_4"), a range of elements
 * still pending together ("123_[4-7,9%2]", expanded into one entry each), or a plain job or
 * an array not split yet ("123": index -1). */
typedef struct slurm_queued {
    long long job_id; /* the array's job id */
    long index;       /* array task id, -1 for the whole job */
    char state[24];   /* PENDING, RUNNING, COMPLETING, ... */
} slurm_queued;

/* Parses every line into a new array (*items, free()); unparseable lines are skipped.
 * AA_ENOMEM. */
int slurm_parse_squeue(const char *out, slurm_queued **items, size_t *count);
/* squeue -j with ids the controller has forgotten (finished long ago) fails with this: for
 * the driver it means "none of them is queued". */
bool slurm_squeue_invalid_id(const char *err_text);

/* The value of KEY=VALUE in `scontrol show job` output (first record; values end at a blank
 * or line end). false when absent. */
bool slurm_parse_scontrol_field(const char *out, const char *key, char *buf, size_t cap);

/* `sacct -n -P -o JobID,State,ExitCode` lines "123_4|FAILED|1:0" (steps "123_4.batch" are
 * skipped): State and ExitCode of job (e.g. "123_4"). false when the job is not listed. */
bool slurm_parse_sacct(const char *out, const char *job, char *state, size_t state_cap,
                       char *exit_code, size_t exit_cap);
/* sacct on a cluster without accounting storage says so (on stderr, exit status 1). */
bool slurm_accounting_disabled(const char *text);

/* `scontrol ping`: "Slurmctld(primary) at host is UP" (a backup line may follow). true when
 * some controller is UP. */
bool slurm_parse_ping_up(const char *out);

#endif
