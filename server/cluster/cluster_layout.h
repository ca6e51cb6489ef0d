/* The shared directory every node sees (docs/cluster.md):
 *   DIR/job-<id>/stage-<s>/task-<i>.json    what shard i runs (written by the daemon)
 *                          output-<i>.json  its output (written by aalab-worker, atomically)
 *                          trace-<i>.json   its trace (aalab-worker, rewritten as it runs)
 *                          log-<i>.out      sbatch --output (log-%a.out)
 *                          array.sh         the batch script of the stage's array
 * and the atomic file write both sides use. */
#ifndef AALAB_CLUSTER_LAYOUT_H
#define AALAB_CLUSTER_LAYOUT_H

#include <stddef.h>

#include <jansson.h>

#include "aa_core.h"

/* DIR/job-<id>/stage-<s> into buf. AA_ERANGE when it does not fit. */
int cluster_stage_dir(const char *shared_dir, long long job_id, int stage, char *buf, size_t cap);
/* <stage dir>/<prefix>-<i>.<ext> ("task", "json"). */
int cluster_shard_path(const char *stage_dir, const char *prefix, long index, const char *ext,
                       char *buf, size_t cap);
/* mkdir -p of path (mode 0775). */
int cluster_mkdirs(const char *path, aa_error *err);
/* Writes data to path atomically: a temporary file in the same directory, fsync, rename, fsync
 * of the directory; a reader sees the old file or the whole new one. */
int cluster_write_atomic(const char *path, const char *data, size_t len, int mode, aa_error *err);
/* JSON (compact, reals with 17 significant digits) written with cluster_write_atomic. */
int cluster_write_json(const char *path, const json_t *value, aa_error *err);
/* Reads a JSON file strictly (JSON_REJECT_DUPLICATES); NULL when absent or invalid. */
json_t *cluster_read_json(const char *path);
/* The last lines of a text file (at most max_bytes, at most lines lines) into buf, newlines
 * as " | "; "" when unreadable. */
void cluster_file_tail(const char *path, int lines, size_t max_bytes, char *buf, size_t cap);

/* What TASK.json holds (format aalab-task/1). */
typedef struct cluster_task {
    long long job_id;
    const char *kind;
    const json_t *spec; /* the kind's spec, envelope and "kind" stripped */
    int stage;
    long shard_index;
    const json_t *shard; /* the plan's descriptor */
    const json_t *prior; /* merged state of the previous stage, NULL for stage 0 */
    const char *output;  /* absolute paths */
    const char *trace;
} cluster_task;

int cluster_write_task(const char *path, const cluster_task *task, aa_error *err);
/* array.sh: runs `worker <stage dir>/task-$SLURM_ARRAY_TASK_ID.json` (exec, no other shell
 * logic). */
int cluster_write_array_script(const char *stage_dir, const char *worker, aa_error *err);

#endif
