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
    PROTO_POINTS_JSON
} proto_points_format;

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

/* "utk" | "xyw" | "csv" | "json" -> format; false for anything else. */
bool proto_points_format_parse(const char *name, proto_points_format *out);
const char *proto_points_format_name(proto_points_format f);

/* Parses text (len bytes, need not be NUL-terminated) in the given format. Errors name field
 * (e.g. "pattern.points.text") with "line N: ..." in the message. On error *out holds nothing
 * to free. */
int proto_pointset_parse(const char *text, size_t len, proto_points_format fmt, proto_pointset *out,
                         const char *field, aa_error *err);
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
 * allocation failure. Numbers are written with 17 significant digits (exact round trip). */
char *proto_pointset_write(const proto_pointset *ps, proto_points_format fmt, size_t *len);
/* The two above in one step. */
char *proto_export_points(const aa_pattern *p, proto_points_format fmt, size_t *len, aa_error *err);

/* Vulkan (VK_EXT_sample_locations) or D3D12 (SetSamplePositions) programmable sample positions
 * where representable (every pixel holds the same power-of-two count 1..16; D3D12 also a 1x1
 * or 2x2 tile and positions on its 1/16 grid), else {"representable": false, "reason"}. */
json_t *proto_export_gpu(const aa_pattern *p, bool d3d12);

/* Export formats by name: "json" (aalab's pattern JSON), "utk", "xyw", "csv", "points-json"
 * (the point-set JSON), "vulkan", "d3d12". false for anything else. */
typedef enum proto_export_kind {
    PROTO_EXPORT_PATTERN,
    PROTO_EXPORT_POINTS,
    PROTO_EXPORT_VULKAN,
    PROTO_EXPORT_D3D12
} proto_export_kind;

bool proto_export_format_parse(const char *name, proto_export_kind *kind,
                               proto_points_format *points);
#define PROTO_EXPORT_FORMATS "json, utk, xyw, csv, points-json, vulkan or d3d12"

#endif
