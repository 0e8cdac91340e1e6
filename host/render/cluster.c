#include "cluster.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

lvcl_error lvcl_cluster_agree(lvcl_cluster *c, lvcl_error e, lvcl_status *st)
{
    if (!lvcl_cluster_shared(c)) return e;
    lvcl_status mine = e ? *st : (lvcl_status){0};
    mine.code = e;
    lvcl_status *all = malloc((size_t)c->size * sizeof *all);
    if (!all) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory comparing the processes' outcomes");
    lvcl_error ge = c->gather(c, &mine, sizeof mine, all, st);
    if (ge) {
        free(all);
        return ge;
    }
    int first = -1, failed = 0, alike = 1;
    for (int r = 0; r < c->size; r++) {
        if (!all[r].code) continue;
        failed++;
        if (first < 0) first = r;
        else if (all[r].code != all[first].code || strcmp(all[r].message, all[first].message)) alike = 0;
    }
    lvcl_error out = LVCL_OK;
    if (first >= 0) {
        out = all[first].code;
        if (failed == c->size && alike) *st = all[first];
        else {
            char message[sizeof st->message];
            snprintf(message, sizeof message, "%s", all[first].message);
            lvcl_fail(st, out, "rank %d: %s", first, message);
        }
    }
    c->agreed_failure = out != LVCL_OK;
    free(all);
    return out;
}
