/* libFuzzer harness for lvcl's command line: the input, split at NUL bytes,
 * is argv; parsing must accept it or refuse it with a one-line message. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../host/app/options.h"

#define MAX_ARGS 64

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = 0;
    char *argv[MAX_ARGS + 1] = {"lvcl"};
    int argc = 1;
    for (char *p = text; p < text + size && argc < MAX_ARGS; p += strlen(p) + 1) argv[argc++] = p;
    argv[argc] = NULL;
    lvcl_options o;
    lvcl_status st = {0};
    if (lvcl_options_parse(argc, argv, &o, &st) != LVCL_OK && (!st.message[0] || strchr(st.message, '\n'))) {
        fprintf(stderr, "refused without a one-line message: '%s'\n", st.message);
        __builtin_trap();
    }
    free(text);
    return 0;
}
