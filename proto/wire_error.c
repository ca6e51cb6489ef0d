/* The error table (wire_error.h). */
#include "wire_error.h"

#include <string.h>

#define ROW(name, status, code, retry_after) {#name, status, code, retry_after},
static const proto_wire_row rows[WIRE_ERROR_COUNT] = {PROTO_WIRE_ERRORS(ROW)};
#undef ROW

#define ENGINE_ROW(aa, row) {#aa, aa, row},
const proto_wire_engine_row proto_wire_engine_rows[] = {PROTO_WIRE_ENGINE_ERRORS(ENGINE_ROW)};
#undef ENGINE_ROW
const size_t proto_wire_engine_row_count =
    sizeof proto_wire_engine_rows / sizeof proto_wire_engine_rows[0];

const proto_wire_row *proto_wire_row_of(proto_wire_error e)
{
    if ((int)e < 0 || e >= WIRE_ERROR_COUNT)
        e = WIRE_INTERNAL;
    return &rows[e];
}

proto_wire_error proto_wire_error_of_aa(int aa_code)
{
    switch (aa_code) {
#define ENGINE_CASE(aa, row)                                                                       \
    case aa:                                                                                       \
        return row;
        PROTO_WIRE_ENGINE_ERRORS(ENGINE_CASE)
#undef ENGINE_CASE
    default:
        return WIRE_INTERNAL;
    }
}

const char *proto_http_reason(int status)
{
    switch (status) {
#define REASON_CASE(s, phrase)                                                                     \
    case s:                                                                                        \
        return phrase;
        PROTO_HTTP_STATUSES(REASON_CASE)
#undef REASON_CASE
    default:
        return "Error";
    }
}

const proto_wire_row *proto_wire_row_find(int status, const char *code)
{
    for (size_t i = 0; code && i < WIRE_ERROR_COUNT; i++)
        if (rows[i].status == status && !strcmp(rows[i].code, code))
            return &rows[i];
    return NULL;
}
