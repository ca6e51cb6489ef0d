/* Where the daemon listens, resolved the same way as aalabd does. */
#ifndef AALAB_SOCKET_PATH_H
#define AALAB_SOCKET_PATH_H

#include <stddef.h>

/* Order: explicit (--socket), $AALAB_SOCKET, $XDG_RUNTIME_DIR/aalab/aalabd.sock when that
 * socket exists (a per-user daemon), /tmp/aalab-UID/aalabd.sock when there is no
 * $XDG_RUNTIME_DIR and that socket exists in a directory we own (aalabd's own fallback), else
 * /run/aalab/aalabd.sock (the system daemon, which team members reach through the socket
 * group). Returns 0, or -1 if the path does not fit. */
int socket_path_resolve(const char *explicit_path, char *out, size_t cap);

/* The candidates socket_path_resolve considers, in its order, as "a, b, c" into out (for the
 * message when nothing answers): the explicit path or $AALAB_SOCKET alone when given. */
void socket_path_tried(const char *explicit_path, char *out, size_t cap);

#endif
