/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * What the IO-Base controller test programs share: logical addresses, short sleeps and
 * waiting for a mode their MODE_IND callback reports. Header-only; include after
 * pniousrx.h, with _POSIX_C_SOURCE defined (nanosleep).
 */
#ifndef PROCIMG_TESTS_IOBASE_CONTROLLER_H
#define PROCIMG_TESTS_IOBASE_CONTROLLER_H

#include "pniousrx.h"

#include <stdatomic.h>
#include <string.h>
#include <time.h>

static inline void sleep_ms(long ms) {
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

/* The logical address `a` in the input or output space. */
static inline PNIO_ADDR logical_addr(PNIO_IO_TYPE io, PNIO_UINT32 a) {
    PNIO_ADDR x;
    memset(&x, 0, sizeof x);
    x.AddrType = PNIO_ADDR_LOG;
    x.IODataType = io;
    x.u.Addr = a;
    return x;
}

/* Waits up to 10 s until *seen, which the program's MODE_IND callback sets, is mode m. */
static inline int wait_for_mode(atomic_int *seen, int m) {
    int i;
    for (i = 0; i < 1000 && atomic_load(seen) != m; i++) {
        sleep_ms(10);
    }
    return atomic_load(seen) == m;
}

#endif
