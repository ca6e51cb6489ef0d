#define _POSIX_C_SOURCE 200809L
#include "socket_path.h"

#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#define SYSTEM_SOCKET "/run/aalab/aalabd.sock"

static int copy_path(const char *src, char *out, size_t cap)
{
    int n = snprintf(out, cap, "%s", src);
    return n < 0 || (size_t)n >= cap ? -1 : 0;
}

int socket_path_resolve(const char *explicit_path, char *out, size_t cap)
{
    if (explicit_path && *explicit_path)
        return copy_path(explicit_path, out, cap);
    const char *env = getenv("AALAB_SOCKET");
    if (env && *env)
        return copy_path(env, out, cap);
    const char *runtime = getenv("XDG_RUNTIME_DIR");
    if (runtime && *runtime) {
        int n = snprintf(out, cap, "%s/aalab/aalabd.sock", runtime);
        struct stat st;
        if (n > 0 && (size_t)n < cap && stat(out, &st) == 0 && S_ISSOCK(st.st_mode))
            return 0;
    }
    /* aalabd's last resort when it has neither root nor $XDG_RUNTIME_DIR; trusted only if the
     * directory is ours, so another user cannot plant a socket there. */
    if (!runtime || !*runtime) {
        char dir[64];
        struct stat st;
        snprintf(dir, sizeof dir, "/tmp/aalab-%u", (unsigned)geteuid());
        int n = snprintf(out, cap, "%s/aalabd.sock", dir);
        if (n > 0 && (size_t)n < cap && lstat(dir, &st) == 0 && S_ISDIR(st.st_mode) &&
            st.st_uid == geteuid() && stat(out, &st) == 0 && S_ISSOCK(st.st_mode))
            return 0;
    }
    return copy_path(SYSTEM_SOCKET, out, cap);
}

void socket_path_tried(const char *explicit_path, char *out, size_t cap)
{
    if (explicit_path && *explicit_path) {
        snprintf(out, cap, "%s (--socket)", explicit_path);
        return;
    }
    const char *env = getenv("AALAB_SOCKET");
    if (env && *env) {
        snprintf(out, cap, "%s ($AALAB_SOCKET)", env);
        return;
    }
    const char *runtime = getenv("XDG_RUNTIME_DIR");
    if (runtime && *runtime)
        snprintf(out, cap, "%s/aalab/aalabd.sock, %s", runtime, SYSTEM_SOCKET);
    else
        snprintf(out, cap, "/tmp/aalab-%u/aalabd.sock, %s", (unsigned)geteuid(), SYSTEM_SOCKET);
}
