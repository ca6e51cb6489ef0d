/* aalab: the command-line client of aalabd. Parses, connects, dispatches to one command. */
#include <stdio.h>
#include <string.h>

#include "aalab_version.h"
#include "args.h"
#include "cli.h"
#include "commands/commands.h"
#include "exit_codes.h"
#include "socket_path.h"

typedef int (*command_fn)(cli_session *);

static command_fn command_for(cli_command c)
{
    switch (c) {
    case CMD_EVAL:
        return cmd_eval;
    case CMD_PRESETS:
        return cmd_presets;
    case CMD_OPTIMIZE:
        return cmd_optimize;
    case CMD_SUBMIT:
        return cmd_submit;
    case CMD_JOBS:
        return cmd_jobs;
    case CMD_JOB:
        return cmd_job;
    case CMD_CANCEL:
        return cmd_cancel;
    case CMD_RENDER:
        return cmd_render;
    case CMD_PREDICT:
        return cmd_predict;
    case CMD_ANALYZE:
        return cmd_analyze;
    case CMD_EXPORT:
        return cmd_export;
    case CMD_HEALTH:
        return cmd_health;
    case CMD_FILTERS:
        return cmd_filters;
    case CMD_ACUITY:
        return cmd_acuity;
    case CMD_ENUMERATE:
        return cmd_enumerate;
    case CMD_TOKEN:
        return cmd_token;
    case CMD_WAIT:
        return cmd_wait;
    case CMD_CONVERT:
        return cmd_convert;
    default:
        return NULL;
    }
}

int main(int argc, char **argv)
{
    cli_args args;
    char err[512];
    if (cli_parse(argc, argv, &args, err, sizeof err)) {
        fprintf(stderr, "aalab: %s\n", err);
        return EXIT_USAGE;
    }
    if (args.command == CMD_HELP) {
        cmd_help(stdout, args.target);
        return EXIT_OK;
    }
    if (args.command == CMD_VERSION) {
        printf("aalab %s\n", aalab_version_full);
        return EXIT_OK;
    }
    char socket_path[4096];
    if (socket_path_resolve(args.socket_path, socket_path, sizeof socket_path)) {
        fprintf(stderr, "aalab: socket path too long\n");
        return EXIT_USAGE;
    }
    http_client *http = http_client_new(socket_path, (long)(args.timeout_s * 1000));
    if (!http) {
        fprintf(stderr, "aalab: cannot initialise libcurl\n");
        return EXIT_NO_CONNECT;
    }
    cli_session s = {.args = &args, .http = http, .out = stdout, .err = stderr};
    int code = command_for(args.command)(&s);
    if (fflush(stdout) != 0 && code == EXIT_OK)
        code = EXIT_USAGE; /* e.g. stdout is a full disk or a closed pipe */
    http_client_free(http);
    return code;
}
