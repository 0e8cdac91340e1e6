/* Helpers shared by the importer tests (capture.h). */
#define _POSIX_C_SOURCE 200809L

#include "capture.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

unsigned char *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    unsigned char *data = NULL;
    size_t n = 0, cap = 0, got;
    unsigned char buf[4096];
    while ((got = fread(buf, 1, sizeof buf, f)) > 0) {
        if (n + got > cap) {
            cap = (n + got) * 2;
            unsigned char *grown = realloc(data, cap);
            if (!grown) break;
            data = grown;
        }
        memcpy(data + n, buf, got);
        n += got;
    }
    fclose(f);
    *size = n;
    return data;
}

int verbose(void)
{
    return getenv("LVCL_TEST_VERBOSE") != NULL;
}

void capture_begin(capture *c)
{
    c->tmp = NULL;
    c->saved_fd = -1;
    if (verbose()) return;
    fflush(stderr);
    c->tmp = tmpfile();
    if (!c->tmp) return;
    c->saved_fd = dup(2);
    dup2(fileno(c->tmp), 2);
}

char *capture_end(capture *c)
{
    if (!c->tmp) return calloc(1, 1);
    fflush(stderr);
    dup2(c->saved_fd, 2);
    close(c->saved_fd);
    long size = ftell(c->tmp);
    if (size < 0) size = 0;
    char *text = calloc((size_t)size + 1, 1);
    rewind(c->tmp);
    if (text && fread(text, 1, (size_t)size, c->tmp) != (size_t)size) text[0] = '\0';
    fclose(c->tmp);
    return text;
}

int sanitizer_report(const char *text)
{
    return text && (strstr(text, "runtime error") || strstr(text, "AddressSanitizer") || strstr(text, "LeakSanitizer"));
}
