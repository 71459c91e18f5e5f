/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * What the C IO device examples (pnio_dev_easy.c, pnio_dev_isochronous.c) share: the demo
 * station's identity, reading the VendorID and DeviceID from the command line or the
 * environment, the annotation they open the device with, geographical addresses and short
 * sleeps. Header-only: static functions, valid C11. A C program defines _POSIX_C_SOURCE
 * (200809L) before its first #include (nanosleep), as the examples do.
 */
#ifndef PROCIMG_EXAMPLES_DEVICE_EXAMPLE_H
#define PROCIMG_EXAMPLES_DEVICE_EXAMPLE_H

#include "pniousrd.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The demo station's (procimgd --demo-device) VendorID and DeviceID. */
#define DEMO_VENDOR_ID 0x0493
#define DEMO_DEVICE_ID 0x0100

/* An ident number: `arg` when given, else the environment variable `env`, else `demo`. */
static inline unsigned long parse_id(const char *arg, const char *env, unsigned long demo) {
    const char *v = arg ? arg : getenv(env);
    return v && *v ? strtoul(v, NULL, 0) : demo;
}

/* The annotation the examples open the device with (what I&M0 and DCP show of it). */
static inline PNIO_ANNOTATION example_annotation(void) {
    PNIO_ANNOTATION ann;
    memset(&ann, 0, sizeof ann);
    strcpy((char *)ann.deviceType, "procimg device");
    strcpy((char *)ann.orderId, "PROCIMG-DEV");
    ann.hwRevision = 1;
    ann.swRevisionPrefix = 'V';
    ann.swRevision2 = 1;
    return ann;
}

/* The geographical address of a submodule (PNIO_IO_IN: the type plug and pull ignore). */
static inline PNIO_DEV_ADDR geo(PNIO_UINT32 slot, PNIO_UINT32 subslot) {
    PNIO_DEV_ADDR a;
    memset(&a, 0, sizeof a);
    a.AddrType = PNIO_ADDR_GEO;
    a.IODataType = PNIO_IO_IN;
    a.u.Geo.Slot = slot;
    a.u.Geo.Subslot = subslot;
    return a;
}

static inline void sleep_ms(long ms) {
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

#endif
