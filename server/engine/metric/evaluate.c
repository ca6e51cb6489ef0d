/* E2 of a whole pattern: every kernel at every angle (metric.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "metric.h"

#define DEG2RAD (3.14159265358979323846 / 180.0)

static int resolve_angles(const aa_metric_params *params, double *angles, size_t *count,
                          aa_error *err)
{
    if (!params || !params->filter || !params->acuity)
        return aa_error_set(err, AA_EINVAL, "", "metric parameters need a filter and an acuity");
    if (!params->angles_deg) {
        *count = aa_acuity_default_angles(params->acuity, angles, AA_MAX_ANGLES);
        return AA_OK;
    }
    if (params->angle_count == 0)
        return aa_error_set(err, AA_EINVAL, "angles", "the angle list is empty");
    if (params->angle_count > AA_MAX_ANGLES)
        return aa_error_set(err, AA_ERANGE, "angles", "at most %d angles", AA_MAX_ANGLES);
    for (size_t i = 0; i < params->angle_count; i++) {
        double a = params->angles_deg[i];
        if (!isfinite(a) || fabs(a) > 1e6) {
            char field[32];
            snprintf(field, sizeof field, "angles[%zu]", i);
            return aa_error_set(err, AA_EINVAL, field, "angle must be a finite number of degrees");
        }
        angles[i] = a;
    }
    *count = params->angle_count;
    return AA_OK;
}

static int check_lp(const aa_metric_params *params, aa_error *err)
{
    if (params->lp != 0 && !(isfinite(params->lp) && params->lp >= 1 && params->lp <= 1e3))
        return aa_error_set(err, AA_EINVAL, "lp", "lp must be 0 (off) or a number in [1, 1000]");
    return AA_OK;
}

void aa_evaluation_free(aa_evaluation *e)
{
    free(e->angles_deg);
    free(e->weight);
    free(e->e1);
    memset(e, 0, sizeof *e);
}

int aa_evaluate(const aa_pattern *p, const aa_metric_params *params, aa_evaluation *out,
                aa_error *err)
{
    memset(out, 0, sizeof *out);
    double *angles = malloc(AA_MAX_ANGLES * sizeof *angles);
    if (!angles)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    size_t na = 0;
    int rc = resolve_angles(params, angles, &na, err);
    if (!rc)
        rc = check_lp(params, err);
    if (rc) {
        free(angles);
        return rc;
    }
    size_t nk = p->kernel_count;
    out->angles_deg = angles;
    out->weight = malloc(na * sizeof *out->weight);
    out->e1 = malloc(nk * na * sizeof *out->e1);
    if (!out->weight || !out->e1) {
        aa_evaluation_free(out);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    out->kernel_count = nk;
    out->angle_count = na;
    out->e2 = -1;
    out->lp_norm = NAN;
    /* Directions once per call; each kernel is one kernel x angle block (aa_e1_kernel_block):
     * its samples copied once, its sort reused from angle to angle (metric.h). */
    double *dir_c = malloc(2 * na * sizeof *dir_c), *dir_s = dir_c ? dir_c + na : NULL;
    if (!dir_c) {
        aa_evaluation_free(out);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    for (size_t a = 0; a < na; a++) {
        out->weight[a] = aa_acuity_weight(params->acuity, angles[a]);
        aa_metric_direction(angles[a] * DEG2RAD, &dir_c[a], &dir_s[a]);
    }

    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    double sum = 0, sum_p = 0;
    for (size_t k = 0; k < nk && !rc; k++) {
        const aa_kernel *ker = &p->kernels[k];
        double *row = out->e1 + k * na;
        rc = aa_e1_kernel_block(params->filter, ker->samples, ker->count, dir_c, dir_s, na,
                                AA_E1_AUTO, &ws, row);
        if (rc) {
            aa_error_set(err, rc, "", "out of memory");
            break;
        }
        for (size_t a = 0; a < na; a++) {
            if (!isfinite(row[a])) {
                char field[48];
                snprintf(field, sizeof field, "pattern.kernels[%zu]", k);
                rc =
                    aa_error_set(err, AA_ERANGE, field,
                                 "E1 overflows for kernel %zu (weights or positions too large)", k);
                break;
            }
            double v = out->weight[a] * row[a];
            sum += v;
            if (params->lp != 0)
                sum_p += pow(v, params->lp);
            if (v > out->e2) {
                out->e2 = v;
                out->argmax_kernel = k;
                out->argmax_angle_deg = angles[a];
            }
        }
    }
    aa_metric_workspace_free(&ws);
    free(dir_c);
    if (rc) {
        aa_evaluation_free(out);
        return rc;
    }
    out->mean = sum / (double)(nk * na);
    if (params->lp != 0)
        out->lp_norm = pow(sum_p / (double)(nk * na), 1.0 / params->lp);
    return AA_OK;
}

int aa_evaluate_dense(const aa_pattern *p, const aa_metric_params *params, double step_deg,
                      aa_dense_check *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    if (!isfinite(step_deg) || step_deg < 0.01 || step_deg > 45)
        return aa_error_set(err, AA_EINVAL, "dense_step_deg",
                            "dense angle step must be in [0.01, 45] degrees");
    aa_evaluation table;
    int rc = aa_evaluate(p, params, &table, err);
    if (rc)
        return rc;
    out->table_max = table.e2;
    aa_evaluation_free(&table);

    out->step_deg = step_deg;
    out->max_weighted = -1;
    size_t steps = (size_t)ceil(180.0 / step_deg - 1e-9);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    for (size_t k = 0; k < p->kernel_count && !rc; k++) {
        const aa_kernel *ker = &p->kernels[k];
        for (size_t i = 0; i < steps; i++) {
            double deg = (double)i * step_deg, e1;
            rc = aa_e1_at_angle(params->filter, ker->samples, ker->count, deg * DEG2RAD, &ws, &e1);
            if (rc) {
                aa_error_set(err, rc, "", "out of memory");
                break;
            }
            double v = aa_acuity_weight(params->acuity, deg) * e1;
            if (v > out->max_weighted) {
                out->max_weighted = v;
                out->argmax_kernel = k;
                out->argmax_angle_deg = deg;
            }
        }
    }
    aa_metric_workspace_free(&ws);
    out->between_table_angles = out->max_weighted > out->table_max * (1 + 1e-9);
    return rc;
}
