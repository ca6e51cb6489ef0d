#define _POSIX_C_SOURCE 200809L
#include "pattern_source.h"

#include "pointset.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* The daemon's default body limit: a point set beyond it could not be sent anyway. */
#define POINT_FILE_MAX_BYTES (8u << 20)

bool pattern_argument_is_file(const char *arg)
{
    size_t n = strlen(arg);
    struct stat st;
    return strchr(arg, '/') || (n > 5 && strcmp(arg + n - 5, ".json") == 0) || stat(arg, &st) == 0;
}

static bool ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n > m && strcmp(s + n - m, suffix) == 0;
}

const char *pattern_points_format(const char *arg, const cli_args *opts)
{
    if (opts && opts->points_format)
        return opts->points_format;
    if (ends_with(arg, ".dat"))
        return "utk";
    if (ends_with(arg, ".txt") || ends_with(arg, ".xyw"))
        return "xyw";
    if (ends_with(arg, ".csv"))
        return "csv";
    if (ends_with(arg, ".bin")) /* UTK's binary files */
        return "bin";
    if (ends_with(arg, ".rps")) /* PSA's raw float32 files */
        return "rps";
    return NULL;
}

static bool points_options_given(const cli_args *o)
{
    return o && (o->points_format || o->tile || o->kernel || o->weights || o->set);
}

/* The whole file, NUL-terminated; NULL with err. */
static char *read_file(const char *path, size_t *len, char *err, size_t errcap)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, errcap, "%s: %s", path, strerror(errno));
        return NULL;
    }
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        size_t got = fread(buf + n, 1, cap - n - 1, f);
        n += got;
        if (n < cap - 1)
            break;
        if (cap > POINT_FILE_MAX_BYTES) {
            snprintf(err, errcap, "%s: larger than %u bytes", path, POINT_FILE_MAX_BYTES);
            free(buf);
            fclose(f);
            return NULL;
        }
        char *more = realloc(buf, cap * 2);
        if (!more) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = more;
        cap *= 2;
    }
    bool bad = ferror(f);
    fclose(f);
    if (!buf || bad) {
        snprintf(err, errcap, "%s: %s", path, buf ? "read error" : "out of memory");
        free(buf);
        return NULL;
    }
    buf[n] = 0;
    *len = n;
    return buf;
}

/* {"points":{"format":F, "text"|"base64"|"data": ..., "set", "tile", "kernel", "weights"}} */
static json_t *points_pattern(const char *format, json_t *content, const cli_args *o)
{
    json_t *pts = json_pack("{s:s}", "format", format);
    if (!pts) {
        json_decref(content);
        return NULL;
    }
    bool binary = !strcmp(format, "bin") || !strcmp(format, "rps");
    json_object_set_new(pts,
                        !json_is_string(content) ? "data"
                        : binary                 ? "base64"
                                                 : "text",
                        content);
    if (o && o->set)
        json_object_set_new(pts, "set",
                            strcmp(o->set, "all") ? json_integer(strtol(o->set, NULL, 10))
                                                  : json_string("all"));
    if (o && o->tile)
        json_object_set_new(pts, "tile", json_integer(o->tile));
    if (o && o->kernel)
        json_object_set_new(pts, "kernel", json_integer(o->kernel));
    if (o && o->weights)
        json_object_set_new(pts, "weights", json_string(o->weights));
    return json_pack("{s:o}", "points", pts);
}

/* A point-set file's text as the points form. */
static int load_point_text(const char *arg, const char *format, const cli_args *o, json_t **pattern,
                           char *err, size_t errcap)
{
    size_t len;
    char *text = read_file(arg, &len, err, errcap);
    if (!text)
        return -1;
    json_t *s;
    if (!strcmp(format, "bin") || !strcmp(format, "rps")) { /* bytes: base64 on the wire */
        char *b64 = proto_base64_encode((const unsigned char *)text, len);
        s = b64 ? json_string(b64) : NULL;
        free(b64);
    } else {
        s = json_stringn(text, len);
    }
    free(text);
    if (!s) {
        snprintf(err, errcap, "%s: not UTF-8 text (or it holds a NUL byte)", arg);
        return -1;
    }
    *pattern = points_pattern(format, s, o);
    return *pattern ? 0 : -1;
}

/* A JSON document that is a point set rather than a pattern or a request. */
static bool is_point_set(const json_t *doc)
{
    return json_is_array(doc) ||
           (json_is_object(doc) && json_is_array(json_object_get(doc, "points")));
}

static int check_loaded(const char *arg, json_t **pattern, json_t **extras, char *err,
                        size_t errcap)
{
    char why[400];
    if (!pattern_check(*pattern, why, sizeof why))
        return 0;
    /* A point's line is in the message: "FILE: line 3: ..." reads like a compiler's; the
     * points form's options are the command's. */
    static const char *const fields[][2] = {{"field pattern.points.text: ", ""},
                                            {"field pattern.points.data", "point"},
                                            {"field pattern.points.weights: ", "--weights: "},
                                            {"field pattern.points.tile: ", "--tile: "},
                                            {"field pattern.points.kernel: ", "--kernel: "},
                                            {"field pattern.points.set: ", "--set: "}};
    const char *rest = why, *name = "";
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
        size_t n = strlen(fields[i][0]);
        if (!strncmp(why, fields[i][0], n)) {
            rest = why + n;
            name = fields[i][1];
            break;
        }
    }
    snprintf(err, errcap, "%s: %s%s", arg, name, rest);
    json_decref(*pattern);
    *pattern = NULL;
    if (extras) {
        json_decref(*extras);
        *extras = NULL;
    }
    return -1;
}

json_t *pattern_json_file(const char *path, char *err, size_t errcap)
{
    json_error_t jerr;
    json_t *doc = json_load_file(path, JSON_REJECT_DUPLICATES, &jerr);
    if (!doc && jerr.line > 0)
        snprintf(err, errcap, "%s:%d:%d: %s", path, jerr.line, jerr.column, jerr.text);
    else if (!doc)
        snprintf(err, errcap, "%s: %s", path, jerr.text);
    return doc;
}

int pattern_argument_load(const char *arg, const cli_args *opts, json_t **pattern, json_t **extras,
                          char *err, size_t errcap)
{
    *pattern = NULL;
    if (extras)
        *extras = NULL;
    bool is_file = pattern_argument_is_file(arg) || (opts && opts->points_format);
    if (!is_file && points_options_given(opts)) {
        snprintf(err, errcap,
                 "'%s': --points-format, --tile, --kernel and --weights apply to point-set "
                 "files",
                 arg);
        return -1;
    }
    if (strncmp(arg, "job:", 4) == 0) { /* the best pattern of a job, resolved by the daemon */
        if (!job_id_valid(arg + 4)) {
            snprintf(err, errcap, "'%s': job:ID wants a job ID", arg);
            return -1;
        }
        *pattern = json_pack("{s:s}", "job", arg + 4);
        return *pattern ? 0 : -1;
    }
    if (!is_file) {
        *pattern = json_pack("{s:s}", "preset", arg);
        return *pattern ? 0 : -1;
    }
    const char *format = pattern_points_format(arg, opts);
    if (format && strcmp(format, "json")) {
        if (load_point_text(arg, format, opts, pattern, err, errcap))
            return -1;
        return check_loaded(arg, pattern, extras, err, errcap);
    }
    json_t *doc = pattern_json_file(arg, err, errcap);
    if (!doc)
        return -1;
    if (is_point_set(doc) || format) {
        *pattern = points_pattern("json", doc, opts);
        if (!*pattern)
            return -1;
        return check_loaded(arg, pattern, extras, err, errcap);
    }
    if (points_options_given(opts)) {
        snprintf(err, errcap,
                 "%s: a pattern file; --tile, --kernel and --weights apply to point sets", arg);
        json_decref(doc);
        return -1;
    }
    if (!json_is_object(doc)) {
        snprintf(err, errcap, "%s: a pattern file holds a JSON object", arg);
        json_decref(doc);
        return -1;
    }
    json_t *inner = json_object_get(doc, "pattern");
    if (inner) { /* a saved request: {"pattern":P, "filter":..., ...} */
        if (!json_is_object(inner)) {
            snprintf(err, errcap, "%s: field pattern: expected an object", arg);
            json_decref(doc);
            return -1;
        }
        *pattern = json_incref(inner);
        json_object_del(doc, "pattern");
        /* `aalab export ID --format json` writes {"job":ID,"pattern":P}: the id is provenance,
         * not a request field. Anything else stays and the daemon judges it. */
        json_object_del(doc, "job");
        if (extras && json_object_size(doc) > 0)
            *extras = json_incref(doc);
        json_decref(doc);
    } else {
        *pattern = doc;
    }
    return check_loaded(arg, pattern, extras, err, errcap);
}
