/* Command-line parsing for `aalab`: pure (no I/O, no globals), so tests can drive it. Global
 * options (--socket, --json, --timeout) may appear before or after the command. */
#ifndef AALAB_ARGS_H
#define AALAB_ARGS_H

#include <stdbool.h>
#include <stddef.h>

typedef enum cli_command {
    CMD_NONE,
    CMD_HELP,
    CMD_VERSION,
    CMD_EVAL,
    CMD_PRESETS,
    CMD_OPTIMIZE,
    CMD_SUBMIT,
    CMD_JOBS,
    CMD_JOB,
    CMD_CANCEL,
    CMD_RENDER,
    CMD_EXPORT,
    CMD_HEALTH,
    CMD_FILTERS,
    CMD_ACUITY,
    CMD_ENUMERATE,
    CMD_TOKEN,
    CMD_WAIT,
    CMD_CONVERT,
    CMD_PREDICT,
    CMD_ANALYZE
} cli_command;

typedef struct cli_args {
    cli_command command;
    /* global */
    const char *socket_path; /* NULL: default resolution */
    bool json;
    bool csv;         /* tables as RFC 4180 CSV (commands that print tables) */
    double timeout_s; /* per request, default 30 */
    /* positional: eval/convert NAME|FILE, submit FILE|-, job/wait/cancel/export ID,
     * help COMMAND */
    const char *target;
    /* token: the second positional of "token revoke ID" */
    const char *target2;
    const char *label; /* token --label */
    /* eval */
    const char *filter; /* NAME[:B=..,C=..] or a JSON object */
    const char *acuity; /* NAME, FILE.json or a JSON object */
    const char *angles; /* comma-separated degrees */
    bool detail;
    /* eval, a temporal pattern (docs/temporal.md): --temporal PRESET|FILE.json|JSON|GENERATOR,
     * --alpha A, --blend box|exponential|A (blend_text), --cut-frames K, --resolve FILTER,
     * --frame-pattern NAME|FILE */
    const char *temporal;
    double alpha;
    bool has_alpha;
    const char *blend_text; /* the --blend argument as given (eval's is a blend kind) */
    long cut_frames;        /* 0: not given */
    const char *resolve;
    const char *frame_pattern;
    /* optimize */
    const char *family;
    const char *pattern; /* optimize: FILE or preset NAME; render: NAME or FILE */
    const char *mode;
    const char *method;   /* optimize: the step rule, NULL = the daemon's choice */
    const char *executor; /* optimize: "local" or "slurm", NULL = the daemon's default */
    long seeds;
    double max_seconds;
    long long rng_seed;
    long max_iterations; /* per seed: with no --max-seconds, a clock-free, reproducible budget */
    bool has_seeds, has_max_seconds, has_rng_seed, has_max_iterations;
    bool wait;
    bool quiet;    /* optimize/submit -q: only the job id on stdout */
    double poll_s; /* --wait polling interval */
    /* jobs: filters sent as ?state=&kind=&limit= */
    const char *state;
    const char *kind;
    long limit;
    bool has_limit;
    /* job/wait --trace: the error-against-time points instead of the view */
    bool trace;
    /* job/wait --pattern: every sample of the best pattern, not only its summary */
    bool full_pattern;
    /* enumerate */
    double cost;
    bool has_cost;
    /* render */
    const char *scene;
    int width, height;
    const char *output; /* -o */
    const char *image;  /* pattern | reference | difference */
    /* predict: the scene's angle (degrees) */
    double angle;
    bool has_angle;
    /* predict --model: edge | reference-profile | exact; NULL: not sent (the daemon's edge) */
    const char *model;
    /* optimize --scene: the blend with E2 of the scene objective */
    double blend;
    bool has_blend;
    /* export, convert: json | utk | xyw | csv | bin | rps | points-json | vulkan | d3d12 | metal */
    const char *format;
    /* point-set pattern files (eval, optimize, render, convert): how to read them */
    const char *points_format; /* utk | xyw | csv | json | bin | rps; NULL: the extension's */
    const char *set;           /* --set N | all (analyze): one set of several; NULL: not given */
    int tile;                  /* --tile T, 0: not given */
    int kernel;                /* --kernel K, 0: not given */
    const char *weights;       /* file | filter | equal; NULL: not given */
    /* analyze: --metrics (comma-separated names), --radius, --pcf-bins */
    const char *metrics;
    long radius, pcf_bins; /* 0: not given (the daemon's default) */
} cli_args;

/* Returns 0, or -1 with a one-line reason in err (exit code 1 then). argv[0] is the program. */
int cli_parse(int argc, char *const *argv, cli_args *out, char *err, size_t errcap);

/* Name <-> id, for help and messages. */
const char *cli_command_name(cli_command c);
cli_command cli_command_from_name(const char *name);

/* Strict number parsing: whole string, in range. Return 0 or -1. */
int parse_long(const char *s, long min, long max, long *out);
int parse_double(const char *s, double min, double max, double *out);
/* Job ids are opaque to the client: 1..64 of [A-Za-z0-9_-] (so never a path). */
bool job_id_valid(const char *id);
/* "256x256" -> 256, 256 (1..16384 each). */
int parse_size(const char *s, int *w, int *h);

#endif
