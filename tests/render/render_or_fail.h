/* A render whose failure is a test's FAIL line, for the render tests that
 * build their scenes in code. A header, not part of the harness: CHECK
 * counts into the including program's own tally (tests/check.h). */
#ifndef LVCL_TESTS_RENDER_OR_FAIL_H
#define LVCL_TESTS_RENDER_OR_FAIL_H

#include <stdio.h>

#include "../check.h"
#include "../harness.h"

/* harness_render_with; returns the image (malloc'ed), or NULL after the
 * line "FAIL <what>: render: <why>". */
static float *render_or_fail(lvcl_scene *scene, const lvcl_session_config *cfg, const lvcl_render_request *req,
                             const char *what)
{
    lvcl_status st = {0};
    lvcl_render_result r = {0};
    if (harness_render_with(scene, cfg, req, &r, &st)) {
        char name[240];
        snprintf(name, sizeof name, "%s: render", what);
        CHECK(name, 0, "%s", st.message);
        return NULL;
    }
    return r.rgb;
}

#endif
