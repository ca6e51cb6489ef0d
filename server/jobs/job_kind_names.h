/* The names of job kinds as messages and usage texts list them, read from the kind table
 * (job_kinds.c), so that no text keeps a second list of kinds. */
#ifndef AALAB_JOB_KIND_NAMES_H
#define AALAB_JOB_KIND_NAMES_H

#include <stdbool.h>
#include <stddef.h>

/* Writes the names of the kinds in table order into buf (at most cap bytes, cut short if it
 * does not fit), ", " between them and last_join before the last. Test-only kinds only with
 * test_kinds; with split_only, only the kinds that split into shards (job_split.h), which are
 * the ones that can run on Slurm and in aalab-worker. */
void job_kind_names_join(char *buf, size_t cap, bool test_kinds, bool split_only,
                         const char *last_join);

#endif
