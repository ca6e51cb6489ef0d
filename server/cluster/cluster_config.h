/* How the daemon reaches Slurm (the --slurm-* flags). Slurm is configured when shared_dir is
 * set. */
#ifndef AALAB_CLUSTER_CONFIG_H
#define AALAB_CLUSTER_CONFIG_H

#define CLUSTER_PATH_MAX 4096

typedef struct cluster_config {
    char shared_dir[CLUSTER_PATH_MAX]; /* "" = Slurm not configured */
    char partition[128];               /* "" = the cluster's default partition */
    int max_tasks;                     /* most shards (array elements) per stage */
    int time_limit_minutes;            /* per task: sbatch --time */
    char sbatch_args[1024];            /* extra sbatch arguments, split on blanks */
    char worker[CLUSTER_PATH_MAX];     /* aalab-worker on the nodes */
    double poll_seconds;               /* between squeue polls */
} cluster_config;

#define CLUSTER_DEFAULT_MAX_TASKS 64
#define CLUSTER_DEFAULT_TIME_LIMIT 60
#define CLUSTER_DEFAULT_POLL 2.0

#endif
