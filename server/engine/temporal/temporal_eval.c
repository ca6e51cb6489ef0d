/* E2 per phase, flicker and the after-cut curve of a temporal pattern (temporal_eval.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "temporal_eval.h"
#include "temporal_flicker.h"

#define DEG2RAD (3.14159265358979323846 / 180.0)

void aa_temporal_evaluation_free(aa_temporal_evaluation *e)
{
    free(e->phase_e2);
    free(e->angles_deg);
    free(e->weight);
    free(e->e1);
    free(e->f1);
    free(e->after_cut);
    memset(e, 0, sizeof *e);
}

static int resolve_angles(const aa_metric_params *params, aa_temporal_evaluation *out,
                          aa_error *err)
{
    if (!params || !params->filter || !params->acuity)
        return aa_error_set(err, AA_EINVAL, "", "metric parameters need a filter and an acuity");
    double *angles = malloc(AA_MAX_ANGLES * sizeof *angles);
    if (!angles)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    out->angles_deg = angles;
    if (!params->angles_deg) {
        out->angle_count = aa_acuity_default_angles(params->acuity, angles, AA_MAX_ANGLES);
        return AA_OK;
    }
    if (params->angle_count == 0 || params->angle_count > AA_MAX_ANGLES)
        return aa_error_set(err, AA_ERANGE, "angles", "1 to %d angles", AA_MAX_ANGLES);
    for (size_t i = 0; i < params->angle_count; i++) {
        if (!isfinite(params->angles_deg[i]) || fabs(params->angles_deg[i]) > 1e6) {
            char field[32];
            snprintf(field, sizeof field, "angles[%zu]", i);
            return aa_error_set(err, AA_EINVAL, field, "angle must be a finite number of degrees");
        }
        angles[i] = params->angles_deg[i];
    }
    out->angle_count = params->angle_count;
    return AA_OK;
}

/* Max of W E1 over the angles of one kernel; e1 gets the unweighted row. */
static int kernel_row(const aa_metric_params *params, const aa_sample *s, size_t n,
                      const double *dc, const double *ds, const double *weight, size_t na,
                      aa_metric_workspace *ws, double *e1, double *best, size_t *best_a)
{
    int rc = aa_e1_kernel_block(params->filter, s, n, dc, ds, na, AA_E1_AUTO, ws, e1);
    if (rc)
        return rc;
    *best = -1;
    for (size_t a = 0; a < na; a++) {
        if (!isfinite(e1[a]))
            return AA_ERANGE;
        if (weight[a] * e1[a] > *best) {
            *best = weight[a] * e1[a];
            *best_a = a;
        }
    }
    return AA_OK;
}

int aa_temporal_evaluate(const aa_temporal *t, const aa_metric_params *params, size_t cut_frames,
                         aa_temporal_evaluation *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    size_t N = t->phase_count, G = t->group_count;
    size_t K = cut_frames ? cut_frames : 4 * N;
    if (cut_frames > AA_TEMPORAL_MAX_CUT_FRAMES)
        return aa_error_set(err, AA_ERANGE, "cut_frames", "cut_frames must be at most %d",
                            AA_TEMPORAL_MAX_CUT_FRAMES);
    if (K > AA_TEMPORAL_MAX_CUT_FRAMES)
        K = AA_TEMPORAL_MAX_CUT_FRAMES;
    int rc = resolve_angles(params, out, err);
    if (rc) {
        aa_temporal_evaluation_free(out);
        return rc;
    }
    size_t na = out->angle_count, m = 0;
    for (size_t g = 0; g < G; g++)
        if (t->groups[g].count > m)
            m = t->groups[g].count;
    out->phase_count = N;
    out->group_count = G;
    out->cut_count = K;
    out->phase_e2 = malloc(N * sizeof *out->phase_e2);
    out->weight = malloc(na * sizeof *out->weight);
    out->e1 = malloc(N * G * na * sizeof *out->e1);
    out->f1 = malloc(G * na * sizeof *out->f1);
    out->after_cut = malloc(K * sizeof *out->after_cut);
    double *dc = malloc(2 * na * sizeof *dc), *ds = dc ? dc + na : NULL;
    aa_sample *kernel = malloc((m ? m : 1) * sizeof *kernel);
    double *row = malloc(na * sizeof *row);
    double *cut_w = malloc(K * sizeof *cut_w), *frame_sum = malloc(N * sizeof *frame_sum);
    aa_flicker_scratch sc = {0};
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    if (!out->phase_e2 || !out->weight || !out->e1 || !out->f1 || !out->after_cut || !dc ||
        !kernel || !row || !cut_w || !frame_sum || aa_flicker_scratch_init(&sc, t, m))
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t a = 0; a < na && !rc; a++) {
        out->weight[a] = aa_acuity_weight(params->acuity, out->angles_deg[a]);
        aa_metric_direction(out->angles_deg[a] * DEG2RAD, &dc[a], &ds[a]);
    }

    /* Steady state: every phase of every group. */
    out->e2 = -1;
    double mean = 0;
    for (size_t p = 0; p < N && !rc; p++) {
        out->phase_e2[p] = -1;
        for (size_t g = 0; g < G && !rc; g++) {
            size_t n = aa_temporal_phase_kernel(t, g, p, kernel);
            double best;
            size_t best_a = 0;
            rc = kernel_row(params, kernel, n, dc, ds, out->weight, na, &ws,
                            out->e1 + (p * G + g) * na, &best, &best_a);
            if (rc) {
                aa_error_set(err, rc, "temporal", "E1 of phase %zu cannot be evaluated", p);
                break;
            }
            if (best > out->phase_e2[p])
                out->phase_e2[p] = best;
            if (best > out->e2) {
                out->e2 = best;
                out->argmax_phase = p;
                out->argmax_group = g;
                out->argmax_angle_deg = out->angles_deg[best_a];
            }
        }
        mean += out->phase_e2[p];
    }
    out->mean_phase_e2 = mean / (double)N;
    out->effective_samples = aa_effective_samples(t->age_weight, N);

    /* Flicker: the angles in order, so each sort starts from the previous angle's order. */
    out->f2 = -1;
    for (size_t g = 0; g < G && !rc; g++) {
        aa_flicker_scratch_reset(&sc, t->groups[g].count);
        for (size_t a = 0; a < na; a++) {
            double f1 = aa_flicker_sorted(t, g, dc[a], ds[a], &sc, NULL);
            out->f1[g * na + a] = f1;
            if (out->weight[a] * f1 > out->f2) {
                out->f2 = out->weight[a] * f1;
                out->f2_group = g;
                out->f2_angle_deg = out->angles_deg[a];
            }
        }
    }

    /* After a cut: k = 1..K frames. */
    for (size_t k = 1; k <= K && !rc; k++) {
        out->after_cut[k - 1] = -1;
        for (size_t g = 0; g < G && !rc; g++) {
            size_t n = aa_temporal_cut_kernel(t, g, k, cut_w, frame_sum, kernel);
            double best;
            size_t best_a = 0;
            rc = kernel_row(params, kernel, n, dc, ds, out->weight, na, &ws, row, &best, &best_a);
            if (rc)
                aa_error_set(err, rc, "temporal", "E1 after %zu frames cannot be evaluated", k);
            else if (best > out->after_cut[k - 1])
                out->after_cut[k - 1] = best;
        }
    }
    out->frames_to_settle = -1;
    if (!rc) {
        for (size_t k = K; k >= 1; k--) {
            double ss = out->phase_e2[(k - 1) % N];
            if (fabs(out->after_cut[k - 1] - ss) > AA_TEMPORAL_SETTLE_TOLERANCE * ss)
                break;
            out->frames_to_settle = (long)k;
        }
    }
    aa_metric_workspace_free(&ws);
    aa_flicker_scratch_free(&sc);
    free(dc);
    free(kernel);
    free(row);
    free(cut_w);
    free(frame_sum);
    if (rc)
        aa_temporal_evaluation_free(out);
    return rc;
}
