/* Error reporting for the engine: negative status codes (libuv style) plus an optional
 * aa_error that names the offending input field, so the HTTP layer can answer
 * {"error":{"code","message","field"}} without re-validating. */
#ifndef AA_ERROR_H
#define AA_ERROR_H

enum {
    AA_OK = 0,
    AA_EINVAL = -22,    /* invalid argument */
    AA_ENOMEM = -12,    /* allocation failed */
    AA_ERANGE = -34,    /* value outside the supported range (too many samples, angles, ...) */
    AA_ECANCELED = -125 /* a progress callback asked to stop */
};

typedef struct aa_error {
    int code;       /* one of the AA_E* values, 0 when no error */
    char field[96]; /* JSON path of the offending input relative to the engine object, "" if none */
    char message[192]; /* human-readable, one sentence */
} aa_error;

/* Fills err (if not NULL) and returns code. printf-style message. */
int aa_error_set(aa_error *err, int code, const char *field, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
const char *aa_strerror(int code);

#endif
