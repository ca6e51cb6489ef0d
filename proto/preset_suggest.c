#define _POSIX_C_SOURCE 200809L
#include "preset_suggest.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "aa_pattern.h"

#define NAME_MAX_LEN 64

/* Levenshtein distance, case-insensitive, of the first NAME_MAX_LEN bytes. */
static size_t edit_distance(const char *a, const char *b)
{
    size_t la = strnlen(a, NAME_MAX_LEN), lb = strnlen(b, NAME_MAX_LEN);
    size_t row[NAME_MAX_LEN + 1];
    for (size_t j = 0; j <= lb; j++)
        row[j] = j;
    for (size_t i = 1; i <= la; i++) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= lb; j++) {
            size_t up = row[j];
            size_t cost = tolower((unsigned char)a[i - 1]) != tolower((unsigned char)b[j - 1]);
            size_t best = diag + cost;
            if (up + 1 < best)
                best = up + 1;
            if (row[j - 1] + 1 < best)
                best = row[j - 1] + 1;
            row[j] = best;
            diag = up;
        }
    }
    return row[lb];
}

size_t proto_preset_nearest(const char *name, const char *out[PROTO_SUGGEST_MAX])
{
    size_t dist[PROTO_SUGGEST_MAX], n = 0;
    for (size_t i = 0; i < aa_preset_count(); i++) {
        const char *cand = aa_preset_at(i)->name;
        size_t d = edit_distance(name ? name : "", cand);
        /* Insertion sort into the best PROTO_SUGGEST_MAX (stable: table order breaks ties). */
        size_t at = n;
        while (at > 0 && dist[at - 1] > d)
            at--;
        if (at >= PROTO_SUGGEST_MAX)
            continue;
        size_t last = n < PROTO_SUGGEST_MAX ? n : PROTO_SUGGEST_MAX - 1;
        for (size_t k = last; k > at; k--) {
            dist[k] = dist[k - 1];
            out[k] = out[k - 1];
        }
        dist[at] = d;
        out[at] = cand;
        if (n < PROTO_SUGGEST_MAX)
            n++;
    }
    /* Names much farther than the nearest are noise. */
    while (n > 1 && dist[n - 1] > dist[0] + 2)
        n--;
    return n;
}

int proto_unknown_preset(aa_error *err, const char *field, const char *name)
{
    const char *near[PROTO_SUGGEST_MAX];
    size_t n = proto_preset_nearest(name, near);
    char list[3 * (NAME_MAX_LEN + 8)] = "";
    size_t used = 0;
    for (size_t i = 0; i < n && used < sizeof list; i++) {
        const char *sep = i == 0 ? "" : i + 1 == n ? " or " : ", ";
        int w = snprintf(list + used, sizeof list - used, "%s\"%s\"", sep, near[i]);
        if (w < 0)
            break;
        used += (size_t)w;
    }
    return aa_error_set(err, AA_EINVAL, field, "unknown preset \"%.64s\"; did you mean %s?",
                        name ? name : "", list);
}
