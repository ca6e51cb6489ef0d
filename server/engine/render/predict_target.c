/* aa_predict_rmse_of (predict.h). */
#include "predict.h"

int aa_predict_rmse_of(void *user, const aa_pattern *p, double *rmse, aa_error *err)
{
    const aa_predict_target *t = user;
    aa_prediction pred;
    int rc = aa_predict_rmse(p, t->filter, t->histogram, &pred, err);
    if (!rc)
        *rmse = pred.rmse;
    return rc;
}
