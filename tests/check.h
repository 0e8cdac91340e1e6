/* A minimal test harness. Each test program prints one line per check,
 * "PASS name" or "FAIL name: why", and exits non-zero if any failed;
 * tests/run.sh counts the lines. */
#ifndef LVCL_CHECK_H
#define LVCL_CHECK_H

#include <stdio.h>

static int check_failures;

/* Records one named check; `why` is printed (printf-style) when it fails. */
#define CHECK(name, cond, ...)         \
    do {                               \
        if (cond) {                    \
            printf("PASS %s\n", name); \
        } else {                       \
            printf("FAIL %s: ", name); \
            printf(__VA_ARGS__);       \
            printf("\n");              \
            check_failures++;          \
        }                              \
        fflush(stdout);                \
    } while (0)

/* Prints a skipped check, with the reason; it counts neither way. */
#define SKIP(name, why) printf("SKIP %s: %s\n", name, why)

#define CHECK_EXIT() return check_failures ? 1 : 0

#endif
