/* Cached socket-group membership (group_membership.h). */
#define _GNU_SOURCE
#include "group_membership.h"
#include "aa_core.h"

#include <grp.h>
#include <pthread.h>
#include <pwd.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define CACHE_SLOTS 64

typedef struct slot {
    long long uid;
    bool member;
    double expires; /* 0 = empty */
} slot;

struct group_membership {
    pthread_mutex_t lock;
    gid_t gid;
    slot cache[CACHE_SLOTS];
};

group_membership *group_membership_create(gid_t gid)
{
    group_membership *gm = calloc(1, sizeof *gm);
    if (!gm)
        return NULL;
    pthread_mutex_init(&gm->lock, NULL);
    gm->gid = gid;
    return gm;
}

void group_membership_destroy(group_membership *gm)
{
    if (!gm)
        return;
    pthread_mutex_destroy(&gm->lock);
    free(gm);
}

/* The NSS lookup: getpwuid_r, then getgrouplist with a list grown as needed. */
static bool lookup(gid_t gid, uid_t uid)
{
    long cap = sysconf(_SC_GETPW_R_SIZE_MAX);
    size_t buflen = cap > 0 ? (size_t)cap : 16384;
    char *buf = malloc(buflen);
    struct passwd pw, *found = NULL;
    bool member = false;
    if (buf && getpwuid_r(uid, &pw, buf, buflen, &found) == 0 && found) {
        member = pw.pw_gid == gid;
        int n = 64;
        for (int tries = 0; !member && tries < 4; tries++) {
            gid_t *groups = malloc((size_t)n * sizeof *groups);
            if (!groups)
                break;
            int got = n;
            int rc = getgrouplist(pw.pw_name, pw.pw_gid, groups, &got);
            for (int i = 0; rc >= 0 && i < got && !member; i++)
                member = groups[i] == gid;
            free(groups);
            if (rc >= 0)
                break;
            n = got > n ? got : 2 * n;
        }
    }
    free(buf);
    return member;
}

bool group_membership_check(group_membership *gm, long long uid)
{
    if (uid == 0)
        return true;
    if (uid < 0 || uid > (long long)(uid_t)-1)
        return false;
    double now = aa_monotonic_seconds();
    pthread_mutex_lock(&gm->lock);
    for (int i = 0; i < CACHE_SLOTS; i++) {
        if (gm->cache[i].expires > now && gm->cache[i].uid == uid) {
            bool member = gm->cache[i].member;
            pthread_mutex_unlock(&gm->lock);
            return member;
        }
    }
    pthread_mutex_unlock(&gm->lock);
    /* Outside the lock: NSS may be slow (LDAP); two threads may look the same uid up. */
    bool member = lookup(gm->gid, (uid_t)uid);
    pthread_mutex_lock(&gm->lock);
    int victim = 0;
    for (int i = 1; i < CACHE_SLOTS; i++)
        if (gm->cache[i].expires < gm->cache[victim].expires)
            victim = i;
    gm->cache[victim] = (slot){.uid = uid, .member = member, .expires = now + GROUP_MEMBERSHIP_TTL};
    pthread_mutex_unlock(&gm->lock);
    return member;
}
