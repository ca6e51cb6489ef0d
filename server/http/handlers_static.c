/* Static dashboard files from --web-dir, on the TCP listener only. The path must be clean
 * (no "..", no backslash, no control bytes) and its realpath must stay inside the web dir,
 * which also stops symlinks that point outside. */
#define _GNU_SOURCE
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "handlers.h"

#define STATIC_MAX_FILE (16u << 20)

static const struct {
    const char *ext, *type;
} mime_types[] = {
    {".html", "text/html; charset=utf-8"},
    {".js", "text/javascript; charset=utf-8"},
    {".mjs", "text/javascript; charset=utf-8"},
    {".css", "text/css; charset=utf-8"},
    {".json", "application/json"},
    {".svg", "image/svg+xml"},
    {".png", "image/png"},
    {".ico", "image/x-icon"},
    {".txt", "text/plain; charset=utf-8"},
    {".map", "application/json"},
    {".woff2", "font/woff2"},
    {".webmanifest", "application/manifest+json"},
};

static const char *mime_for(const char *path)
{
    const char *dot = strrchr(path, '.');
    if (dot && !strchr(dot, '/'))
        for (size_t i = 0; i < sizeof mime_types / sizeof mime_types[0]; i++)
            if (!strcmp(dot, mime_types[i].ext))
                return mime_types[i].type;
    return "application/octet-stream";
}

static bool path_clean(const char *p)
{
    if (p[0] != '/' || strstr(p, "//"))
        return false;
    for (const char *c = p; *c; c++)
        if ((unsigned char)*c < 0x20 || *c == '\\' || *c == '%' || *c == 0x7f)
            return false;
    for (const char *seg = p; seg; seg = strchr(seg + 1, '/')) {
        const char *s = seg + 1;
        size_t len = strcspn(s, "/");
        if ((len == 1 && s[0] == '.') || (len == 2 && s[0] == '.' && s[1] == '.'))
            return false;
        if (len > 0 && s[0] == '.') /* hidden files */
            return false;
    }
    return true;
}

void handle_static(api_context *ctx, const api_request *req, api_response *resp)
{
    const aalab_config *cfg = api_context_config(ctx);
    const char *path = req->path;
    if (!path_clean(path)) {
        api_reply_wire(resp, WIRE_NOT_FOUND, "", "no such file");
        return;
    }
    char root[PATH_MAX], want[PATH_MAX * 2], real[PATH_MAX];
    if (!realpath(cfg->web_dir, root)) {
        api_reply_wire(resp, WIRE_NOT_FOUND, "", "no dashboard directory configured");
        return;
    }
    bool dir_index = path[strlen(path) - 1] == '/';
    snprintf(want, sizeof want, "%s%s%s", root, path, dir_index ? "index.html" : "");
    if (!realpath(want, real) || strncmp(real, root, strlen(root)) ||
        (real[strlen(root)] != '/' && real[strlen(root)] != 0)) {
        api_reply_wire(resp, WIRE_NOT_FOUND, "", "no such file");
        return;
    }
    int fd = open(real, O_RDONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) || !S_ISREG(st.st_mode) || st.st_size > STATIC_MAX_FILE) {
        if (fd >= 0)
            close(fd);
        api_reply_wire(resp, WIRE_NOT_FOUND, "", "no such file");
        return;
    }
    char *buf = malloc((size_t)st.st_size + 1);
    size_t got = 0;
    while (buf && got < (size_t)st.st_size) {
        ssize_t n = read(fd, buf + got, (size_t)st.st_size - got);
        if (n <= 0)
            break;
        got += (size_t)n;
    }
    close(fd);
    if (!buf || got != (size_t)st.st_size) {
        free(buf);
        api_reply_wire(resp, WIRE_INTERNAL, "", "cannot read the file");
        return;
    }
    resp->status = 200;
    resp->content_type = mime_for(real);
    resp->body = buf;
    resp->body_len = got;
    resp->cache_control = "no-cache";
}
