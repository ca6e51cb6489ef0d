/* The service error table (service_error.h). */
#include "service_error.h"

#define ROW(name, value, row, field, message) {#name, value, row, field, message},
const proto_service_row proto_service_rows[] = {PROTO_SERVICE_ERRORS(ROW)};
#undef ROW
const size_t proto_service_row_count = sizeof proto_service_rows / sizeof proto_service_rows[0];

const proto_service_row *proto_service_row_of(int code)
{
    for (size_t i = 0; i < proto_service_row_count; i++)
        if (proto_service_rows[i].value == code)
            return &proto_service_rows[i];
    return NULL;
}
