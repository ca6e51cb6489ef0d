/* cluster_sweep.h. */
#define _XOPEN_SOURCE 700 /* nftw */
#include "cluster_sweep.h"

#include <dirent.h>
#include <errno.h>
#include <ftw.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

/* Depth first (FTW_DEPTH): files before their directory; symlinks are removed, not followed
 * (FTW_PHYS). */
static int remove_entry(const char *path, const struct stat *sb, int type, struct FTW *ftw)
{
    (void)sb;
    (void)type;
    (void)ftw;
    return remove(path) && errno != ENOENT ? -1 : 0;
}

int cluster_remove_job_dir(const char *shared_dir, long long job_id, aa_error *err)
{
    char dir[4096];
    if ((size_t)snprintf(dir, sizeof dir, "%s/job-%lld", shared_dir, job_id) >= sizeof dir)
        return aa_error_set(err, AA_ERANGE, "", "--slurm-shared-dir is too long");
    struct stat st;
    if (lstat(dir, &st))
        return errno == ENOENT
                   ? AA_OK
                   : aa_error_set(err, AA_EINVAL, "", "%.120s: %s", dir, strerror(errno));
    if (nftw(dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS))
        return aa_error_set(err, AA_EINVAL, "", "cannot remove %.120s: %s", dir, strerror(errno));
    return AA_OK;
}

/* "job-<digits>" exactly: anything else in the shared directory is not ours to remove. */
static bool job_dir_name(const char *name, long long *id)
{
    if (strncmp(name, "job-", 4) || !name[4])
        return false;
    long long v = 0;
    for (const char *c = name + 4; *c; c++) {
        if (*c < '0' || *c > '9' || v > (1LL << 55))
            return false;
        v = v * 10 + (*c - '0');
    }
    *id = v;
    return true;
}

int cluster_sweep_orphans(const char *shared_dir, cluster_job_known_fn known, void *user,
                          size_t *removed, aa_error *err)
{
    *removed = 0;
    DIR *d = opendir(shared_dir);
    if (!d)
        return aa_error_set(err, AA_EINVAL, "", "%.120s: %s", shared_dir, strerror(errno));
    int rc = AA_OK;
    struct dirent *e;
    while ((e = readdir(d))) {
        long long id;
        if (!job_dir_name(e->d_name, &id) || known(user, id))
            continue;
        aa_error one = {0};
        if (cluster_remove_job_dir(shared_dir, id, &one)) {
            if (!rc) { /* the first failure is reported; the sweep goes on */
                rc = AA_EINVAL;
                if (err)
                    *err = one;
            }
        } else {
            (*removed)++;
        }
    }
    closedir(d);
    return rc;
}
