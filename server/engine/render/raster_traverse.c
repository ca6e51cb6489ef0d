/* Hierarchical early in/out over output pixel blocks (raster_traverse.h). */
#include "raster_traverse.h"

#include <string.h>

typedef struct traversal {
    const aa_scene *scene;
    aa_rect region;
    double offset, extent;
    aa_image *out;
    uint8_t *mask;
    size_t marked;
} traversal;

static void visit(traversal *t, int x0, int y0, int x1, int y1)
{
    double v;
    if (aa_scene_box_uniform(t->scene, x0 + t->offset - t->extent, y0 + t->offset - t->extent,
                             x1 - 1 + t->offset + t->extent, y1 - 1 + t->offset + t->extent, &v)) {
        for (int j = y0; j < y1; j++)
            for (int i = x0; i < x1; i++)
                t->out->px[(size_t)j * t->out->width + i] = (float)v;
        return;
    }
    if (x1 - x0 == 1 && y1 - y0 == 1) {
        size_t rw = (size_t)(t->region.x1 - t->region.x0);
        t->mask[(size_t)(y0 - t->region.y0) * rw + (size_t)(x0 - t->region.x0)] = 1;
        t->marked++;
        return;
    }
    int xm = x1 - x0 > 1 ? (x0 + x1) / 2 : x1, ym = y1 - y0 > 1 ? (y0 + y1) / 2 : y1;
    visit(t, x0, y0, xm, ym);
    if (xm < x1)
        visit(t, xm, y0, x1, ym);
    if (ym < y1) {
        visit(t, x0, ym, xm, y1);
        if (xm < x1)
            visit(t, xm, ym, x1, y1);
    }
}

size_t aa_traverse_footprints(const aa_scene *s, aa_rect region, double offset, double extent,
                              bool skip, aa_image *out, uint8_t *mask)
{
    size_t area = aa_rect_area(region);
    if (area == 0)
        return 0;
    if (!skip) {
        memset(mask, 1, area);
        return area;
    }
    memset(mask, 0, area);
    traversal t = {s, region, offset, extent, out, mask, 0};
    for (int by = region.y0; by < region.y1; by += AA_TRAVERSE_BLOCK)
        for (int bx = region.x0; bx < region.x1; bx += AA_TRAVERSE_BLOCK) {
            int ex = bx + AA_TRAVERSE_BLOCK < region.x1 ? bx + AA_TRAVERSE_BLOCK : region.x1;
            int ey = by + AA_TRAVERSE_BLOCK < region.y1 ? by + AA_TRAVERSE_BLOCK : region.y1;
            visit(&t, bx, by, ex, ey);
        }
    return t.marked;
}
