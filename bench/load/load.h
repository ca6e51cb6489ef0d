/* The load generator behind aalab_load (bench/load). */
#ifndef AALAB_LOAD_H
#define AALAB_LOAD_H

#include <stdbool.h>

typedef struct load_config {
    char socket_path[256];
    char tcp_host[64];
    int tcp_port; /* 0: Unix socket */
    int connections;
    long requests;
    double seconds;
    char method[8];
    char path[256];
    const char *body;
    bool has_body;
    bool vary;
    char token[80];
} load_config;

typedef struct load_result {
    long requests, errors;
    double seconds, rps, p50_us, p99_us;
} load_result;

int load_run(const load_config *c, load_result *out);

#endif
