/* aa_edge_histogram_folded (edge_histogram.h). */
#include "edge_histogram.h"

#include <string.h>

void aa_edge_histogram_folded(const aa_edge_histogram *h, double out[AA_EDGE_BINS])
{
    memcpy(out, h->length, sizeof h->length);
    for (size_t i = 0; i < h->locked_count; i++)
        out[aa_locked_edge_bin(&h->locked[i])] += h->locked[i].length;
}
