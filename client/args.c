/* Table-driven option parsing: each option lists the commands it belongs to, so an option given
 * to the wrong command is a usage error rather than silently ignored. */
#include "args.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BIT(c) (1u << (c))
#define ALL_COMMANDS 0xffffffffu

typedef enum opt_id {
    OPT_SOCKET,
    OPT_JSON,
    OPT_TIMEOUT,
    OPT_HELP,
    OPT_VERSION,
    OPT_FILTER,
    OPT_ACUITY,
    OPT_ANGLES,
    OPT_DETAIL,
    OPT_FAMILY,
    OPT_PATTERN,
    OPT_SEEDS,
    OPT_MAX_SECONDS,
    OPT_RNG_SEED,
    OPT_MAX_ITERATIONS,
    OPT_EXECUTOR,
    OPT_MODE,
    OPT_METHOD,
    OPT_WAIT,
    OPT_POLL,
    OPT_SCENE,
    OPT_SIZE,
    OPT_OUTPUT,
    OPT_IMAGE,
    OPT_FORMAT,
    OPT_COST,
    OPT_LABEL,
    OPT_CSV,
    OPT_QUIET,
    OPT_STATE,
    OPT_KIND,
    OPT_LIMIT,
    OPT_TRACE,
    OPT_FULL_PATTERN,
    OPT_POINTS_FORMAT,
    OPT_TILE,
    OPT_KERNEL,
    OPT_WEIGHTS,
    OPT_ANGLE,
    OPT_BLEND,
    OPT_MODEL,
    OPT_METRICS,
    OPT_RADIUS,
    OPT_PCF_BINS,
    OPT_TEMPORAL,
    OPT_ALPHA,
    OPT_CUT_FRAMES,
    OPT_RESOLVE,
    OPT_FRAME_PATTERN,
    OPT_SET
} opt_id;

typedef struct opt_spec {
    const char *long_name;
    char short_name; /* 0: none */
    bool takes_value;
    unsigned commands; /* mask of BIT(cli_command) */
    opt_id id;
} opt_spec;

/* The commands that print tables, so --csv has a meaning there. */
#define TABLE_COMMANDS                                                                             \
    (BIT(CMD_EVAL) | BIT(CMD_PRESETS) | BIT(CMD_JOBS) | BIT(CMD_JOB) | BIT(CMD_WAIT) |             \
     BIT(CMD_HEALTH) | BIT(CMD_FILTERS) | BIT(CMD_ACUITY) | BIT(CMD_ENUMERATE) | BIT(CMD_TOKEN) |  \
     BIT(CMD_PREDICT) | BIT(CMD_ANALYZE))

/* The commands that take a pattern argument, which may be a point-set file. */
#define PATTERN_COMMANDS                                                                           \
    (BIT(CMD_EVAL) | BIT(CMD_OPTIMIZE) | BIT(CMD_RENDER) | BIT(CMD_CONVERT) | BIT(CMD_ANALYZE))

static const opt_spec OPTIONS[] = {
    {"socket", 's', true, ALL_COMMANDS, OPT_SOCKET},
    {"json", 0, false, ALL_COMMANDS, OPT_JSON},
    {"timeout", 0, true, ALL_COMMANDS, OPT_TIMEOUT},
    {"help", 'h', false, ALL_COMMANDS, OPT_HELP},
    {"version", 'V', false, ALL_COMMANDS, OPT_VERSION},
    {"filter", 0, true, BIT(CMD_EVAL), OPT_FILTER},
    {"acuity", 0, true, BIT(CMD_EVAL), OPT_ACUITY},
    {"angles", 0, true, BIT(CMD_EVAL), OPT_ANGLES},
    {"detail", 0, false, BIT(CMD_EVAL), OPT_DETAIL},
    {"family", 0, true, BIT(CMD_OPTIMIZE) | BIT(CMD_ENUMERATE), OPT_FAMILY},
    {"cost", 0, true, BIT(CMD_ENUMERATE), OPT_COST},
    {"pattern", 'p', true, BIT(CMD_OPTIMIZE) | BIT(CMD_RENDER) | BIT(CMD_PREDICT), OPT_PATTERN},
    {"seeds", 0, true, BIT(CMD_OPTIMIZE), OPT_SEEDS},
    {"max-seconds", 0, true, BIT(CMD_OPTIMIZE), OPT_MAX_SECONDS},
    {"rng-seed", 0, true, BIT(CMD_OPTIMIZE), OPT_RNG_SEED},
    {"max-iterations", 0, true, BIT(CMD_OPTIMIZE), OPT_MAX_ITERATIONS},
    {"executor", 0, true, BIT(CMD_OPTIMIZE), OPT_EXECUTOR},
    {"mode", 0, true, BIT(CMD_OPTIMIZE), OPT_MODE},
    {"method", 0, true, BIT(CMD_OPTIMIZE), OPT_METHOD},
    {"wait", 'w', false, BIT(CMD_OPTIMIZE) | BIT(CMD_SUBMIT), OPT_WAIT},
    {"poll", 0, true, BIT(CMD_OPTIMIZE) | BIT(CMD_SUBMIT) | BIT(CMD_WAIT), OPT_POLL},
    {"quiet", 'q', false, BIT(CMD_OPTIMIZE) | BIT(CMD_SUBMIT), OPT_QUIET},
    {"csv", 0, false, TABLE_COMMANDS, OPT_CSV},
    {"state", 0, true, BIT(CMD_JOBS), OPT_STATE},
    {"kind", 0, true, BIT(CMD_JOBS), OPT_KIND},
    {"limit", 0, true, BIT(CMD_JOBS), OPT_LIMIT},
    {"trace", 0, false, BIT(CMD_JOB) | BIT(CMD_WAIT), OPT_TRACE},
    {"pattern", 0, false, BIT(CMD_JOB) | BIT(CMD_WAIT), OPT_FULL_PATTERN},
    {"scene", 0, true, BIT(CMD_RENDER) | BIT(CMD_PREDICT) | BIT(CMD_OPTIMIZE), OPT_SCENE},
    {"size", 0, true, BIT(CMD_RENDER) | BIT(CMD_PREDICT) | BIT(CMD_OPTIMIZE), OPT_SIZE},
    {"angle", 0, true, BIT(CMD_PREDICT) | BIT(CMD_OPTIMIZE), OPT_ANGLE},
    /* optimize: a number (the scene blend); eval: the temporal blend (checked in check_command) */
    {"blend", 0, true, BIT(CMD_OPTIMIZE) | BIT(CMD_EVAL), OPT_BLEND},
    {"temporal", 0, true, BIT(CMD_EVAL), OPT_TEMPORAL},
    {"alpha", 0, true, BIT(CMD_EVAL), OPT_ALPHA},
    {"cut-frames", 0, true, BIT(CMD_EVAL), OPT_CUT_FRAMES},
    {"resolve", 0, true, BIT(CMD_EVAL), OPT_RESOLVE},
    {"frame-pattern", 0, true, BIT(CMD_EVAL), OPT_FRAME_PATTERN},
    {"model", 0, true, BIT(CMD_PREDICT), OPT_MODEL},
    {"output", 'o', true, BIT(CMD_RENDER) | BIT(CMD_EXPORT) | BIT(CMD_CONVERT), OPT_OUTPUT},
    {"image", 0, true, BIT(CMD_RENDER), OPT_IMAGE},
    {"format", 'f', true, BIT(CMD_EXPORT) | BIT(CMD_CONVERT), OPT_FORMAT},
    {"points-format", 0, true, PATTERN_COMMANDS, OPT_POINTS_FORMAT},
    {"tile", 0, true, PATTERN_COMMANDS, OPT_TILE},
    {"kernel", 0, true, PATTERN_COMMANDS, OPT_KERNEL},
    {"weights", 0, true, PATTERN_COMMANDS, OPT_WEIGHTS},
    {"label", 0, true, BIT(CMD_TOKEN), OPT_LABEL},
    {"metrics", 0, true, BIT(CMD_ANALYZE), OPT_METRICS},
    {"radius", 0, true, BIT(CMD_ANALYZE), OPT_RADIUS},
    {"pcf-bins", 0, true, BIT(CMD_ANALYZE), OPT_PCF_BINS},
    {"set", 0, true, PATTERN_COMMANDS, OPT_SET},
};

static const struct {
    const char *name;
    cli_command id;
} COMMANDS[] = {
    {"help", CMD_HELP},       {"version", CMD_VERSION},   {"eval", CMD_EVAL},
    {"presets", CMD_PRESETS}, {"optimize", CMD_OPTIMIZE}, {"submit", CMD_SUBMIT},
    {"jobs", CMD_JOBS},       {"job", CMD_JOB},           {"cancel", CMD_CANCEL},
    {"render", CMD_RENDER},   {"export", CMD_EXPORT},     {"health", CMD_HEALTH},
    {"filters", CMD_FILTERS}, {"acuity", CMD_ACUITY},     {"enumerate", CMD_ENUMERATE},
    {"token", CMD_TOKEN},     {"wait", CMD_WAIT},         {"convert", CMD_CONVERT},
    {"predict", CMD_PREDICT}, {"analyze", CMD_ANALYZE},
};

const char *cli_command_name(cli_command c)
{
    for (size_t i = 0; i < sizeof COMMANDS / sizeof COMMANDS[0]; i++)
        if (COMMANDS[i].id == c)
            return COMMANDS[i].name;
    return "";
}

cli_command cli_command_from_name(const char *name)
{
    for (size_t i = 0; i < sizeof COMMANDS / sizeof COMMANDS[0]; i++)
        if (strcmp(COMMANDS[i].name, name) == 0)
            return COMMANDS[i].id;
    return CMD_NONE;
}

static int fail(char *err, size_t cap, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

static int fail(char *err, size_t cap, const char *fmt, ...)
{
    if (err && cap) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, cap, fmt, ap);
        va_end(ap);
    }
    return -1;
}

int parse_long(const char *s, long min, long max, long *out)
{
    if (!s || !*s)
        return -1;
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || *end || v < min || v > max)
        return -1;
    *out = v;
    return 0;
}

int parse_double(const char *s, double min, double max, double *out)
{
    if (!s || !*s)
        return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || *end || !isfinite(v) || v < min || v > max)
        return -1;
    *out = v;
    return 0;
}

int parse_size(const char *s, int *w, int *h)
{
    const char *x = s ? strchr(s, 'x') : NULL;
    if (!x || x == s || strlen(x) > 16)
        return -1;
    char left[16];
    size_t n = (size_t)(x - s);
    if (n >= sizeof left)
        return -1;
    memcpy(left, s, n);
    left[n] = '\0';
    long lw, lh;
    if (parse_long(left, 1, 16384, &lw) || parse_long(x + 1, 1, 16384, &lh))
        return -1;
    *w = (int)lw;
    *h = (int)lh;
    return 0;
}

/* The option of that name; where two share a name (--pattern NAME for optimize, the flag
 * --pattern for job), the one of the command already named. */
static const opt_spec *find_long(const char *name, size_t len, cli_command cmd)
{
    const opt_spec *first = NULL;
    for (size_t i = 0; i < sizeof OPTIONS / sizeof OPTIONS[0]; i++)
        if (strlen(OPTIONS[i].long_name) == len && strncmp(OPTIONS[i].long_name, name, len) == 0) {
            if (cmd != CMD_NONE && (OPTIONS[i].commands & BIT(cmd)))
                return &OPTIONS[i];
            if (!first)
                first = &OPTIONS[i];
        }
    return first;
}

static const opt_spec *find_short(char c)
{
    for (size_t i = 0; i < sizeof OPTIONS / sizeof OPTIONS[0]; i++)
        if (OPTIONS[i].short_name == c)
            return &OPTIONS[i];
    return NULL;
}

static bool one_of(const char *v, const char *const *allowed)
{
    for (; *allowed; allowed++)
        if (strcmp(v, *allowed) == 0)
            return true;
    return false;
}

static int apply_option(cli_args *a, const opt_spec *o, const char *v, char *err, size_t cap)
{
    static const char *const MODES[] = {"weights", "positions", "both", NULL};
    static const char *const METHODS[] = {"auto", "laine-aila", "minimax", "smooth", NULL};
    static const char *const EXECUTORS[] = {"local", "slurm", NULL};
    static const char *const IMAGES[] = {"pattern", "reference", "difference", NULL};
    static const char *const MODELS[] = {"edge", "reference-profile", "exact", NULL};
    static const char *const FORMATS[] = {"json",        "utk",    "xyw",   "csv",   "bin", "rps",
                                          "points-json", "vulkan", "d3d12", "metal", NULL};
    static const char *const POINTS_FORMATS[] = {"utk", "xyw", "csv", "json", "bin", "rps", NULL};
    static const char *const WEIGHTS[] = {"file", "filter", "equal", NULL};
    static const char *const STATES[] = {"queued",    "running",     "done", "failed",
                                         "cancelled", "interrupted", NULL};
    long l;
    switch (o->id) {
    case OPT_SOCKET:
        a->socket_path = v;
        break;
    case OPT_JSON:
        a->json = true;
        break;
    case OPT_TIMEOUT:
        if (parse_double(v, 0.001, 86400, &a->timeout_s))
            return fail(err, cap, "--timeout wants seconds in (0, 86400], got '%s'", v);
        break;
    case OPT_HELP: /* handled by cli_parse */
    case OPT_VERSION:
        break;
    case OPT_FILTER:
        a->filter = v;
        break;
    case OPT_ACUITY:
        a->acuity = v;
        break;
    case OPT_ANGLES:
        a->angles = v;
        break;
    case OPT_DETAIL:
        a->detail = true;
        break;
    case OPT_FAMILY:
        a->family = v;
        break;
    case OPT_PATTERN:
        a->pattern = v;
        break;
    case OPT_SEEDS:
        if (parse_long(v, 1, 1000000, &a->seeds))
            return fail(err, cap, "--seeds wants an integer in 1..1000000, got '%s'", v);
        a->has_seeds = true;
        break;
    case OPT_MAX_SECONDS:
        if (parse_double(v, 0.001, 604800, &a->max_seconds))
            return fail(err, cap, "--max-seconds wants seconds in (0, 604800], got '%s'", v);
        a->has_max_seconds = true;
        break;
    case OPT_RNG_SEED:
        if (parse_long(v, 0, LONG_MAX, &l))
            return fail(err, cap, "--rng-seed wants a non-negative integer, got '%s'", v);
        a->rng_seed = l;
        a->has_rng_seed = true;
        break;
    case OPT_MAX_ITERATIONS:
        if (parse_long(v, 1, 10000000, &a->max_iterations))
            return fail(err, cap, "--max-iterations wants an integer in 1..10000000, got '%s'", v);
        a->has_max_iterations = true;
        break;
    case OPT_EXECUTOR:
        if (!one_of(v, EXECUTORS))
            return fail(err, cap, "--executor wants local or slurm, got '%s'", v);
        a->executor = v;
        break;
    case OPT_MODE:
        if (!one_of(v, MODES))
            return fail(err, cap, "--mode wants weights, positions or both, got '%s'", v);
        a->mode = v;
        break;
    case OPT_METHOD:
        if (!one_of(v, METHODS))
            return fail(err, cap, "--method wants auto, laine-aila, minimax or smooth, got '%s'",
                        v);
        a->method = v;
        break;
    case OPT_WAIT:
        a->wait = true;
        break;
    case OPT_POLL:
        if (parse_double(v, 0.01, 60, &a->poll_s))
            return fail(err, cap, "--poll wants seconds in [0.01, 60], got '%s'", v);
        break;
    case OPT_SCENE:
        a->scene = v;
        break;
    case OPT_SIZE:
        if (parse_size(v, &a->width, &a->height))
            return fail(err, cap, "--size wants WIDTHxHEIGHT (1..16384 each), got '%s'", v);
        break;
    case OPT_OUTPUT:
        a->output = v;
        break;
    case OPT_IMAGE:
        if (!one_of(v, IMAGES))
            return fail(err, cap, "--image wants pattern, reference or difference, got '%s'", v);
        a->image = v;
        break;
    case OPT_COST:
        if (parse_double(v, 0.001, 1e6, &a->cost))
            return fail(err, cap, "--cost wants samples per pixel (> 0), got '%s'", v);
        a->has_cost = true;
        break;
    case OPT_LABEL:
        a->label = v;
        break;
    case OPT_ANGLE:
        if (parse_double(v, -1e6, 1e6, &a->angle))
            return fail(err, cap, "--angle wants degrees, got '%s'", v);
        a->has_angle = true;
        break;
    case OPT_METRICS:
        a->metrics = v;
        break;
    case OPT_RADIUS:
        if (parse_long(v, 1, 128, &a->radius))
            return fail(err, cap, "--radius wants an integer from 1 to 128, got '%s'", v);
        break;
    case OPT_PCF_BINS:
        if (parse_long(v, 1, 1024, &a->pcf_bins))
            return fail(err, cap, "--pcf-bins wants an integer from 1 to 1024, got '%s'", v);
        break;
    case OPT_SET:
        if (strcmp(v, "all") && parse_long(v, 0, 0x7fffffff, &l))
            return fail(err, cap, "--set wants a set number from 0 (or all for analyze), got '%s'",
                        v);
        a->set = v;
        break;
    case OPT_MODEL:
        if (!one_of(v, MODELS))
            return fail(err, cap, "--model wants edge, reference-profile or exact, got '%s'", v);
        a->model = v;
        break;
    case OPT_BLEND: /* the command may come later: judged in check_command */
        a->blend_text = v;
        a->has_blend = parse_double(v, 0, 1, &a->blend) == 0;
        break;
    case OPT_TEMPORAL:
        a->temporal = v;
        break;
    case OPT_ALPHA:
        if (parse_double(v, 1e-6, 1, &a->alpha))
            return fail(err, cap, "--alpha wants a number in [1e-6, 1], got '%s'", v);
        a->has_alpha = true;
        break;
    case OPT_CUT_FRAMES:
        if (parse_long(v, 1, 4096, &a->cut_frames))
            return fail(err, cap, "--cut-frames wants an integer in 1..4096, got '%s'", v);
        break;
    case OPT_RESOLVE:
        a->resolve = v;
        break;
    case OPT_FRAME_PATTERN:
        a->frame_pattern = v;
        break;
    case OPT_CSV:
        a->csv = true;
        break;
    case OPT_QUIET:
        a->quiet = true;
        break;
    case OPT_TRACE:
        a->trace = true;
        break;
    case OPT_FULL_PATTERN:
        a->full_pattern = true;
        break;
    case OPT_STATE:
        if (!one_of(v, STATES))
            return fail(err, cap,
                        "--state wants queued, running, done, failed, cancelled or interrupted, "
                        "got '%s'",
                        v);
        a->state = v;
        break;
    case OPT_KIND:
        if (!*v)
            return fail(err, cap, "--kind wants a job kind, e.g. family-sweep");
        a->kind = v;
        break;
    case OPT_LIMIT:
        if (parse_long(v, 1, 1000000, &a->limit))
            return fail(err, cap, "--limit wants a positive integer, got '%s'", v);
        a->has_limit = true;
        break;
    case OPT_FORMAT:
        if (!one_of(v, FORMATS))
            return fail(err, cap,
                        "--format wants json, utk, xyw, csv, bin, rps, points-json, vulkan, d3d12 "
                        "or metal, got '%s'",
                        v);
        a->format = v;
        break;
    case OPT_POINTS_FORMAT:
        if (!one_of(v, POINTS_FORMATS))
            return fail(err, cap, "--points-format wants utk, xyw, csv, json, bin or rps, got '%s'",
                        v);
        a->points_format = v;
        break;
    case OPT_TILE:
        if (parse_long(v, 1, 16, &l))
            return fail(err, cap, "--tile wants the tile size in pixels, 1..16, got '%s'", v);
        a->tile = (int)l;
        break;
    case OPT_KERNEL:
        if (parse_long(v, 1, 8, &l))
            return fail(err, cap, "--kernel wants the kernel size in pixels, 1..8, got '%s'", v);
        a->kernel = (int)l;
        break;
    case OPT_WEIGHTS:
        if (!one_of(v, WEIGHTS))
            return fail(err, cap, "--weights wants file, filter or equal, got '%s'", v);
        a->weights = v;
        break;
    }
    return 0;
}

bool job_id_valid(const char *id)
{
    size_t n = strlen(id);
    if (n == 0 || n > 64)
        return false;
    for (size_t i = 0; i < n; i++) {
        char c = id[i];
        bool ok = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                  c == '-' || c == '_';
        if (!ok)
            return false;
    }
    return true;
}

/* Checks that need the whole command line: required positionals and option combinations. */
static int check_command(cli_args *a, char *err, size_t cap)
{
    const char *name = cli_command_name(a->command);
    if (a->set && !strcmp(a->set, "all") && a->command != CMD_ANALYZE)
        return fail(err, cap, "--set all is for 'aalab analyze' (every set, averaged)");
    switch (a->command) {
    case CMD_NONE:
        return fail(err, cap, "no command given (try 'aalab help')");
    case CMD_EVAL:
        if (a->blend_text && strcmp(a->blend_text, "box") && strcmp(a->blend_text, "exponential") &&
            !(a->has_blend && a->blend >= 1e-6))
            return fail(err, cap,
                        "--blend wants box, exponential or an alpha in [1e-6, 1], got '%s'",
                        a->blend_text);
        if (a->temporal && a->target)
            return fail(err, cap, "give a pattern or --temporal, not both");
        if (a->temporal)
            break;
        /* fall through */
    case CMD_ANALYZE:
    case CMD_CONVERT:
    case CMD_SUBMIT:
    case CMD_JOB:
    case CMD_WAIT:
    case CMD_CANCEL:
    case CMD_EXPORT:
        if (!a->target)
            return fail(err, cap, "'%s' needs %s", name,
                        a->command == CMD_EVAL || a->command == CMD_CONVERT ||
                                a->command == CMD_ANALYZE
                            ? "a preset NAME, a pattern FILE.json or a point-set file"
                        : a->command == CMD_SUBMIT ? "a job spec FILE.json (or - for stdin)"
                                                   : "a job ID");
        if (a->command != CMD_EVAL && a->command != CMD_CONVERT && a->command != CMD_SUBMIT &&
            a->command != CMD_ANALYZE && !job_id_valid(a->target))
            return fail(err, cap, "'%s' wants a job ID (letters, digits, '-', '_'), got '%s'", name,
                        a->target);
        break;
    case CMD_OPTIMIZE:
        if (a->blend_text && !a->has_blend)
            return fail(err, cap, "--blend wants a number in [0, 1], got '%s'", a->blend_text);
        if (!a->family == !a->pattern)
            return fail(err, cap, "'optimize' needs exactly one of --family or --pattern");
        if (a->family && (a->points_format || a->tile || a->kernel || a->weights))
            return fail(err, cap,
                        "--points-format, --tile, --kernel and --weights read a point-set "
                        "--pattern, not a --family");
        break;
    case CMD_ENUMERATE:
        if (!a->family)
            return fail(err, cap, "'enumerate' needs --family, e.g. 'P(4,1+,n)' --cost 1.25");
        break;
    case CMD_TOKEN:
        if (a->target && strcmp(a->target, "list") && strcmp(a->target, "revoke"))
            return fail(err, cap, "'token' takes list or revoke ID, got '%s'", a->target);
        if (a->target && !strcmp(a->target, "revoke") &&
            !job_id_valid(a->target2 ? a->target2 : ""))
            return fail(err, cap, "'token revoke' needs a token ID (see 'aalab token list')");
        if (a->target2 && strcmp(a->target, "revoke"))
            return fail(err, cap, "unexpected argument '%s'", a->target2);
        if (a->label && a->target)
            return fail(err, cap, "--label is for issuing a token ('aalab token --label TEXT')");
        break;
    case CMD_PREDICT:
        if (!a->pattern)
            return fail(err, cap, "'predict' needs --pattern NAME|FILE[,NAME|FILE...]");
        break;
    case CMD_RENDER:
        if (!a->pattern)
            return fail(err, cap, "'render' needs --pattern NAME|FILE");
        if (!a->output && !a->json)
            return fail(err, cap, "'render' needs -o FILE.png (or --json for the stats only)");
        break;
    default:
        break;
    }
    if (a->csv && a->json)
        return fail(err, cap, "give --csv or --json, not both");
    bool takes_argument = a->command == CMD_EVAL || a->command == CMD_CONVERT ||
                          a->command == CMD_SUBMIT || a->command == CMD_JOB ||
                          a->command == CMD_WAIT || a->command == CMD_CANCEL ||
                          a->command == CMD_EXPORT || a->command == CMD_PRESETS ||
                          a->command == CMD_TOKEN || a->command == CMD_ANALYZE;
    if (a->target && !takes_argument)
        return fail(err, cap, "'%s' takes no argument, got '%s'", name, a->target);
    return 0;
}

int cli_parse(int argc, char *const *argv, cli_args *out, char *err, size_t errcap)
{
    memset(out, 0, sizeof *out);
    out->timeout_s = 30;
    out->poll_s = 0.25;
    out->image = "pattern";
    out->format = "json";
    bool only_positionals = false;
    bool help = false, version = false;

    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const opt_spec *o = NULL;
        const char *value = NULL;
        if (!only_positionals && strcmp(arg, "--") == 0) {
            only_positionals = true;
            continue;
        }
        if (!only_positionals && arg[0] == '-' && arg[1] == '-') {
            const char *name = arg + 2;
            const char *eq = strchr(name, '=');
            size_t len = eq ? (size_t)(eq - name) : strlen(name);
            o = find_long(name, len, out->command);
            if (!o)
                return fail(err, errcap, "unknown option '--%.*s'", (int)len, name);
            if (eq) {
                if (!o->takes_value)
                    return fail(err, errcap, "option '--%s' takes no value", o->long_name);
                value = eq + 1;
            }
        } else if (!only_positionals && arg[0] == '-' && arg[1] != '\0') {
            o = find_short(arg[1]);
            if (!o)
                return fail(err, errcap, "unknown option '-%c'", arg[1]);
            if (arg[2] != '\0') {
                if (!o->takes_value)
                    return fail(err, errcap, "option '-%c' takes no value", arg[1]);
                value = arg + 2;
            }
        }
        if (!o) { /* positional: the command first, then its one argument */
            if (out->command == CMD_NONE) {
                out->command = cli_command_from_name(arg);
                if (out->command == CMD_NONE)
                    return fail(err, errcap, "unknown command '%s' (try 'aalab help')", arg);
            } else if (!out->target) {
                out->target = arg;
            } else if (out->command == CMD_TOKEN && !out->target2) {
                out->target2 = arg;
            } else {
                return fail(err, errcap, "unexpected argument '%s'", arg);
            }
            continue;
        }
        if (o->takes_value && !value) {
            if (i + 1 >= argc)
                return fail(err, errcap, "option '--%s' needs a value", o->long_name);
            value = argv[++i];
        }
        if (o->id == OPT_HELP) {
            help = true;
            continue;
        }
        if (o->id == OPT_VERSION) {
            version = true;
            continue;
        }
        /* Command-specific options are checked once the command is known (it may come later). */
        if (apply_option(out, o, value, err, errcap))
            return -1;
    }
    /* Second pass: every command-specific option must belong to the command. */
    for (int i = 1; i < argc && !help; i++) {
        const char *arg = argv[i];
        if (strcmp(arg, "--") == 0)
            break;
        const opt_spec *o = NULL;
        if (arg[0] == '-' && arg[1] == '-') {
            const char *eq = strchr(arg + 2, '=');
            o = find_long(arg + 2, eq ? (size_t)(eq - arg - 2) : strlen(arg + 2), out->command);
        } else if (arg[0] == '-' && arg[1] != '\0') {
            o = find_short(arg[1]);
        }
        if (!o)
            continue;
        if (o->takes_value && !strchr(arg, '=') && !(arg[1] != '-' && arg[2] != '\0'))
            i++; /* skip the value */
        if (out->command != CMD_NONE && !(o->commands & BIT(out->command)))
            return fail(err, errcap, "option '--%s' does not apply to '%s'", o->long_name,
                        cli_command_name(out->command));
    }
    if (version && !help) {
        out->command = CMD_VERSION;
        out->target = NULL;
        return 0;
    }
    if (help) {
        out->target = out->command == CMD_NONE || out->command == CMD_HELP
                          ? out->target
                          : cli_command_name(out->command);
        out->command = CMD_HELP;
        return 0;
    }
    if (out->command == CMD_HELP) {
        if (out->target && cli_command_from_name(out->target) == CMD_NONE)
            return fail(err, errcap, "no help for unknown command '%s'", out->target);
        return 0;
    }
    return check_command(out, err, errcap);
}
