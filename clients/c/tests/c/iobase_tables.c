/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * The manual's PNIO_data_read and PNIO_data_write example tables through the C API, on a
 * server laid out as in the manual (inputs 2 bytes at I 0..1 and 4 bytes at I 2..5; outputs
 * 2 bytes at Q 0..1, 4 bytes at Q 2..5 and 4 bytes at Q 10..13).
 *
 *   iobase_tables slice   PNIO_CEP_SLICE_ACCESS: both tables exactly as printed
 *   iobase_tables exact   without it: only whole submodules at their first address
 *
 * Prints every row; exits 0 when all rows give what the manual says.
 */
#define _POSIX_C_SOURCE 200809L
#include "pniousrx.h"
#include "iobase_controller.h"

#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static atomic_int mode_seen = -1;
static int failures;

static void on_mode(PNIO_CBE_PRM *p) {
    atomic_store(&mode_seen, (int)p->ModeInd.Mode);
}

static void on_record(PNIO_CBE_PRM *p) {
    (void)p;
}

static const char *code_name(PNIO_UINT32 c) {
    switch (c) {
    case PNIO_OK: return "PNIO_OK";
    case PNIO_ERR_VALUE_LEN: return "PNIO_ERR_VALUE_LEN";
    case PNIO_ERR_UNKNOWN_ADDR: return "PNIO_ERR_UNKNOWN_ADDR";
    case PNIO_ERR_NO_CONNECTION: return "PNIO_ERR_NO_CONNECTION";
    default: return "another code";
    }
}

/* (I address, BufLen, expected return, expected *pDataLen) */
static void read_row(PNIO_UINT32 h, PNIO_UINT32 a, PNIO_UINT32 len, PNIO_UINT32 want,
                     PNIO_UINT32 want_len) {
    PNIO_ADDR x = logical(PNIO_IO_IN, a);
    PNIO_UINT8 buf[16];
    PNIO_UINT32 data_len = 0xdead;
    PNIO_IOXS rem = PNIO_S_BAD;
    PNIO_UINT32 r = PNIO_data_read(h, &x, len, &data_len, buf, PNIO_S_GOOD, &rem);
    int ok = r == want && (r != PNIO_OK || data_len == want_len);
    printf("read  I %2u BufLen %u -> %s (0x%03x), *pDataLen %u   %s\n", a, len, code_name(r), r,
           r == PNIO_OK ? data_len : 0, ok ? "ok" : "WRONG");
    if (!ok) {
        printf("      expected %s, *pDataLen %u\n", code_name(want), want_len);
        failures++;
    }
}

/* (Q address, BufLen, expected return) */
static void write_row(PNIO_UINT32 h, PNIO_UINT32 a, PNIO_UINT32 len, PNIO_UINT32 want) {
    PNIO_ADDR x = logical(PNIO_IO_OUT, a);
    PNIO_UINT8 buf[16];
    PNIO_IOXS rem = PNIO_S_BAD;
    PNIO_UINT32 r;
    memset(buf, 0x11, sizeof buf);
    r = PNIO_data_write(h, &x, len, buf, PNIO_S_GOOD, &rem);
    printf("write Q %2u BufLen %u -> %s (0x%03x)   %s\n", a, len, code_name(r), r,
           r == want ? "ok" : "WRONG");
    if (r != want) {
        printf("      expected %s\n", code_name(want));
        failures++;
    }
}

int main(int argc, char **argv) {
    int slice = argc > 1 && strcmp(argv[1], "slice") == 0;
    PNIO_UINT32 h = 0, r;
    int i;
    PNIO_UINT32 ext = PNIO_CEP_MODE_CTRL | (slice ? PNIO_CEP_SLICE_ACCESS : 0);

    r = PNIO_controller_open(1, ext, on_record, on_record, NULL, &h);
    if (r != PNIO_OK) {
        printf("PNIO_controller_open: 0x%x\n", r);
        return 2;
    }
    printf("controller %u open, %s slice access\n", h, slice ? "with" : "without");
    if (PNIO_register_cbf(h, PNIO_CBE_MODE_IND, on_mode) != PNIO_OK ||
        PNIO_set_mode(h, PNIO_MODE_OPERATE) != PNIO_OK || !wait_for_mode(&mode_seen, PNIO_MODE_OPERATE)) {
        printf("OPERATE not reached\n");
        return 2;
    }
    /* The device connects after OPERATE: wait until its inputs are exchanged. */
    for (i = 0; i < 1000; i++) {
        PNIO_ADDR x = logical(PNIO_IO_IN, 0);
        PNIO_UINT8 b[2];
        PNIO_UINT32 n;
        PNIO_IOXS rem;
        if (PNIO_data_read(h, &x, 2, &n, b, PNIO_S_GOOD, &rem) == PNIO_OK) {
            break;
        }
        sleep_ms(10);
    }
    printf("device in data exchange after %d ms\n", i * 10);

    if (slice) {
        /* The manual's PNIO_data_read table: every row PNIO_OK. */
        read_row(h, 2, 8, PNIO_OK, 4);
        read_row(h, 2, 2, PNIO_OK, 4);
        read_row(h, 3, 2, PNIO_OK, 3);
        read_row(h, 5, 1, PNIO_OK, 1);
        read_row(h, 5, 8, PNIO_OK, 1);
        read_row(h, 1, 2, PNIO_OK, 1);
        read_row(h, 1, 1, PNIO_OK, 1);
        read_row(h, 6, 1, PNIO_ERR_UNKNOWN_ADDR, 0);
        /* The manual's PNIO_data_write table. */
        write_row(h, 2, 8, PNIO_ERR_VALUE_LEN);
        write_row(h, 2, 2, PNIO_OK);
        write_row(h, 1, 2, PNIO_ERR_VALUE_LEN);
        write_row(h, 1, 1, PNIO_OK);
        write_row(h, 3, 3, PNIO_OK);
        write_row(h, 3, 1, PNIO_OK);
        write_row(h, 3, 4, PNIO_ERR_VALUE_LEN);
        write_row(h, 6, 4, PNIO_ERR_UNKNOWN_ADDR);
        write_row(h, 10, 1, PNIO_OK);
        write_row(h, 11, 1, PNIO_OK);
        write_row(h, 9, 1, PNIO_ERR_UNKNOWN_ADDR);
        /* The ExtPar example: 2 bytes from Q 3 land in bytes 3..4 of the module at Q 2. */
        {
            PNIO_ADDR q2 = logical(PNIO_IO_OUT, 2), q3 = logical(PNIO_IO_OUT, 3);
            PNIO_UINT8 whole[4] = {1, 2, 3, 4}, part[2] = {0xaa, 0xbb}, back[4];
            PNIO_UINT32 n = 0;
            PNIO_IOXS loc, rem;
            int seen = 0;
            PNIO_data_write(h, &q2, 4, whole, PNIO_S_GOOD, &rem);
            PNIO_data_write(h, &q3, 2, part, PNIO_S_GOOD, &rem);
            for (i = 0; i < 200 && !seen; i++) {
                r = PNIO_output_data_read(h, &q2, 4, &n, back, &loc, &rem);
                seen = r == PNIO_OK && n == 4 && back[0] == 1 && back[1] == 0xaa &&
                       back[2] == 0xbb && back[3] == 4;
                if (!seen) {
                    sleep_ms(5);
                }
            }
            printf("Q 2..5 after writing 2 bytes at Q 3: %02x %02x %02x %02x   %s\n", back[0],
                   back[1], back[2], back[3], seen ? "ok" : "WRONG");
            failures += !seen;
        }
    } else {
        /* Without slice access: the first address only, whole submodules for writes. */
        read_row(h, 2, 4, PNIO_OK, 4);
        read_row(h, 2, 8, PNIO_OK, 4);
        read_row(h, 2, 2, PNIO_OK, 4); /* the pDataLen rule: 2 copied, 4 needed */
        read_row(h, 0, 2, PNIO_OK, 2);
        read_row(h, 3, 2, PNIO_ERR_UNKNOWN_ADDR, 0);
        read_row(h, 5, 1, PNIO_ERR_UNKNOWN_ADDR, 0);
        write_row(h, 2, 4, PNIO_OK);
        write_row(h, 0, 2, PNIO_OK);
        write_row(h, 10, 4, PNIO_OK);
        write_row(h, 2, 2, PNIO_ERR_VALUE_LEN);
        write_row(h, 2, 8, PNIO_ERR_VALUE_LEN);
        write_row(h, 3, 3, PNIO_ERR_VALUE_LEN);
        write_row(h, 11, 1, PNIO_ERR_VALUE_LEN);
        write_row(h, 6, 4, PNIO_ERR_UNKNOWN_ADDR);
        write_row(h, 9, 1, PNIO_ERR_UNKNOWN_ADDR);
    }

    if (PNIO_set_mode(h, PNIO_MODE_OFFLINE) != PNIO_OK || !wait_for_mode(&mode_seen, PNIO_MODE_OFFLINE)) {
        printf("OFFLINE not reached\n");
        failures++;
    }
    r = PNIO_controller_close(h);
    if (r != PNIO_OK) {
        printf("PNIO_controller_close: 0x%x\n", r);
        failures++;
    }
    printf("%d rows wrong\n", failures);
    return failures != 0;
}
