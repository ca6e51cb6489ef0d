/* Trust checks for the daemon's own directories and private files: the state directory, the
 * socket's directory and the databases in them. Another user who can write one of these
 * directories can plant a symlink or a file of their choice (issue 35), so a directory is used
 * only when it and every directory above it is safe from other users, and a database is opened
 * only when it is a regular file of ours with one link. */
#ifndef AALAB_OWNED_PATH_H
#define AALAB_OWNED_PATH_H

#include <stddef.h>
#include <sys/types.h>

/* Creates path (mkdir -p; the last component with `mode`, the ones above 0755) if missing,
 * then checks it: a directory owned by the effective uid and not writable by group or others
 * (group-readable is fine: systemd's StateDirectoryMode=0750), below directories each owned by
 * root or the effective uid and not writable by group or others unless sticky (/tmp). `what`
 * names the role in the message ("state directory"). 0, or -1 with msg naming the path. */
int owned_dir_prepare(const char *path, mode_t mode, const char *what, char *msg, size_t cap);

/* Opens path read-write without following a symlink, creating it 0600 if missing. An existing
 * file must be a regular file owned by the effective uid with one link, else -1 (msg names the
 * path and the problem); a mode other than 0600 is set to 0600 through the descriptor and
 * *fixed_mode gets the old mode (else 0). Returns the descriptor (O_CLOEXEC). */
int owned_file_open(const char *path, mode_t *fixed_mode, char *msg, size_t cap);

/* SQLite's companions of path (-wal, -shm, -journal), if present, must be regular files owned by
 * the effective uid with one link: SQLite opens them itself and would follow a symlink. 0 or -1
 * with msg. */
int owned_db_companions_check(const char *path, char *msg, size_t cap);

#endif
