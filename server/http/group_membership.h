/* Is a token's owner (still) in the socket group? A token outlives a `gpasswd -d`: without this
 * check a user removed from the team would keep the TCP listener. Answers are cached per uid
 * for GROUP_MEMBERSHIP_TTL seconds, so a TCP request costs no NSS lookup in the common case.
 * Thread-safe. */
#ifndef AALAB_GROUP_MEMBERSHIP_H
#define AALAB_GROUP_MEMBERSHIP_H

#include <stdbool.h>
#include <sys/types.h>

#define GROUP_MEMBERSHIP_TTL 2.0

typedef struct group_membership group_membership;

/* NULL on out of memory. */
group_membership *group_membership_create(gid_t gid);
void group_membership_destroy(group_membership *gm);
/* uid 0 always; else the uid's primary or supplementary groups include gid. An unknown uid (the
 * account was deleted) is not a member. */
bool group_membership_check(group_membership *gm, long long uid);

#endif
