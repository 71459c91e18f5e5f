/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * A PN Driver program against procimg: the program starts its own stack, as PN Driver's
 * samples do, and needs no procimgd running beforehand.
 *
 *   1. SERV_CP_init with a trace callback (procimgd's log lines arrive in it),
 *   2. SERV_CP_get_network_adapters, and the adapter named on the command line (its
 *      interface name), else the first,
 *   3. SERV_CP_startup with the configuration file read into memory: procimg's own
 *      configuration (`procimgd --print-demo-config` prints the demo's, a simulated plant
 *      that needs no root); a procimgd now serves CP 1,
 *   4. PNIO_controller_open, PNIO_CBE_MODE_IND, OPERATE, then cyclic exchanges with the
 *      demo's echo device (outputs Q 0..15 come back as inputs I 0..15),
 *   5. OFFLINE, PNIO_controller_close,
 *   6. SERV_CP_shutdown (the stack ends) and SERV_CP_undo_init.
 *
 *   procimgd --print-demo-config > plant.toml
 *   cc -std=c11 pnd_easy.c -I clients/c/include -I shm-layout/include -lprocimg
 *   PROCIMGD=target/debug/procimgd ./a.out plant.toml [adapter] [exchanges]
 *
 * The stack is the procimgd PROCIMGD names, else procimgd on PATH; CP 1 is the instance in
 * $PROCIMG_CP1, else $PROCIMG_INSTANCE, else "procimg". Driving a real interface needs the
 * rights procimgd needs there (root, or CAP_NET_RAW and CAP_SYS_NICE). Exits 0 when every
 * step worked.
 */
#define _POSIX_C_SOURCE 200809L
#include "pniousrx.h"
#include "servusrx.h"
#include "procimg.h"
#include "pnio_example.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define ECHO_LEN 16

static atomic_int current_mode = PNIO_MODE_OFFLINE;
static atomic_long trace_bytes;

/* Callbacks run on threads of the library: only flags and the IO data functions here. */
static void on_mode(PNIO_CBE_PRM *p) { atomic_store(&current_mode, (int)p->ModeInd.Mode); }
static void on_record(PNIO_CBE_PRM *p) { (void)p; }

/* The stack's trace: procimgd's log lines, a buffer at a time. A real program would keep
 * them in a file for its support; this one prints them. */
static void on_trace(PNIO_UINT8 *buffer, PNIO_UINT32 size) {
    atomic_fetch_add(&trace_bytes, (long)size);
    fwrite(buffer, 1, size, stdout);
}

static int failed(const char *what, PNIO_UINT32 rc) {
    fprintf(stderr, "%s: 0x%x (%s)\n", what, (unsigned)rc, procimg_last_error());
    return 1;
}

static int wait_mode(int mode) {
    for (int i = 0; i < 1000 && atomic_load(&current_mode) != mode; i++) sleep_ms(10);
    return atomic_load(&current_mode) == mode;
}

static char config[1 << 16];

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: %s CONFIG [ADAPTER] [EXCHANGES]\n", argv[0]);
        return 2;
    }
    FILE *f = fopen(argv[1], "rb");
    if (f == NULL) {
        perror(argv[1]);
        return 1;
    }
    size_t config_len = fread(config, 1, sizeof config - 1, f);
    fclose(f);
    const char *wanted = argc > 2 && argv[2][0] != '\0' ? argv[2] : NULL;
    int exchanges = argc > 3 ? atoi(argv[3]) : 100;

    /* 1. */
    PNIO_DEBUG_SETTINGS_TYPE debug;
    memset(&debug, 0, sizeof debug);
    debug.CbfPntrcBufferFull = on_trace;
    memset(debug.TraceLevels, PNIO_TRACE_LEVEL_NOTE, sizeof debug.TraceLevels);
    PNIO_UINT32 rc = SERV_CP_init(&debug);
    if (rc != PNIO_OK) return failed("SERV_CP_init", rc);

    /* 2. */
    static PNIO_CP_ID_TYPE cps[PROCIMG_MAX_NETWORK_ADAPTERS];
    PNIO_UINT8 n = 0;
    rc = SERV_CP_get_network_adapters(cps, &n);
    if (rc != PNIO_OK) return failed("SERV_CP_get_network_adapters", rc);
    int chosen = 0;
    for (int i = 0; i < n; i++) {
        printf("adapter %d: %s\n", i, (const char *)cps[i].Description);
        if (wanted != NULL && strcmp((const char *)cps[i].Description, wanted) == 0) chosen = i;
    }

    /* 3. */
    rc = SERV_CP_startup(&cps[chosen], 1, (PNIO_UINT8 *)config, (PNIO_UINT32)config_len, NULL, 0,
                         NULL);
    if (rc != PNIO_OK) return failed("SERV_CP_startup", rc);
    printf("stack started on %s\n", (const char *)cps[chosen].Description);

    /* 4. */
    PNIO_UINT32 h = 0;
    rc = PNIO_controller_open(1, PNIO_CEP_MODE_CTRL, on_record, on_record, NULL, &h);
    if (rc != PNIO_OK) return failed("PNIO_controller_open", rc);
    rc = PNIO_register_cbf(h, PNIO_CBE_MODE_IND, on_mode);
    if (rc != PNIO_OK) return failed("PNIO_register_cbf", rc);
    rc = PNIO_set_mode(h, PNIO_MODE_OPERATE);
    if (rc != PNIO_OK || !wait_mode(PNIO_MODE_OPERATE)) return failed("OPERATE", rc);

    PNIO_ADDR out = logical(PNIO_IO_OUT, 0), in = logical(PNIO_IO_IN, 0);
    int echoed = 0;
    for (int i = 0; i < 2000 && echoed < exchanges; i++) {
        PNIO_UINT8 q[ECHO_LEN], x[ECHO_LEN];
        PNIO_IOXS rem = PNIO_S_BAD;
        PNIO_UINT32 len = 0;
        memset(q, 0x40 + i % 64, sizeof q); /* never 0: echo's inputs start at 0 */
        if (PNIO_data_write(h, &out, ECHO_LEN, q, PNIO_S_GOOD, &rem) == PNIO_OK &&
            PNIO_data_read(h, &in, ECHO_LEN, &len, x, PNIO_S_GOOD, &rem) == PNIO_OK &&
            rem == PNIO_S_GOOD && len == ECHO_LEN && x[0] >= 0x40) {
            echoed++;
        }
        sleep_ms(10);
    }
    printf("%d exchanges with the echo device\n", echoed);

    /* 5. */
    rc = PNIO_set_mode(h, PNIO_MODE_OFFLINE);
    if (rc != PNIO_OK || !wait_mode(PNIO_MODE_OFFLINE)) return failed("OFFLINE", rc);
    rc = PNIO_controller_close(h);
    if (rc != PNIO_OK) return failed("PNIO_controller_close", rc);

    /* 6. */
    rc = SERV_CP_shutdown();
    if (rc != PNIO_OK) return failed("SERV_CP_shutdown", rc);
    rc = SERV_CP_undo_init();
    if (rc != PNIO_OK) return failed("SERV_CP_undo_init", rc);
    printf("stack ended; %ld bytes of trace\n", atomic_load(&trace_bytes));
    return echoed >= exchanges ? 0 : 1;
}
