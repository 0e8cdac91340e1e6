/* The --device argument's lists of devices: "all", or indices "0,2". */
#ifndef LVCL_DEVICE_LIST_H
#define LVCL_DEVICE_LIST_H

#include "device.h"

#define LVCL_MAX_DEVICES 16

/* The device indices that spec names ("all", or a comma-separated list) in
 * indices[0 .. *count); *count = 0 if it names a single device (NULL, cpu,
 * gpu, an index) for lvcl_device_open. */
lvcl_error lvcl_device_list_parse(const char *spec, int indices[LVCL_MAX_DEVICES], int *count, lvcl_status *st);

#endif
