/* Captures what a printer writes to a FILE * (open_memstream), for output tests. */
#ifndef AALAB_TEST_CAPTURE_H
#define AALAB_TEST_CAPTURE_H

#include <stdio.h>
#include <stdlib.h>

typedef struct capture {
    FILE *f;
    char *text;
    size_t len;
} capture;

static inline FILE *capture_begin(capture *c)
{
    c->text = NULL;
    c->len = 0;
    c->f = open_memstream(&c->text, &c->len);
    return c->f;
}

/* Returns the text (owned by c until capture_free). */
static inline const char *capture_end(capture *c)
{
    fclose(c->f);
    return c->text;
}

static inline void capture_free(capture *c)
{
    free(c->text);
}

#endif
