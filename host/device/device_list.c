#include "device_list.h"

#include <stdlib.h>
#include <string.h>

lvcl_error lvcl_device_list_parse(const char *spec, int indices[LVCL_MAX_DEVICES], int *count, lvcl_status *st)
{
    *count = 0;
    if (!spec || (strcmp(spec, "all") && !strchr(spec, ','))) return LVCL_OK;
    int n = 0;
    if (!strcmp(spec, "all")) {
        int available = lvcl_device_count(0);
        if (available == 0) return lvcl_fail(st, LVCL_ERR_DEVICE, "no OpenCL device found");
        for (; n < available && n < LVCL_MAX_DEVICES; n++) indices[n] = n;
        *count = n;
        return LVCL_OK;
    }
    for (const char *p = spec; *p;) {
        char *end;
        long v = strtol(p, &end, 10);
        if (end == p || v < 0 || (*end && *end != ','))
            return lvcl_fail(st, LVCL_ERR_USAGE, "bad device list '%s' (expected indices like 0,2, or all)", spec);
        for (int k = 0; k < n; k++)
            if (indices[k] == v) return lvcl_fail(st, LVCL_ERR_USAGE, "device %ld is listed twice in '%s'", v, spec);
        if (n == LVCL_MAX_DEVICES)
            return lvcl_fail(st, LVCL_ERR_USAGE, "more than %d devices in '%s'", LVCL_MAX_DEVICES, spec);
        indices[n++] = (int)v;
        p = *end ? end + 1 : end;
    }
    *count = n;
    return LVCL_OK;
}
