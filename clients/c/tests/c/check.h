/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * How the C test programs fail: CHECK(cond, fmt, ...) and CHECK_RC(call, expected) name the
 * line, what went wrong and the library's last error on stderr, and exit 1. A program that
 * runs in parts sets check_part to the part's name so that a failure says which part.
 */
#ifndef PROCIMG_TESTS_CHECK_H
#define PROCIMG_TESTS_CHECK_H

#include "procimg.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

static const char *check_part = NULL;

static void fail(int line, const char *fmt, ...) {
    va_list ap;
    if (check_part != NULL) fprintf(stderr, "%s: ", check_part);
    fprintf(stderr, "line %d: ", line);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, " (last error: %s)\n", procimg_last_error());
    exit(1);
}

#define CHECK(cond, ...)                               \
    do {                                               \
        if (!(cond)) fail(__LINE__, __VA_ARGS__);      \
    } while (0)

#define CHECK_RC(call, expected)                                                         \
    do {                                                                                 \
        PNIO_UINT32 rc_ = (call);                                                        \
        if (rc_ != (PNIO_UINT32)(expected))                                              \
            fail(__LINE__, "%s returned 0x%x, expected 0x%x", #call, (unsigned)rc_,      \
                 (unsigned)(expected));                                                  \
    } while (0)

#endif
