#define _POSIX_C_SOURCE 200809L
#include "http.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <curl/curl.h>

#include "exit_codes.h"

#define MAX_RESPONSE_BYTES (256u * 1024 * 1024) /* refuse absurd answers instead of eating RAM */

struct http_client {
    CURL *curl;
    char *socket_path;
    long timeout_ms;
};

typedef struct buffer {
    char *data;
    size_t len, cap;
    bool too_big;
} buffer;

int exit_code_for_status(long status)
{
    if (status >= 200 && status < 300)
        return EXIT_OK;
    if (status >= 400 && status < 500)
        return EXIT_CLIENT_4XX;
    return EXIT_SERVER_5XX; /* 5xx, and anything else unexpected from the server */
}

http_client *http_client_new(const char *socket_path, long timeout_ms)
{
    static bool initialised;
    if (!initialised) { /* single-threaded CLI: one global init is enough */
        if (curl_global_init(CURL_GLOBAL_DEFAULT) != CURLE_OK)
            return NULL;
        initialised = true;
    }
    http_client *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    c->curl = curl_easy_init();
    c->socket_path = strdup(socket_path);
    c->timeout_ms = timeout_ms;
    if (!c->curl || !c->socket_path) {
        http_client_free(c);
        return NULL;
    }
    return c;
}

void http_client_free(http_client *c)
{
    if (!c)
        return;
    if (c->curl)
        curl_easy_cleanup(c->curl);
    free(c->socket_path);
    free(c);
}

const char *http_client_socket(const http_client *c)
{
    return c->socket_path;
}

static size_t on_body(char *data, size_t size, size_t nmemb, void *userp)
{
    buffer *b = userp;
    size_t n = size * nmemb;
    if (b->len + n + 1 > MAX_RESPONSE_BYTES) {
        b->too_big = true;
        return 0; /* aborts the transfer */
    }
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->len + n + 1)
            cap *= 2;
        char *p = realloc(b->data, cap);
        if (!p)
            return 0;
        b->data = p;
        b->cap = cap;
    }
    memcpy(b->data + b->len, data, n);
    b->len += n;
    b->data[b->len] = '\0';
    return n;
}

/* Keeps Retry-After (delta-seconds form, which is what aalabd sends). */
static size_t on_header(char *data, size_t size, size_t nmemb, void *userp)
{
    http_response *r = userp;
    size_t n = size * nmemb;
    static const char name[] = "retry-after:";
    if (n > sizeof name - 1 && strncasecmp(data, name, sizeof name - 1) == 0) {
        char value[32];
        size_t len = n - (sizeof name - 1);
        if (len >= sizeof value)
            len = sizeof value - 1;
        memcpy(value, data + sizeof name - 1, len);
        value[len] = '\0';
        long v = strtol(value, NULL, 10);
        if (v > 0)
            r->retry_after = v;
    }
    return n;
}

int http_request(http_client *c, const char *method, const char *path, const char *body,
                 size_t body_len, http_response *out, char *err, size_t errcap)
{
    memset(out, 0, sizeof *out);
    buffer b = {0};
    char url[2048];
    char curl_err[CURL_ERROR_SIZE] = "";
    /* The host name is irrelevant over a Unix socket but must be a loopback name: the daemon
     * checks Host on TCP, and keeping one spelling avoids surprises. */
    if (snprintf(url, sizeof url, "http://localhost%s", path) >= (int)sizeof url) {
        snprintf(err, errcap, "request path too long");
        return -1;
    }
    CURL *h = c->curl;
    curl_easy_reset(h);
    curl_easy_setopt(h, CURLOPT_UNIX_SOCKET_PATH, c->socket_path);
    curl_easy_setopt(h, CURLOPT_URL, url);
    curl_easy_setopt(h, CURLOPT_WRITEFUNCTION, on_body);
    curl_easy_setopt(h, CURLOPT_WRITEDATA, &b);
    curl_easy_setopt(h, CURLOPT_HEADERFUNCTION, on_header);
    curl_easy_setopt(h, CURLOPT_HEADERDATA, out);
    curl_easy_setopt(h, CURLOPT_ERRORBUFFER, curl_err);
    curl_easy_setopt(h, CURLOPT_NOSIGNAL, 1L);
    curl_easy_setopt(h, CURLOPT_CONNECTTIMEOUT_MS, 10000L);
    if (c->timeout_ms > 0)
        curl_easy_setopt(h, CURLOPT_TIMEOUT_MS, c->timeout_ms);
    struct curl_slist *headers = NULL;
    headers = curl_slist_append(headers, "Accept: application/json");
    if (strcmp(method, "POST") == 0) {
        headers = curl_slist_append(headers, "Content-Type: application/json");
        curl_easy_setopt(h, CURLOPT_POST, 1L);
        curl_easy_setopt(h, CURLOPT_POSTFIELDS, body ? body : "");
        curl_easy_setopt(h, CURLOPT_POSTFIELDSIZE_LARGE, (curl_off_t)(body ? body_len : 0));
    } else if (strcmp(method, "GET") != 0) {
        curl_easy_setopt(h, CURLOPT_CUSTOMREQUEST, method);
    }
    headers = curl_slist_append(headers, "Expect:"); /* no 100-continue round trip */
    curl_easy_setopt(h, CURLOPT_HTTPHEADER, headers);

    CURLcode rc = curl_easy_perform(h);
    curl_slist_free_all(headers);
    if (rc != CURLE_OK) {
        if (b.too_big)
            snprintf(err, errcap, "response larger than %u bytes", MAX_RESPONSE_BYTES);
        else
            snprintf(err, errcap, "%s: %s", c->socket_path,
                     curl_err[0] ? curl_err : curl_easy_strerror(rc));
        free(b.data);
        return rc == CURLE_COULDNT_CONNECT ? HTTP_NO_DAEMON : HTTP_BROKEN;
    }
    curl_easy_getinfo(h, CURLINFO_RESPONSE_CODE, &out->status);
    char *ct = NULL;
    if (curl_easy_getinfo(h, CURLINFO_CONTENT_TYPE, &ct) == CURLE_OK && ct)
        snprintf(out->content_type, sizeof out->content_type, "%s", ct);
    if (!b.data) {
        b.data = calloc(1, 1);
        if (!b.data) {
            snprintf(err, errcap, "out of memory");
            return -1;
        }
    }
    out->body = b.data;
    out->len = b.len;
    return 0;
}

void http_response_free(http_response *r)
{
    free(r->body);
    r->body = NULL;
    r->len = 0;
}
