/* job_progress_span_report (job_kind.h): kept apart from job_ctx.c so that kinds tested
 * against a stub job context link it too. */
#include "job_kind.h"

int job_progress_span_report(void *user, double fraction)
{
    job_progress_span *s = user;
    return job_ctx_progress(s->ctx, s->base + s->span * fraction, NULL);
}
