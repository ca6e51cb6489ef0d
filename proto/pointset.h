/* Point sets in and out: UTK text, plain "x y [w]" text, CSV and JSON arrays of points, shared
 * by the daemon (the "points" pattern form, exports) and the client (import, export, convert).
 *
 * One coordinate convention for every file format: points in the unit square [0, 1)^2 of the
 * WHOLE TILE (UTK's convention; x right, y down along the tile's y axis), one point per tile
 * sample. A tile of T x T pixels maps point (u, v) to tile coordinates (T u, T v).
 *
 * aalab's own exports put what an exact round trip needs in one leading comment line that other
 * tools ignore, "# aalab-pattern {JSON}" (utk, xyw, csv), or the object form
 * {"aalab": {JSON}, "points": [...]} (json). The JSON object holds "tile", "kernel", "border" and
 * the per-kernel "weights" of a tile pattern, or "pattern", the wire form itself, for patterns
 * whose form is not the tile form (explicit kernels, mirrored, presets). */
#ifndef AALAB_PROTO_POINTSET_H
#define AALAB_PROTO_POINTSET_H

#include <stdbool.h>
#include <stddef.h>

#include <jansson.h>

#include "aa_core.h"
#include "aa_pattern.h"

#define PROTO_POINTS_MAX AA_MAX_KERNEL_SAMPLES /* points of one file (one tile) */
#define PROTO_POINTS_HEADER "# aalab-pattern "

typedef enum proto_points_format {
    PROTO_POINTS_UTK,
    PROTO_POINTS_XYW,
    PROTO_POINTS_CSV,
    PROTO_POINTS_JSON,
    PROTO_POINTS_BIN, /* UTK's binary .bin: float32 or float64, 2-D (pointset_binary.c) */
    PROTO_POINTS_RPS  /* PSA's raw little-endian float32 pairs, no header */
} proto_points_format;
#define PROTO_POINTS_FORMATS "utk, xyw, csv, json, bin or rps"

/* Several sets in one file: UTK and pbrt's pspec separate them by '#' lines (utk, xyw) and UTK's
 * .bin holds m sets of N points. PROTO_POINTS_WHOLE reads the file as one set (text: '#' lines
 * are comments, as before; bin: m must be 1). */
#define PROTO_POINTS_WHOLE ((size_t)-1)

typedef struct proto_point {
    double x, y, w; /* w is 0 when the set has no weights */
} proto_point;

typedef struct proto_pointset {
    size_t count;
    proto_point *points;
    size_t *where;      /* per point: its 1-based line (text) or its array index (JSON data) */
    bool by_index;      /* where[] holds array indices: errors name "field[i]" */
    bool by_line;       /* where[] holds lines: errors say "line N: " (else "point N: ") */
    bool has_weights;   /* every point has a w */
    json_t *header;     /* the aalab-pattern object (owned), or NULL */
    size_t header_line; /* its line (text formats), 0 for JSON */
} proto_pointset;

/* "utk" | "xyw" | "csv" | "json" | "bin" | "rps" -> format; false for anything else. */
bool proto_points_format_parse(const char *name, proto_points_format *out);
const char *proto_points_format_name(proto_points_format f);
/* bin and rps: bytes, not text (base64 on the wire). */
bool proto_points_format_is_binary(proto_points_format f);
/* utk, xyw and bin can hold several sets. */
bool proto_points_format_has_sets(proto_points_format f);

/* Parses text (len bytes, need not be NUL-terminated) in the given format. Errors name field
 * (e.g. "pattern.points.text") with "line N: ..." in the message. On error *out holds nothing
 * to free. */
int proto_pointset_parse(const char *text, size_t len, proto_points_format fmt, proto_pointset *out,
                         const char *field, aa_error *err);
/* Set number `set` (0-based; PROTO_POINTS_WHOLE: as proto_pointset_parse) of a file. Text sets
 * (utk, xyw) are UTK's: a '#' line after a point starts the next set, so the comment lines
 * before a set's first point (its aalab-pattern header) belong to it; sets without points do
 * not count. *set_count (may be NULL) gets the number of sets when the file splits. Errors name
 * field; a set past the last names set_field. */
int proto_pointset_parse_set(const char *text, size_t len, proto_points_format fmt, size_t set,
                             proto_pointset *out, size_t *set_count, const char *field,
                             const char *set_field, aa_error *err);
/* The number of sets of a file (utk, xyw: '#'-separated; bin: m; others 1). */
int proto_pointset_count_sets(const char *text, size_t len, proto_points_format fmt, size_t *count,
                              const char *field, aa_error *err);
/* UTK .bin / PSA .rps bytes (pointset_binary.c), as proto_pointset_parse_set. */
int proto_pointset_parse_binary(const unsigned char *b, size_t len, proto_points_format fmt,
                                size_t set, proto_pointset *out, size_t *set_count,
                                const char *field, const char *set_field, aa_error *err);
/* The sets of a bin file (UTK's m, the header checked, no point read); 1 for rps. */
int proto_pointset_binary_set_count(const unsigned char *b, size_t len, proto_points_format fmt,
                                    size_t *count, const char *field, aa_error *err);
/* Base64 (RFC 4648, padding required, no line breaks) -> bytes (malloc'd, *len). NULL with
 * *bad_at the offending offset, or with *bad_at == (size_t)-1 on allocation failure. */
unsigned char *proto_base64_decode(const char *s, size_t n, size_t *len, size_t *bad_at);
/* Bytes -> base64 text (NUL-terminated, malloc'd). NULL on allocation failure. */
char *proto_base64_encode(const unsigned char *b, size_t n);
/* A JSON array of points ([x,y], [x,y,w] or {"x","y","w"}) or the object form
 * {"aalab":{...},"points":[...]}. by_index: errors name field[i] (the "data" key); otherwise
 * they name field with "point i: ..." in the message (a JSON text). */
int proto_pointset_from_json(const json_t *j, bool by_index, proto_pointset *out, const char *field,
                             aa_error *err);
void proto_pointset_free(proto_pointset *ps);
/* Appends a point (growing the arrays; *cap is their capacity). AA_ENOMEM on failure. The
 * caller bounds the count by PROTO_POINTS_MAX. */
int proto_pointset_push(proto_pointset *ps, size_t *cap, proto_point p, size_t where);

/* Where the weights of a point set come from (without an aalab header, or to override it). */
typedef enum proto_weights_rule {
    PROTO_WEIGHTS_FILE,   /* the points' w (kernel 1), or the header's per-kernel weights */
    PROTO_WEIGHTS_FILTER, /* each kernel's samples weighted by the filter h(x) h(y), normalised */
    PROTO_WEIGHTS_EQUAL   /* each kernel's samples weighted equally */
} proto_weights_rule;

bool proto_weights_rule_parse(const char *name, proto_weights_rule *out);
const char *proto_weights_rule_name(proto_weights_rule r);

typedef struct proto_points_options {
    int tile;                   /* T, 0 = not stated (the header's, else 1) */
    int kernel;                 /* K, 0 = not stated (the header's, else 1) */
    int border;                 /* -1 = not stated (the header's, else false), 0, 1 */
    proto_weights_rule weights; /* PROTO_WEIGHTS_FILE by default */
    const aa_filter *filter;    /* for PROTO_WEIGHTS_FILTER; NULL = the default (Mitchell) */
    unsigned flags;             /* AA_PATTERN_NORMALIZE */
} proto_points_options;

/* Default options: nothing stated, weights from the file. */
proto_points_options proto_points_options_default(void);

/* Builds the pattern a point set describes: with an aalab header, exactly the exported pattern
 * (stated options must agree with it; weights filter/equal replace its weights); without, a
 * tile pattern of the stated T, K, border and weights. Errors name options_field ("pattern.
 * points") + ".tile" / ".kernel" / ".weights" for options and points_field (".text" /
 * ".data") for the points themselves, with the line of the point at fault. */
int proto_pattern_from_pointset(const proto_pointset *ps, const proto_points_options *o,
                                aa_pattern *out, const char *options_field,
                                const char *points_field, aa_error *err);

/* The pattern as a point set with its aalab header: the tile samples divided by T, with a w per
 * point where every kernel reading a sample gives it the same weight. A pattern without a tile
 * (explicit kernels, s not a square) lists its first kernel's samples around the pixel centre
 * (+0.5) and restores from the header's wire form. AA_ENOMEM on allocation failure. */
int proto_pointset_of_pattern(const aa_pattern *p, proto_pointset *out, aa_error *err);
/* The text of a point set in a format (NUL-terminated, malloc'd; *len without the NUL). NULL on
 * allocation failure. Numbers are written with 17 significant digits (exact round trip). bin and
 * rps are bytes (pointset_binary.c): bin float64 with the aalab header as a trailer after the
 * data (UTK's reader stops at the data's end), rps float32 and nothing else (the format has no
 * room: re-import with tile, kernel and weights). */
char *proto_pointset_write(const proto_pointset *ps, proto_points_format fmt, size_t *len);
/* bin and rps bytes (pointset_binary.c; proto_pointset_write calls it). */
char *proto_pointset_write_binary(const proto_pointset *ps, proto_points_format fmt, size_t *len);
/* The two above in one step. */
char *proto_export_points(const aa_pattern *p, proto_points_format fmt, size_t *len, aa_error *err);

/* Vulkan (VK_EXT_sample_locations) or D3D12 (SetSamplePositions) programmable sample positions
 * where representable (every pixel holds the same power-of-two count 1..16; D3D12 also a 1x1
 * or 2x2 tile and positions on its 1/16 grid), else {"representable": false, "reason"}. */
json_t *proto_export_gpu(const aa_pattern *p, bool d3d12);
/* Metal (MTLRenderPassDescriptor setSamplePositions:count:): one pixel's MTLSamplePosition list
 * for every pixel, so a 1x1 tile of 1, 2, 4 or 8 samples, each on the 1/16 grid in
 * [0, 15/16], else {"representable": false, "reason"}. */
json_t *proto_export_metal(const aa_pattern *p);

/* Export formats by name: "json" (aalab's pattern JSON), "utk", "xyw", "csv", "bin", "rps",
 * "points-json" (the point-set JSON), "vulkan", "d3d12", "metal". false for anything else. */
typedef enum proto_export_writer {
    PROTO_EXPORT_PATTERN,
    PROTO_EXPORT_POINTS,
    PROTO_EXPORT_VULKAN,
    PROTO_EXPORT_D3D12,
    PROTO_EXPORT_METAL
} proto_export_writer;

bool proto_export_format_parse(const char *name, proto_export_writer *writer,
                               proto_points_format *points);
#define PROTO_EXPORT_FORMATS "json, utk, xyw, csv, bin, rps, points-json, vulkan, d3d12 or metal"

#endif
