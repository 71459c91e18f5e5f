/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * PnioEasy, the IO-Base manual's first controller program, against procimgd:
 *
 *   1. PNIO_controller_open on CP 1 with PNIO_CEP_MODE_CTRL (the controller is OFFLINE),
 *   2. PNIO_register_cbf for PNIO_CBE_MODE_IND,
 *   3. PNIO_set_mode(PNIO_MODE_OPERATE) and wait for the second MODE_IND (CLEAR, then
 *      OPERATE),
 *   4. cyclic PNIO_data_write / PNIO_data_read of the demo's echo device (outputs Q 0..15
 *      come back as inputs I 0..15) until the inputs echo the outputs with remote status
 *      GOOD, then as many more exchanges as asked for,
 *   5. PNIO_set_mode(PNIO_MODE_OFFLINE), wait for MODE_IND OFFLINE,
 *   6. PNIO_controller_close.
 *
 *   cc -std=c11 pnio_easy.c -I clients/c/include -I shm-layout/include -lprocimg
 *   procimgd --demo &
 *   ./a.out [exchanges]
 *
 * CP 1 is the instance in $PROCIMG_CP1, else $PROCIMG_INSTANCE, else "procimg". Exits 0
 * when every step worked.
 *
 * The server's mode. A procimgd is shared, and in OFFLINE the programs that use it after
 * this one (native_cycle, `procimg io`) see no data exchanged. Step 1 takes the server to
 * OFFLINE and the manual's flow ends there; the IO-Base API can neither tell the mode before
 * open nor change it after close. So, outside the manual's flow, the program reads the
 * server's mode before step 1 and gives it back after step 6, through procimg.h: see
 * server_mode.h, next to this file.
 */
#define _POSIX_C_SOURCE 200809L
#include "pniousrx.h"
#include "procimg.h"
#include "server_mode.h"
#include "pnio_example.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define CP_INDEX 1
#define ECHO_LEN 16

static atomic_int mode_reports; /* MODE_IND calls so far */
static atomic_int current_mode = PNIO_MODE_OFFLINE;

/* Callbacks run on threads of the library: only flags and the IO data functions here. */
static void on_mode(PNIO_CBE_PRM *p) {
    atomic_store(&current_mode, (int)p->ModeInd.Mode);
    atomic_fetch_add(&mode_reports, 1);
}

static void on_record_read(PNIO_CBE_PRM *p) {
    printf("record read confirmed: index 0x%x, %u bytes\n", p->RecReadConf.RecordIndex,
           p->RecReadConf.Length);
}

static void on_record_write(PNIO_CBE_PRM *p) {
    printf("record write confirmed: index 0x%x\n", p->RecWriteConf.RecordIndex);
}

static void on_alarm(PNIO_CBE_PRM *p) {
    printf("alarm 0x%x from slot %u\n", (unsigned)p->AlarmInd.pAlarmData->AlarmType,
           (unsigned)p->AlarmInd.pAlarmData->SlotNum);
}

/* Waits (up to 10 s) until MODE_IND has been called `reports` times in all. */
static int wait_mode_reports(int reports) {
    int i;
    for (i = 0; i < 1000 && atomic_load(&mode_reports) < reports; i++) {
        sleep_ms(10);
    }
    return atomic_load(&mode_reports) >= reports;
}

/* A failed call: its code, and the library's text for this thread, which names the code
 * (PNIO_ERR_...) and says what to do (procimg_last_error() serves both APIs). */
static int failed(const char *what, PNIO_UINT32 code) {
    fprintf(stderr, "pnio_easy: %s failed with 0x%03x\n  %s\n", what, code,
            procimg_last_error());
    return 1;
}

/* ---- The manual's flow ------------------------------------------------------------------ */

static int pnio_easy(long exchanges) {
    PNIO_UINT32 h = 0, r;
    PNIO_ADDR out, in;
    PNIO_UINT8 q[ECHO_LEN], i_data[ECHO_LEN];
    PNIO_UINT32 len;
    PNIO_IOXS out_remote, in_remote;
    long n, round, echoed = 0, good = 0;
    int k, rc = 0;

    memset(&out, 0, sizeof out);
    out.AddrType = PNIO_ADDR_LOG;
    out.IODataType = PNIO_IO_OUT;
    out.u.Addr = 0;
    in = out;
    in.IODataType = PNIO_IO_IN;

    /* 1. Register as IO controller. */
    r = PNIO_controller_open(CP_INDEX, PNIO_CEP_MODE_CTRL, on_record_read, on_record_write,
                             on_alarm, &h);
    if (r != PNIO_OK) {
        return failed("PNIO_controller_open", r);
    }
    printf("controller open, handle %u, mode OFFLINE\n", h);

    /* 2. The mode callback (in OFFLINE). */
    r = PNIO_register_cbf(h, PNIO_CBE_MODE_IND, on_mode);
    if (r != PNIO_OK) {
        rc = failed("PNIO_register_cbf(MODE_IND)", r);
        PNIO_controller_close(h);
        return rc;
    }

    /* 3. OPERATE; OFFLINE -> OPERATE is reported twice: CLEAR, then OPERATE. */
    r = PNIO_set_mode(h, PNIO_MODE_OPERATE);
    if (r != PNIO_OK) {
        rc = failed("PNIO_set_mode(OPERATE)", r);
        PNIO_controller_close(h);
        return rc;
    }
    if (!wait_mode_reports(2) || atomic_load(&current_mode) != PNIO_MODE_OPERATE) {
        fprintf(stderr, "pnio_easy: OPERATE was not reported (mode %d)\n",
                atomic_load(&current_mode));
        PNIO_controller_close(h);
        return 1;
    }
    printf("mode OPERATE\n");

    /* 4. Cyclic IO: write Q 0..15, read I 0..15 (the echo device sends them back). */
    for (n = 0, round = 0; round < 2000 && good < exchanges; round++) {
        for (k = 0; k < ECHO_LEN; k++) {
            q[k] = (PNIO_UINT8)(round + k);
        }
        r = PNIO_data_write(h, &out, ECHO_LEN, q, PNIO_S_GOOD, &out_remote);
        if (r != PNIO_OK && r != PNIO_ERR_NO_CONNECTION) {
            rc = failed("PNIO_data_write", r);
            break;
        }
        sleep_ms(5); /* a few cycles: the device echoes one cycle later */
        r = PNIO_data_read(h, &in, ECHO_LEN, &len, i_data, PNIO_S_GOOD, &in_remote);
        if (r == PNIO_ERR_NO_CONNECTION) {
            continue; /* the device is still connecting after OPERATE */
        }
        if (r != PNIO_OK) {
            rc = failed("PNIO_data_read", r);
            break;
        }
        n++;
        if (len == ECHO_LEN && in_remote == PNIO_S_GOOD && memcmp(q, i_data, ECHO_LEN) == 0) {
            if (echoed == 0) {
                printf("inputs echo the outputs after %ld rounds (remote status GOOD)\n", round);
            }
            echoed = 1;
        }
        if (echoed) {
            good += in_remote == PNIO_S_GOOD && out_remote == PNIO_S_GOOD;
        }
    }
    printf("%ld reads, %ld good exchanges after the first echo\n", n, good);
    if (rc == 0 && (!echoed || good < exchanges)) {
        fprintf(stderr, "pnio_easy: the inputs did not echo the outputs\n");
        rc = 1;
    }

    /* 5. OFFLINE: CLEAR, then OFFLINE. */
    {
        int before = atomic_load(&mode_reports);
        r = PNIO_set_mode(h, PNIO_MODE_OFFLINE);
        if (r != PNIO_OK) {
            rc = failed("PNIO_set_mode(OFFLINE)", r);
        } else if (!wait_mode_reports(before + 2) ||
                   atomic_load(&current_mode) != PNIO_MODE_OFFLINE) {
            fprintf(stderr, "pnio_easy: OFFLINE was not reported\n");
            rc = 1;
        } else {
            printf("mode OFFLINE\n");
        }
    }

    /* 6. Deregister. */
    r = PNIO_controller_close(h);
    if (r != PNIO_OK) {
        rc = failed("PNIO_controller_close", r);
    }
    printf("controller closed\n");
    return rc;
}

int main(int argc, char **argv) {
    long exchanges = argc > 1 ? strtol(argv[1], NULL, 10) : 100;
    const char *instance = cp_instance();
    uint32_t before = 0;
    int known, rc;

    if (exchanges <= 0) {
        fprintf(stderr, "usage: %s [exchanges]\n", argv[0]);
        return 2;
    }
    /* Without a server this finds nothing, and PNIO_controller_open says what to do. */
    known = server_mode("pnio_easy", instance, &before);
    rc = pnio_easy(exchanges);
    if (known && !restore_mode("pnio_easy", instance, before)) {
        rc = 1;
    }
    return rc;
}
