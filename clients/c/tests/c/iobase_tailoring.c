/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * Tailoring the IO system with PNIO_iosystem_reconfig, against a procimgd whose
 * configuration (tests/iobase_tailoring.rs) has three simulated devices:
 *
 *   mandatory    I/Q 0..3, its port 1 (diagnostic address 101) with a fixed neighbour, its
 *                port 2 (102) with a programmable peer
 *   opt-present  optional, I/Q 4..7, ports 111 and 112 programmable
 *   opt-absent   optional, I/Q 8..11, not on the simulated network
 *
 * The refusals at the call, the refusals in the confirmation (a mandatory device named as
 * optional, a fixed port joined), a tailoring with opt-present and a port pair (opt-present
 * then exchanges data, opt-absent stays down), and DEACT. Prints
 * "tailoring: all checks held" at the end.
 */
#define _POSIX_C_SOURCE 200809L

#include "pniousrx.h"
#include "iobase_controller.h"
#include "procimg.h"
#include "check.h"

#include <pthread.h>
#include <stdio.h>
#include <string.h>

static atomic_int mode_seen = -1;
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static int reconfigs;
static PNIO_CBE_PRM_IOSYS_CONF last;
static PNIO_ADDR last_addr;

static void on_event(PNIO_CBE_PRM *p) {
    if (p->CbeType == PNIO_CBE_MODE_IND) atomic_store(&mode_seen, (int)p->ModeInd.Mode);
    if (p->CbeType == PNIO_CBE_IOSYSTEM_RECONFIG) {
        pthread_mutex_lock(&lock);
        last = p->IoSystemReconf;
        last_addr = *p->IoSystemReconf.pAddr;
        last.pAddr = NULL;
        reconfigs++;
        pthread_mutex_unlock(&lock);
    }
}

/* Waits for confirmation number n; returns it. */
static PNIO_CBE_PRM_IOSYS_CONF confirmation(int n, PNIO_ADDR *addr) {
    for (int i = 0; i < 1000; i++) {
        pthread_mutex_lock(&lock);
        int got = reconfigs;
        PNIO_CBE_PRM_IOSYS_CONF c = last;
        *addr = last_addr;
        pthread_mutex_unlock(&lock);
        if (got >= n) return c;
        sleep_ms(10);
    }
    fail(__LINE__, "no PNIO_CBE_IOSYSTEM_RECONFIG number %d", n);
    return last;
}

/* Waits until the 4 input bytes at `a` read with remote state `want` (GOOD) or fail with
 * PNIO_ERR_NO_CONNECTION (`want` BAD). */
static void wait_inputs(PNIO_UINT32 h, PNIO_UINT32 a, PNIO_IOXS want) {
    PNIO_ADDR in = logical(PNIO_IO_IN, a);
    for (int i = 0; i < 1500; i++) {
        PNIO_UINT8 data[4];
        PNIO_UINT32 len = 0;
        PNIO_IOXS rem = PNIO_S_BAD;
        PNIO_UINT32 rc = PNIO_data_read(h, &in, sizeof data, &len, data, PNIO_S_GOOD, &rem);
        if (want == PNIO_S_GOOD && rc == PNIO_OK && rem == PNIO_S_GOOD) return;
        if (want == PNIO_S_BAD && rc == PNIO_ERR_NO_CONNECTION) return;
        sleep_ms(10);
    }
    fail(__LINE__, "the inputs at I %u never became %s", (unsigned)a,
         want == PNIO_S_GOOD ? "GOOD" : "unconnected");
}

static int same(PNIO_ADDR a, PNIO_ADDR b) {
    return a.AddrType == b.AddrType && a.IODataType == b.IODataType && a.u.Addr == b.u.Addr;
}

int main(void) {
    check_part = "tailoring";
    PNIO_UINT32 h = 0;
    PNIO_ADDR addr;
    CHECK_RC(PNIO_controller_open(1, PNIO_CEP_MODE_CTRL, on_event, on_event, NULL, &h), PNIO_OK);
    CHECK_RC(PNIO_register_cbf(h, PNIO_CBE_MODE_IND, on_event), PNIO_OK);

    /* Refusals at the call. */
    CHECK_RC(PNIO_iosystem_reconfig(h, PNIO_IOS_RECONFIG_MODE_DEACT, 0, NULL, 0, NULL),
             PNIO_ERR_SEQUENCE); /* its callback is not registered */
    CHECK_RC(PNIO_register_cbf(h, PNIO_CBE_IOSYSTEM_RECONFIG, on_event), PNIO_OK);
    CHECK_RC(PNIO_iosystem_reconfig(h + 1000, PNIO_IOS_RECONFIG_MODE_DEACT, 0, NULL, 0, NULL),
             PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_iosystem_reconfig(h, (PNIO_IOS_RECONFIG_MODE)3, 0, NULL, 0, NULL),
             PNIO_ERR_MODE_VALUE);
    CHECK_RC(PNIO_iosystem_reconfig(h, PNIO_IOS_RECONFIG_MODE_TAILOR, 1, NULL, 0, NULL),
             PNIO_ERR_PRM_BUF);
    PNIO_ADDR nowhere = logical(PNIO_IO_IN, 999);
    CHECK_RC(PNIO_iosystem_reconfig(h, PNIO_IOS_RECONFIG_MODE_TAILOR, 1, &nowhere, 0, NULL),
             PNIO_ERR_PRM_ADD);

    CHECK_RC(PNIO_set_mode(h, PNIO_MODE_OPERATE), PNIO_OK);
    CHECK(wait_for_mode(&mode_seen, PNIO_MODE_OPERATE), "OPERATE never reported");
    wait_inputs(h, 0, PNIO_S_GOOD); /* the mandatory device */
    wait_inputs(h, 4, PNIO_S_BAD);  /* the optional ones wait */

    /* Refused in the confirmation, changing nothing. */
    PNIO_ADDR mandatory = logical(PNIO_IO_IN, 0);
    CHECK_RC(PNIO_iosystem_reconfig(h, PNIO_IOS_RECONFIG_MODE_TAILOR, 1, &mandatory, 0, NULL),
             PNIO_OK);
    PNIO_CBE_PRM_IOSYS_CONF c = confirmation(1, &addr);
    CHECK(c.Status == PNIO_ERR_INVALID_STATION && same(addr, mandatory),
          "a mandatory device named: Status 0x%x", (unsigned)c.Status);
    PNIO_ADDR fixed[2] = {logical(PNIO_IO_IN, 101), logical(PNIO_IO_IN, 111)};
    CHECK_RC(PNIO_iosystem_reconfig(h, PNIO_IOS_RECONFIG_MODE_TAILOR, 0, NULL, 1, fixed),
             PNIO_OK);
    c = confirmation(2, &addr);
    CHECK(c.Status == PNIO_ERR_INVALID_PORT && same(addr, fixed[0]),
          "a fixed port joined: Status 0x%x, address %u", (unsigned)c.Status,
          (unsigned)addr.u.Addr);

    /* The machine has opt-present, joined to the mandatory device's port 2. */
    PNIO_ADDR present = logical(PNIO_IO_OUT, 4); /* any address of the device */
    PNIO_ADDR joined[2] = {logical(PNIO_IO_IN, 102), logical(PNIO_IO_IN, 111)};
    CHECK_RC(PNIO_iosystem_reconfig(h, PNIO_IOS_RECONFIG_MODE_TAILOR, 1, &present, 1, joined),
             PNIO_OK);
    c = confirmation(3, &addr);
    CHECK(c.Status == PNIO_OK && c.Mode == PNIO_DA_TRUE && addr.u.Addr == 0 && addr.AddrType == 0,
          "the tailoring: Status 0x%x Mode %u", (unsigned)c.Status, (unsigned)c.Mode);
    wait_inputs(h, 0, PNIO_S_GOOD);
    wait_inputs(h, 4, PNIO_S_GOOD);
    wait_inputs(h, 8, PNIO_S_BAD);

    /* Every device down. */
    CHECK_RC(PNIO_iosystem_reconfig(h, PNIO_IOS_RECONFIG_MODE_DEACT, 0, NULL, 0, NULL), PNIO_OK);
    c = confirmation(4, &addr);
    CHECK(c.Status == PNIO_OK && c.Mode == PNIO_DA_FALSE, "DEACT: Status 0x%x Mode %u",
          (unsigned)c.Status, (unsigned)c.Mode);
    wait_inputs(h, 0, PNIO_S_BAD);
    wait_inputs(h, 4, PNIO_S_BAD);

    CHECK_RC(PNIO_set_mode(h, PNIO_MODE_OFFLINE), PNIO_OK);
    CHECK(wait_for_mode(&mode_seen, PNIO_MODE_OFFLINE), "OFFLINE never reported");
    CHECK_RC(PNIO_controller_close(h), PNIO_OK);
    printf("tailoring: all checks held\n");
    return 0;
}
