/* The session's private parts, shared by session.c (opening, closing,
 * accessors), session_volume.c (the light volume over every device) and
 * session_render.c (the camera passes). */
#ifndef LVCL_SESSION_INTERNAL_H
#define LVCL_SESSION_INTERNAL_H

#include "session.h"

/* The scene on one device, and that device's share of the last render. */
typedef struct {
    lvcl_device device;
    lvcl_device_scene device_scene;
    lvcl_program program;
    lvcl_light_volume *volume; /* lv modes only */
    lvcl_pass_share pass;
} session_device;

struct lvcl_session {
    lvcl_scene scene;
    lvcl_accel accel;
    lvcl_packed_scene packed;
    session_device devices[LVCL_MAX_DEVICES];
    int device_count;
    double merge_seconds;
    unsigned features;
    double bvh_build_seconds;
};

#endif
