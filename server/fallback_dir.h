/* The per-user fallback directory /tmp/aalab-UID (socket and state when neither root nor
 * $XDG_RUNTIME_DIR nor $HOME give a place). /tmp is world-writable: another user may have
 * created that directory first and would then own our socket (and receive our requests).
 * The daemon applies the client's rule (client/socket_path.c): it must be ours and 0700. */
#ifndef AALAB_FALLBACK_DIR_H
#define AALAB_FALLBACK_DIR_H

#include <stddef.h>

/* If path lies in /tmp/aalab-<euid>/, creates that directory 0700 when missing and checks it is
 * a real directory (not a symlink) owned by the effective uid with mode 0700. Returns 0 if path
 * is elsewhere or the directory is safe, else -1 with why in msg. */
int fallback_dir_check(const char *path, char *msg, size_t cap);

#endif
