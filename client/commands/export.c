/* aalab export ID --format json|utk|xyw|csv|bin|rps|points-json|vulkan|d3d12|metal [-o FILE]:
 * the daemon's answer as it is (GET /v1/patterns/ID/export). */
#include "commands.h"

#include <errno.h>
#include <string.h>

#include "../exit_codes.h"

int write_output(FILE *out, FILE *err, const char *path, const char *data, size_t len)
{
    if (!path || strcmp(path, "-") == 0) {
        if (fwrite(data, 1, len, out) != len)
            return EXIT_USAGE;
        return EXIT_OK;
    }
    FILE *f = fopen(path, "wb");
    if (!f) {
        fprintf(err, "aalab: cannot write %s: %s\n", path, strerror(errno));
        return EXIT_USAGE;
    }
    size_t written = fwrite(data, 1, len, f);
    if (fclose(f) != 0 || written != len) {
        fprintf(err, "aalab: cannot write %s\n", path);
        return EXIT_USAGE;
    }
    return EXIT_OK;
}

int write_command_output(cli_session *s, const char *data, size_t len)
{
    const char *path = s->args->output;
    int code = write_output(s->out, s->err, path, data, len);
    if (code == EXIT_OK && path && !s->args->json && strcmp(path, "-") != 0)
        fprintf(s->err, "wrote %s (%zu bytes)\n", path, len);
    return code;
}

int cmd_export(cli_session *s)
{
    char path[160];
    snprintf(path, sizeof path, "/v1/patterns/%s/export?format=%s", s->args->target,
             s->args->format);
    http_response resp;
    int code = cli_call_raw(s, "GET", path, &resp);
    if (code != EXIT_OK)
        return code;
    code = write_command_output(s, resp.body, resp.len);
    http_response_free(&resp);
    return code;
}
