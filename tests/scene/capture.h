/* Helpers shared by the importer tests: reading a whole file, and sending
 * stderr to a temporary file to check the warnings a load prints. */
#ifndef LVCL_TESTS_SCENE_CAPTURE_H
#define LVCL_TESTS_SCENE_CAPTURE_H

#include <stddef.h>
#include <stdio.h>

/* The bytes of file `path` (caller frees), or NULL. */
unsigned char *read_all(const char *path, size_t *size);

typedef struct {
    FILE *tmp;
    int saved_fd;
} capture;

/* Whether LVCL_TEST_VERBOSE is set: then nothing is captured. */
int verbose(void);

void capture_begin(capture *c);

/* Restores stderr and returns what was written meanwhile (caller frees). */
char *capture_end(capture *c);

/* Whether `text` holds an ASan, LSan or UBSan report. */
int sanitizer_report(const char *text);

#endif
