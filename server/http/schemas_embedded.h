/* The JSON Schemas of proto/schemas, embedded at build time (server/embed_schemas.cmake):
 * path relative to proto/schemas ("kinds/optimize.spec.json") and the file's text. */
#ifndef AALAB_SCHEMAS_EMBEDDED_H
#define AALAB_SCHEMAS_EMBEDDED_H

#include <stddef.h>

typedef struct embedded_schema {
    const char *path;
    const char *text;
} embedded_schema;

extern const embedded_schema embedded_schemas[]; /* ends with {NULL, NULL} */
extern const size_t embedded_schema_count;

#endif
