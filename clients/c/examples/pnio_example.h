/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * What the C controller examples (pnio_easy.c, pnio_isochronous.c) share besides the
 * server's mode: short sleeps and logical addresses. The C test programs of the controller
 * API use them too. Header-only: static functions, valid C11. A C program defines
 * _POSIX_C_SOURCE (200809L) before its first #include (nanosleep), as the examples do.
 */
#ifndef PROCIMG_EXAMPLES_PNIO_EXAMPLE_H
#define PROCIMG_EXAMPLES_PNIO_EXAMPLE_H

#include "pniousrx.h"

#include <string.h>
#include <time.h>

static inline void sleep_ms(long ms) {
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

/* The logical address `a` in the input or output space. */
static inline PNIO_ADDR logical(PNIO_IO_TYPE io, PNIO_UINT32 a) {
    PNIO_ADDR x;
    memset(&x, 0, sizeof x);
    x.AddrType = PNIO_ADDR_LOG;
    x.IODataType = io;
    x.u.Addr = a;
    return x;
}

#endif
