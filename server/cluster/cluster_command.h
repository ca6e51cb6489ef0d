/* Runs one external command (sbatch, squeue, scontrol, sacct, scancel) without a shell: argv is
 * spawned as is (PATH lookup), stdin is /dev/null, stdout and stderr are captured (each at most
 * CLUSTER_COMMAND_OUTPUT_MAX bytes, the rest discarded), and a command that outlives its timeout
 * is killed. Blocks the calling thread for at most the timeout: call it from the Slurm job
 * threads and the probe thread, never from an HTTP handler. */
#ifndef AALAB_CLUSTER_COMMAND_H
#define AALAB_CLUSTER_COMMAND_H

#include <stdbool.h>

#include "aa_core.h"

#define CLUSTER_COMMAND_OUTPUT_MAX (1 << 20)

typedef struct cluster_output {
    int exit_code;  /* the exit status, or 128 + signal when killed by one */
    bool timed_out; /* killed after the timeout */
    char *out;      /* NUL-terminated, never NULL after a successful run */
    char *err;
} cluster_output;

/* AA_OK when the command ran (whatever its exit code); AA_EINVAL when it could not be started
 * (err says why: not on PATH, ...), AA_ENOMEM. Free out with cluster_output_free. */
int cluster_command_run(char *const argv[], double timeout_seconds, cluster_output *out,
                        aa_error *err);
void cluster_output_free(cluster_output *out);
/* The first line of s, trimmed, at most cap-1 bytes, into buf (for messages). */
void cluster_first_line(const char *s, char *buf, size_t cap);

#endif
