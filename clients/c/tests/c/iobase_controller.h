/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * What the IO-Base controller test programs share: the examples' logical addresses and
 * short sleeps (pnio_example.h), and waiting for a mode their MODE_IND callback reports.
 * Header-only; include after pniousrx.h, with _POSIX_C_SOURCE defined (nanosleep).
 */
#ifndef PROCIMG_TESTS_IOBASE_CONTROLLER_H
#define PROCIMG_TESTS_IOBASE_CONTROLLER_H

#include "../../examples/pnio_example.h"
#include "pniousrx.h"

#include <stdatomic.h>

/* Waits up to 10 s until *seen, which the program's MODE_IND callback sets, is mode m. */
static inline int wait_for_mode(atomic_int *seen, int m) {
    int i;
    for (i = 0; i < 1000 && atomic_load(seen) != m; i++) {
        sleep_ms(10);
    }
    return atomic_load(seen) == m;
}

#endif
