/* Errors and warnings. Every fallible host function returns an lvcl_error and,
 * on failure, leaves a one-line message in an lvcl_status the caller owns. */
#ifndef LVCL_STATUS_H
#define LVCL_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    LVCL_OK = 0,
    LVCL_ERR_USAGE,        /* bad command-line flags or values */
    LVCL_ERR_IO,           /* a file could not be read or written */
    LVCL_ERR_PARSE,        /* malformed input (glTF JSON, GLB container, accessors) */
    LVCL_ERR_UNSUPPORTED,  /* valid input using a feature lvcl does not have */
    LVCL_ERR_DEVICE,       /* no OpenCL device, or an OpenCL call failed */
    LVCL_ERR_TOO_LARGE,    /* the scene does not fit the device's memory budget */
    LVCL_ERR_OUT_OF_MEMORY, /* a host allocation failed */
    LVCL_ERR_CLUSTER        /* the processes of a distributed render could not talk (lvcl-mpi) */
} lvcl_error;

typedef struct {
    lvcl_error code;
    char message[512];
} lvcl_status;

/* Records `code` and a printf-style message in `st` (if non-NULL); returns `code`. */
lvcl_error lvcl_fail(lvcl_status *st, lvcl_error code, const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Prints "lvcl: warning: ..." on stderr, unless muted. */
void lvcl_warn(const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 1, 2)))
#endif
    ;

/* Mutes warnings (1) or lets them through (0): lvcl-mpi's ranks but 0 keep quiet. */
void lvcl_warn_mute(int mute);

/* A size for messages ("512 B", "3.2 MiB", "21.8 TiB") written into `buf`;
 * returns `buf`. */
const char *lvcl_bytes_text(double bytes, char buf[32]);

#ifdef __cplusplus
}
#endif
#endif
