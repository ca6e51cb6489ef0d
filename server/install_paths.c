#define _DEFAULT_SOURCE /* readlink */
#include "install_paths.h"

#include <string.h>
#include <unistd.h>

/* True if the running executable lies under the CMake build directory it was built in. */
static int running_from_build_tree(void)
{
    char exe[4096];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0)
        return 0;
    exe[n] = '\0';
    size_t len = strlen(AALAB_BUILD_DIR);
    return strncmp(exe, AALAB_BUILD_DIR, len) == 0 && exe[len] == '/';
}

const char *install_default_web_dir(void)
{
    return running_from_build_tree() ? AALAB_SOURCE_WEB_DIR : AALAB_INSTALLED_WEB_DIR;
}
