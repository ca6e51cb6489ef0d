/* Point-set text -> points (pointset.h): UTK, x y [w], CSV with a header, and the sets of a
 * '#'-separated file; JSON text goes to pointset_json.c, bytes (bin, rps) to
 * pointset_binary.c. */
#include "pointset.h"

#include <assert.h>
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "codec_internal.h"

bool proto_points_format_parse(const char *name, proto_points_format *out)
{
    static const char *const names[] = {"utk", "xyw", "csv", "json", "bin", "rps"};
    for (int i = 0; name && i < 6; i++) {
        if (!strcmp(name, names[i])) {
            *out = (proto_points_format)i;
            return true;
        }
    }
    return false;
}

const char *proto_points_format_name(proto_points_format f)
{
    switch (f) {
    case PROTO_POINTS_UTK:
        return "utk";
    case PROTO_POINTS_XYW:
        return "xyw";
    case PROTO_POINTS_CSV:
        return "csv";
    case PROTO_POINTS_BIN:
        return "bin";
    case PROTO_POINTS_RPS:
        return "rps";
    default:
        return "json";
    }
}

bool proto_points_format_is_binary(proto_points_format f)
{
    return f == PROTO_POINTS_BIN || f == PROTO_POINTS_RPS;
}

bool proto_points_format_has_sets(proto_points_format f)
{
    return f == PROTO_POINTS_UTK || f == PROTO_POINTS_XYW || f == PROTO_POINTS_BIN;
}

void proto_pointset_free(proto_pointset *ps)
{
    if (!ps)
        return;
    free(ps->points);
    free(ps->where);
    json_decref(ps->header);
    memset(ps, 0, sizeof *ps);
}

int proto_pointset_push(proto_pointset *ps, size_t *cap, proto_point p, size_t where)
{
    assert(ps->count <= *cap); /* *cap is the size of both points and where */
    if (ps->count == *cap) {
        size_t n = *cap ? *cap * 2 : 64;
        proto_point *pts = realloc(ps->points, n * sizeof *pts);
        if (!pts)
            return AA_ENOMEM;
        ps->points = pts;
        size_t *w = realloc(ps->where, n * sizeof *w);
        if (!w)
            return AA_ENOMEM;
        ps->where = w;
        *cap = n;
    }
    ps->points[ps->count] = p;
    ps->where[ps->count++] = where;
    return AA_OK;
}

/* A token for an error message: at most 24 bytes, anything but printable ASCII as '?' (the
 * message goes into JSON, which must be UTF-8). */
static void quote_token(char *out, size_t cap, const char *s, size_t n)
{
    size_t m = n < 24 ? n : 24, o = 0;
    for (size_t i = 0; i < m && o + 1 < cap; i++)
        out[o++] = (s[i] >= 0x20 && s[i] < 0x7f) ? s[i] : '?';
    if (n > m && o + 4 < cap) {
        memcpy(out + o, "...", 3);
        o += 3;
    }
    out[o < cap ? o : cap - 1] = 0;
}

/* A finite decimal number spanning exactly s[0..n). */
static bool parse_number(const char *s, size_t n, double *out)
{
    char buf[64];
    if (n == 0 || n >= sizeof buf)
        return false;
    memcpy(buf, s, n);
    buf[n] = 0;
    /* strtod also reads "nan", "inf" and hex floats; a point file holds decimal numbers only. */
    for (size_t i = 0; i < n; i++)
        if (!strchr("0123456789+-.eE", buf[i]))
            return false;
    char *end;
    double v = strtod(buf, &end);
    if (end != buf + n || !isfinite(v))
        return false;
    *out = v;
    return true;
}

static bool is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

/* Lines of a text without their end ('\n', '\r\n'); *line is 1-based. */
typedef struct line_reader {
    const char *p, *end;
    size_t line;
} line_reader;

static bool next_line(line_reader *r, const char **s, size_t *n)
{
    if (r->p >= r->end)
        return false;
    const char *nl = memchr(r->p, '\n', (size_t)(r->end - r->p));
    const char *e = nl ? nl : r->end;
    *s = r->p;
    *n = (size_t)(e - r->p);
    while (*n && is_blank((*s)[*n - 1]))
        (*n)--;
    while (*n && is_blank(**s)) {
        (*s)++;
        (*n)--;
    }
    r->p = nl ? nl + 1 : r->end;
    r->line++;
    return true;
}

/* A comment line: the aalab header (once, before the first point) or anything else ignored. */
static int comment_line(proto_pointset *ps, const char *s, size_t n, size_t line, const char *field,
                        aa_error *err)
{
    size_t hn = strlen(PROTO_POINTS_HEADER);
    if (n < hn || memcmp(s, PROTO_POINTS_HEADER, hn))
        return AA_OK;
    if (ps->header)
        return aa_error_set(err, AA_EINVAL, field,
                            "line %zu: a second aalab-pattern header (the first is on line %zu; "
                            "several sets in one file? choose one with set)",
                            line, ps->header_line);
    if (ps->count)
        return aa_error_set(err, AA_EINVAL, field,
                            "line %zu: the aalab-pattern header must come before the points", line);
    json_error_t je;
    json_t *h = json_loadb(s + hn, n - hn, JSON_REJECT_DUPLICATES, &je);
    char cut[96];
    if (!h || !json_is_object(h)) {
        bool parsed = h != NULL;
        json_decref(h);
        return aa_error_set(err, AA_EINVAL, field,
                            "line %zu: the aalab-pattern header is not a JSON object%s%s", line,
                            parsed ? "" : ": ",
                            parsed ? "" : proto_utf8_prefix(cut, sizeof cut, je.text, 80));
    }
    ps->header = h;
    ps->header_line = line;
    return AA_OK;
}

/* The next line that is neither blank nor a comment (comments go through comment_line): 1 with
 * the line in *s, *n; 0 at the end of the text; or comment_line's error. */
static int next_point_line(line_reader *r, proto_pointset *ps, const char **s, size_t *n,
                           const char *field, aa_error *err)
{
    while (next_line(r, s, n)) {
        if (*n == 0)
            continue;
        if ((*s)[0] != '#')
            return 1;
        int rc = comment_line(ps, *s, *n, r->line, field, err);
        if (rc)
            return rc;
    }
    return 0;
}

/* UTK ("x y") and xyw ("x y" or "x y w", the same on every line). */
static int parse_columns(const char *text, size_t len, size_t line0, bool utk, proto_pointset *ps,
                         const char *field, aa_error *err)
{
    line_reader r = {text, text + len, line0};
    const char *s;
    size_t n, cap = 0, arity_line = 0;
    int arity = 0;
    int rc;
    while ((rc = next_point_line(&r, ps, &s, &n, field, err)) == 1) {
        double v[4];
        int got = 0;
        size_t i = 0;
        while (i < n) {
            while (i < n && is_blank(s[i]))
                i++;
            if (i == n)
                break;
            size_t t = i;
            while (i < n && !is_blank(s[i]))
                i++;
            if (got == 3)
                return aa_error_set(err, AA_EINVAL, field, "line %zu: expected %s", r.line,
                                    utk ? "2 numbers (x y)" : "2 or 3 numbers (x y [w])");
            if (!parse_number(s + t, i - t, &v[got])) {
                char tok[32];
                quote_token(tok, sizeof tok, s + t, i - t);
                return aa_error_set(err, AA_EINVAL, field, "line %zu: '%s' is not a number", r.line,
                                    tok);
            }
            got++;
        }
        if (got < 2 || (utk && got != 2))
            return aa_error_set(err, AA_EINVAL, field, "line %zu: expected %s", r.line,
                                utk ? "2 numbers (x y)" : "2 or 3 numbers (x y [w])");
        if (arity && got != arity)
            return aa_error_set(err, AA_EINVAL, field,
                                "line %zu: %d numbers, but line %zu has %d (every line gives "
                                "x y, or every line x y w)",
                                r.line, got, arity_line, arity);
        if (!arity) {
            arity = got;
            arity_line = r.line;
        }
        if (ps->count == PROTO_POINTS_MAX)
            return aa_error_set(err, AA_ERANGE, field, "line %zu: more than %d points", r.line,
                                PROTO_POINTS_MAX);
        proto_point p = {v[0], v[1], got == 3 ? v[2] : 0};
        if (proto_pointset_push(ps, &cap, p, r.line))
            return aa_error_set(err, AA_ENOMEM, field, "out of memory");
    }
    if (rc)
        return rc;
    ps->has_weights = arity == 3;
    return AA_OK;
}

/* One CSV field, trimmed, without surrounding double quotes. */
static void csv_field(const char **s, size_t *n)
{
    while (*n && is_blank(**s)) {
        (*s)++;
        (*n)--;
    }
    while (*n && is_blank((*s)[*n - 1]))
        (*n)--;
    if (*n >= 2 && (*s)[0] == '"' && (*s)[*n - 1] == '"') {
        (*s)++;
        *n -= 2;
    }
}

/* Fields split per line: enough to name the first column that is not x, y or w. */
#define CSV_MAX_COLUMNS 8

/* Splits a line at commas into at most max fields; returns the count, or max + 1 if more. */
static int csv_split(const char *s, size_t n, const char **f, size_t *fn, int max)
{
    int c = 0;
    size_t start = 0;
    for (size_t i = 0; i <= n; i++) {
        if (i < n && s[i] != ',')
            continue;
        if (c == max)
            return max + 1;
        f[c] = s + start;
        fn[c] = i - start;
        csv_field(&f[c], &fn[c]);
        c++;
        start = i + 1;
    }
    return c;
}

static int parse_csv(const char *text, size_t len, proto_pointset *ps, const char *field,
                     aa_error *err)
{
    line_reader r = {text, text + len, 0};
    const char *s;
    size_t n, cap = 0;
    int col[CSV_MAX_COLUMNS]; /* which of x, y, w each column is */
    int columns = 0;
    size_t header_line = 0;
    int rc;
    while ((rc = next_point_line(&r, ps, &s, &n, field, err)) == 1) {
        const char *f[CSV_MAX_COLUMNS];
        size_t fn[CSV_MAX_COLUMNS];
        int c = csv_split(s, n, f, fn, CSV_MAX_COLUMNS);
        if (!columns) {
            static const char *const names[] = {"x", "y", "w"};
            bool seen[3] = {false, false, false};
            if (c > CSV_MAX_COLUMNS)
                return aa_error_set(err, AA_EINVAL, field,
                                    "line %zu: more than %d columns (the columns are x, y and "
                                    "optionally w)",
                                    r.line, CSV_MAX_COLUMNS);
            for (int i = 0; i < c; i++) {
                int which = -1;
                for (int k = 0; k < 3; k++)
                    if (fn[i] == 1 && tolower((unsigned char)f[i][0]) == names[k][0])
                        which = k;
                char tok[32];
                quote_token(tok, sizeof tok, f[i], fn[i]);
                if (which < 0)
                    return aa_error_set(err, AA_EINVAL, field,
                                        "line %zu: unknown column '%s' (the columns are x, y "
                                        "and optionally w, named in a header line)",
                                        r.line, tok);
                if (seen[which])
                    return aa_error_set(err, AA_EINVAL, field, "line %zu: column %s twice", r.line,
                                        names[which]);
                seen[which] = true;
                col[i] = which;
            }
            if (!seen[0] || !seen[1])
                return aa_error_set(err, AA_EINVAL, field,
                                    "line %zu: the header line must name columns x and y", r.line);
            columns = c;
            header_line = r.line;
            ps->has_weights = seen[2];
            continue;
        }
        if (c != columns)
            return aa_error_set(
                err, AA_EINVAL, field, "line %zu: %s%d field%s, but the header (line %zu) names %d",
                r.line, c > CSV_MAX_COLUMNS ? "more than " : "",
                c > CSV_MAX_COLUMNS ? CSV_MAX_COLUMNS : c, c == 1 ? "" : "s", header_line, columns);
        double v[3] = {0, 0, 0};
        for (int i = 0; i < c && i < columns; i++) {
            if (!parse_number(f[i], fn[i], &v[col[i]])) {
                char tok[32];
                quote_token(tok, sizeof tok, f[i], fn[i]);
                return aa_error_set(err, AA_EINVAL, field, "line %zu: %s: '%s' is not a number",
                                    r.line,
                                    col[i] == 0   ? "x"
                                    : col[i] == 1 ? "y"
                                                  : "w",
                                    tok);
            }
        }
        if (ps->count == PROTO_POINTS_MAX)
            return aa_error_set(err, AA_ERANGE, field, "line %zu: more than %d points", r.line,
                                PROTO_POINTS_MAX);
        if (proto_pointset_push(ps, &cap, (proto_point){v[0], v[1], v[2]}, r.line))
            return aa_error_set(err, AA_ENOMEM, field, "out of memory");
    }
    if (rc)
        return rc;
    if (!columns)
        return aa_error_set(err, AA_EINVAL, field,
                            "no header line: a CSV point set starts with x,y or x,y,w");
    return AA_OK;
}

/* The text formats from line line0 + 1 on. */
static int parse_text(const char *text, size_t len, size_t line0, proto_points_format fmt,
                      proto_pointset *out, const char *field, aa_error *err)
{
    memset(out, 0, sizeof *out);
    int rc;
    if (fmt == PROTO_POINTS_JSON) {
        json_error_t je;
        json_t *j = json_loadb(text, len, JSON_REJECT_DUPLICATES, &je);
        char cut[96];
        if (!j)
            return aa_error_set(err, AA_EINVAL, field, "line %d: not valid JSON: %s", je.line,
                                proto_utf8_prefix(cut, sizeof cut, je.text, 80));
        rc = proto_pointset_from_json(j, false, out, field, err);
        json_decref(j);
        return rc;
    }
    out->by_line = true;
    if (fmt == PROTO_POINTS_CSV)
        rc = parse_csv(text, len, out, field, err);
    else
        rc = parse_columns(text, len, line0, fmt == PROTO_POINTS_UTK, out, field, err);
    if (!rc && out->count == 0)
        rc = aa_error_set(err, AA_EINVAL, field, "no points (one point per line: %s)",
                          fmt == PROTO_POINTS_CSV ? "x,y after a header line" : "x y");
    if (rc)
        proto_pointset_free(out);
    return rc;
}

int proto_pointset_parse(const char *text, size_t len, proto_points_format fmt, proto_pointset *out,
                         const char *field, aa_error *err)
{
    return proto_pointset_parse_set(text, len, fmt, PROTO_POINTS_WHOLE, out, NULL, field, "set",
                                    err);
}

/* UTK's sets of a '#'-separated text: a '#' line after a point line starts the next set. Finds
 * set `want` (its bytes and the line before its first) and counts the sets. */
typedef struct text_set {
    const char *start, *end;
    size_t line0;
} text_set;

static size_t split_sets(const char *text, size_t len, size_t want, text_set *found)
{
    line_reader r = {text, text + len, 0};
    const char *s, *set_start = text, *line_start = text;
    size_t n, count = 0, set_line0 = 0;
    bool has_points = false;
    while (line_start = r.p, next_line(&r, &s, &n)) {
        if (n == 0)
            continue;
        if (s[0] == '#') {
            if (!has_points)
                continue;
            /* The set before this line is complete. */
            if (count == want)
                *found = (text_set){set_start, line_start, set_line0};
            count++;
            set_start = line_start;
            set_line0 = r.line - 1;
            has_points = false;
            continue;
        }
        has_points = true;
    }
    if (has_points) {
        if (count == want)
            *found = (text_set){set_start, text + len, set_line0};
        count++;
    }
    return count;
}

int proto_pointset_count_sets(const char *text, size_t len, proto_points_format fmt, size_t *count,
                              const char *field, aa_error *err)
{
    if (proto_points_format_is_binary(fmt))
        return proto_pointset_binary_set_count((const unsigned char *)text, len, fmt, count, field,
                                               err);
    text_set unused;
    *count = proto_points_format_has_sets(fmt) ? split_sets(text, len, 0, &unused) : 1;
    return AA_OK;
}

int proto_pointset_parse_set(const char *text, size_t len, proto_points_format fmt, size_t set,
                             proto_pointset *out, size_t *set_count, const char *field,
                             const char *set_field, aa_error *err)
{
    if (proto_points_format_is_binary(fmt))
        return proto_pointset_parse_binary((const unsigned char *)text, len, fmt, set, out,
                                           set_count, field, set_field, err);
    memset(out, 0, sizeof *out);
    if (set == PROTO_POINTS_WHOLE)
        return parse_text(text, len, 0, fmt, out, field, err);
    if (!proto_points_format_has_sets(fmt))
        return aa_error_set(err, AA_EINVAL, set_field,
                            "a %s file holds one set; set is for utk, xyw and bin files",
                            proto_points_format_name(fmt));
    text_set t = {NULL, NULL, 0};
    size_t count = split_sets(text, len, set, &t);
    if (set_count)
        *set_count = count;
    if (!t.start)
        return aa_error_set(err, AA_ERANGE, set_field,
                            "is %zu but the file holds %zu set%s ('#' lines separate them; sets "
                            "count from 0)",
                            set, count, count == 1 ? "" : "s");
    return parse_text(t.start, (size_t)(t.end - t.start), t.line0, fmt, out, field, err);
}
