/* The argument lists of the test kernels that take the contract's blocks
 * (kernels/shared_types.h), shared by tests/kernels/unit_tests.cl and the
 * tests that bind them. */
#ifndef LV_TEST_ARGS_H
#define LV_TEST_ARGS_H

#include "../../kernels/shared_types.h"

/* The radiance the kernels read from every bin of one stored cell. */
#define T_BIN_RADIANCE_ARGS(X, SEP)                                            \
    X(t_bin_radiance, VOLUME, , volume) SEP() X(t_bin_radiance, VALUE, lv_u32, slot) SEP() \
    X(t_bin_radiance, BUFFER, float4, radiance)

LV_ARG_INDICES(T_BIN_RADIANCE_ARGS, t_bin_radiance);

#endif
