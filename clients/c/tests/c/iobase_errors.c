/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * The error paths of the IO-Base controller API against procimgd --demo: every NULL
 * pointer, wrong and closed handles, wrong lengths, IODataType and AddrType, bad
 * IOlocState, the registration rules, set_mode's sequence, calls that are not allowed
 * inside a callback. Prints each check; exits 0 when all give the expected code.
 */
#define _POSIX_C_SOURCE 200809L
#include "pniousrx.h"
#include "iobase_controller.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int failures;
static atomic_int mode_seen = -1;
static atomic_int mode_calls;
/* Holds the first MODE_IND (CLEAR) until the test has asked for a second mode: the library
 * reports OPERATE only after it returns, so the change is still pending then, however the
 * threads are scheduled. */
static atomic_int second_request_made;
static PNIO_UINT32 handle;
/* What the calls made inside the MODE_IND callback returned (first callback only). */
static atomic_uint in_cb_set_mode = 0xffffffffu;
static atomic_uint in_cb_close = 0xffffffffu;
static atomic_uint in_cb_register = 0xffffffffu;
static atomic_uint in_cb_read = 0xffffffffu;
static atomic_uint in_cb_write = 0xffffffffu;

static void expect(const char *what, PNIO_UINT32 got, PNIO_UINT32 want) {
    printf("%-58s 0x%03x %s\n", what, got, got == want ? "ok" : "WRONG");
    if (got != want) {
        printf("    expected 0x%03x\n", want);
        failures++;
    }
}

static void on_record(PNIO_CBE_PRM *p) {
    (void)p;
}

static void on_startop(PNIO_CP_CBE_PRM *p) {
    (void)p;
}

static void on_mode(PNIO_CBE_PRM *p) {
    if (atomic_fetch_add(&mode_calls, 1) == 0) {
        /* Inside a callback: the IO data functions are allowed, the others are not. */
        PNIO_ADDR i0 = logical(PNIO_IO_IN, 0), q0 = logical(PNIO_IO_OUT, 0);
        PNIO_UINT8 buf[16] = {0};
        PNIO_UINT32 n;
        PNIO_IOXS rem;
        atomic_store(&in_cb_set_mode, PNIO_set_mode(handle, PNIO_MODE_OFFLINE));
        atomic_store(&in_cb_close, PNIO_controller_close(handle));
        atomic_store(&in_cb_register, PNIO_register_cbf(handle, PNIO_CBE_DEV_ACT_CONF, on_record));
        atomic_store(&in_cb_read, PNIO_data_read(handle, &i0, 16, &n, buf, PNIO_S_GOOD, &rem));
        atomic_store(&in_cb_write, PNIO_data_write(handle, &q0, 16, buf, PNIO_S_GOOD, &rem));
        for (int i = 0; i < 10000 && !atomic_load(&second_request_made); i++) {
            sleep_ms(1);
        }
    }
    atomic_store(&mode_seen, (int)p->ModeInd.Mode);
}

static void data_errors(PNIO_UINT32 h) {
    PNIO_ADDR i0 = logical(PNIO_IO_IN, 0), q0 = logical(PNIO_IO_OUT, 0);
    PNIO_ADDR geo = logical(PNIO_IO_IN, 0), gap = logical(PNIO_IO_IN, 200), qgap = logical(PNIO_IO_OUT, 200);
    PNIO_UINT8 buf[32] = {0};
    PNIO_UINT32 n;
    PNIO_IOXS rem, loc;
    geo.AddrType = PNIO_ADDR_GEO;

    expect("data_read: wrong handle", PNIO_data_read(h + 1000, &i0, 16, &n, buf, PNIO_S_GOOD, &rem),
           PNIO_ERR_WRONG_HND);
    expect("data_read: pBuffer NULL", PNIO_data_read(h, &i0, 16, &n, NULL, PNIO_S_GOOD, &rem),
           PNIO_ERR_PRM_BUF);
    expect("data_read: BufLen 0", PNIO_data_read(h, &i0, 0, &n, buf, PNIO_S_GOOD, &rem),
           PNIO_ERR_PRM_BUF);
    expect("data_read: pAddr NULL", PNIO_data_read(h, NULL, 16, &n, buf, PNIO_S_GOOD, &rem),
           PNIO_ERR_PRM_ADD);
    expect("data_read: IODataType OUT", PNIO_data_read(h, &q0, 16, &n, buf, PNIO_S_GOOD, &rem),
           PNIO_ERR_PRM_IO_TYPE);
    expect("data_read: AddrType GEO", PNIO_data_read(h, &geo, 16, &n, buf, PNIO_S_GOOD, &rem),
           PNIO_ERR_PRM_ADD);
    expect("data_read: IOlocState 5",
           PNIO_data_read(h, &i0, 16, &n, buf, (PNIO_IOXS)5, &rem), PNIO_ERR_PRM_LOC_STATE);
    expect("data_read: pDataLen NULL", PNIO_data_read(h, &i0, 16, NULL, buf, PNIO_S_GOOD, &rem),
           PNIO_ERR_PRM_LEN);
    expect("data_read: pIOremState NULL",
           PNIO_data_read(h, &i0, 16, &n, buf, PNIO_S_GOOD, NULL), PNIO_ERR_PRM_RSTATE);
    expect("data_read: I 200 (no submodule)",
           PNIO_data_read(h, &gap, 16, &n, buf, PNIO_S_GOOD, &rem), PNIO_ERR_UNKNOWN_ADDR);
    expect("data_read: I 0 BufLen 32 (pDataLen rule)",
           PNIO_data_read(h, &i0, 32, &n, buf, PNIO_S_GOOD, &rem), PNIO_OK);
    expect("data_read: ... *pDataLen is 16", n, 16);

    expect("output_data_read: pIOlocState NULL",
           PNIO_output_data_read(h, &q0, 16, &n, buf, NULL, &rem), PNIO_ERR_PRM_LOC_STATE);
    expect("output_data_read: IODataType IN",
           PNIO_output_data_read(h, &i0, 16, &n, buf, &loc, &rem), PNIO_ERR_PRM_IO_TYPE);
    expect("output_data_read: pDataLen NULL",
           PNIO_output_data_read(h, &q0, 16, NULL, buf, &loc, &rem), PNIO_ERR_PRM_LEN);
    expect("output_data_read: Q 0", PNIO_output_data_read(h, &q0, 16, &n, buf, &loc, &rem),
           PNIO_OK);

    expect("data_write: wrong handle", PNIO_data_write(h + 1000, &q0, 16, buf, PNIO_S_GOOD, &rem),
           PNIO_ERR_WRONG_HND);
    expect("data_write: pBuffer NULL", PNIO_data_write(h, &q0, 16, NULL, PNIO_S_GOOD, &rem),
           PNIO_ERR_PRM_BUF);
    expect("data_write: pAddr NULL", PNIO_data_write(h, NULL, 16, buf, PNIO_S_GOOD, &rem),
           PNIO_ERR_PRM_ADD);
    expect("data_write: IODataType IN", PNIO_data_write(h, &i0, 16, buf, PNIO_S_GOOD, &rem),
           PNIO_ERR_PRM_IO_TYPE);
    expect("data_write: IOlocState 7", PNIO_data_write(h, &q0, 16, buf, (PNIO_IOXS)7, &rem),
           PNIO_ERR_PRM_LOC_STATE);
    expect("data_write: pIOremState NULL", PNIO_data_write(h, &q0, 16, buf, PNIO_S_GOOD, NULL),
           PNIO_ERR_PRM_RSTATE);
    expect("data_write: Q 200 (no submodule)",
           PNIO_data_write(h, &qgap, 1, buf, PNIO_S_GOOD, &rem), PNIO_ERR_UNKNOWN_ADDR);
    expect("data_write: Q 0 BufLen 17", PNIO_data_write(h, &q0, 17, buf, PNIO_S_GOOD, &rem),
           PNIO_ERR_VALUE_LEN);
    expect("data_write: Q 0 BufLen 16", PNIO_data_write(h, &q0, 16, buf, PNIO_S_GOOD, &rem),
           PNIO_OK);

    expect("data_read_cache_refresh: wrong handle", PNIO_data_read_cache_refresh(h + 1000),
           PNIO_ERR_WRONG_HND);
    expect("data_read_cache_refresh", PNIO_data_read_cache_refresh(h), PNIO_OK);
    expect("data_read_cache: pDataLen NULL",
           PNIO_data_read_cache(h, &i0, 16, NULL, buf, PNIO_S_GOOD, &rem), PNIO_ERR_PRM_LEN);
    expect("data_read_cache: I 0", PNIO_data_read_cache(h, &i0, 16, &n, buf, PNIO_S_GOOD, &rem),
           PNIO_OK);
    expect("data_write_cache: Q 0 BufLen 15 (no slice access)",
           PNIO_data_write_cache(h, &q0, 15, buf, PNIO_S_GOOD, &rem), PNIO_ERR_VALUE_LEN);
    expect("data_write_cache: Q 0", PNIO_data_write_cache(h, &q0, 16, buf, PNIO_S_GOOD, &rem),
           PNIO_OK);
    expect("data_write_cache_flush: wrong handle", PNIO_data_write_cache_flush(h + 1000),
           PNIO_ERR_WRONG_HND);
    expect("data_write_cache_flush", PNIO_data_write_cache_flush(h), PNIO_OK);
}

int main(void) {
    PNIO_UINT32 h = 0, h2 = 0;
    PNIO_ADDR q0 = logical(PNIO_IO_OUT, 0), i0 = logical(PNIO_IO_IN, 0);
    PNIO_CTRL_DIAG diag;
    PNIO_UINT8 rec[4] = {0};
    int i;
    memset(&diag, 0, sizeof diag);

    /* Opening. */
    expect("open: Handle NULL",
           PNIO_controller_open(1, PNIO_CEP_MODE_CTRL, on_record, on_record, NULL, NULL),
           PNIO_ERR_PRM_HND);
    expect("open: CpIndex 0", PNIO_controller_open(0, PNIO_CEP_MODE_CTRL, on_record, on_record, NULL, &h),
           PNIO_ERR_PRM_CP_ID);
    expect("open: CpIndex 256",
           PNIO_controller_open(256, PNIO_CEP_MODE_CTRL, on_record, on_record, NULL, &h),
           PNIO_ERR_PRM_CP_ID);
    expect("open: ExtPar with a device flag",
           PNIO_controller_open(1, PNIO_CEP_MODE_CTRL | PNIO_CEP_DEV_MAXAR_BY_TYPE, on_record,
                                on_record, NULL, &h),
           PNIO_ERR_PRM_EXT_PAR);
    expect("open: read callback NULL",
           PNIO_controller_open(1, PNIO_CEP_MODE_CTRL, NULL, on_record, NULL, &h),
           PNIO_ERR_PRM_CALLBACK);
    expect("open: write callback NULL",
           PNIO_controller_open(1, PNIO_CEP_MODE_CTRL, on_record, NULL, NULL, &h),
           PNIO_ERR_PRM_CALLBACK);
    setenv("PROCIMG_CP7", "no-such-procimg-instance", 1);
    expect("open: CpIndex 7 names no server",
           PNIO_controller_open(7, PNIO_CEP_MODE_CTRL, on_record, on_record, NULL, &h),
           PNIO_ERR_NO_CONFIG);
    expect("open: CpIndex 1, MODE_CTRL",
           PNIO_controller_open(1, PNIO_CEP_MODE_CTRL, on_record, on_record, NULL, &h), PNIO_OK);
    handle = h;
    expect("open: a second controller (the outputs are owned)",
           PNIO_controller_open(1, 0, on_record, on_record, NULL, &h2), PNIO_ERR_MAX_REACHED);

    /* Registration in OFFLINE. */
    expect("register_cbf: wrong handle", PNIO_register_cbf(h + 1000, PNIO_CBE_MODE_IND, on_mode),
           PNIO_ERR_WRONG_HND);
    expect("register_cbf: NULL", PNIO_register_cbf(h, PNIO_CBE_MODE_IND, NULL), PNIO_ERR_PRM_CALLBACK);
    expect("register_cbf: ALARM_IND (open's)", PNIO_register_cbf(h, PNIO_CBE_ALARM_IND, on_mode),
           PNIO_ERR_PRM_TYPE);
    expect("register_cbf: REC_READ_CONF (open's)",
           PNIO_register_cbf(h, PNIO_CBE_REC_READ_CONF, on_mode), PNIO_ERR_PRM_TYPE);
    expect("register_cbf: type 99", PNIO_register_cbf(h, (PNIO_CBE_TYPE)99, on_mode),
           PNIO_ERR_PRM_TYPE);
    expect("set_mode: before MODE_IND is registered", PNIO_set_mode(h, PNIO_MODE_OPERATE),
           PNIO_ERR_SEQUENCE);
    expect("register_cbf: MODE_IND", PNIO_register_cbf(h, PNIO_CBE_MODE_IND, on_mode), PNIO_OK);
    expect("register_cbf: MODE_IND again", PNIO_register_cbf(h, PNIO_CBE_MODE_IND, on_mode),
           PNIO_ERR_ALLREADY_DONE);
    expect("CP_register_cbf: STARTOP before OPFAULT",
           PNIO_CP_register_cbf(h, PNIO_CP_CBE_STARTOP_IND, on_startop), PNIO_ERR_OPFAULT_NOT_REG);
    expect("CP_register_cbf: NULL", PNIO_CP_register_cbf(h, PNIO_CP_CBE_OPFAULT_IND, NULL),
           PNIO_ERR_PRM_CALLBACK);
    expect("CP_register_cbf: type 9", PNIO_CP_register_cbf(h, (PNIO_CP_CBE_TYPE)9, on_startop),
           PNIO_ERR_PRM_TYPE);
    expect("CP_set_opdone: STARTOP not registered", PNIO_CP_set_opdone(h, NULL),
           PNIO_ERR_STARTOP_NOT_REGISTERED);
    expect("device_activate: in OFFLINE", PNIO_device_activate(h, &q0, PNIO_DA_TRUE),
           PNIO_ERR_MODE_VALUE);

    /* Modes. */
    expect("set_mode: wrong handle", PNIO_set_mode(h + 1000, PNIO_MODE_OPERATE), PNIO_ERR_WRONG_HND);
    expect("set_mode: mode 7", PNIO_set_mode(h, (PNIO_MODE_TYPE)7), PNIO_ERR_MODE_VALUE);
    expect("set_mode: OPERATE", PNIO_set_mode(h, PNIO_MODE_OPERATE), PNIO_OK);
    expect("set_mode: OFFLINE before OPERATE was reported", PNIO_set_mode(h, PNIO_MODE_OFFLINE),
           PNIO_ERR_SEQUENCE);
    atomic_store(&second_request_made, 1);
    expect("OPERATE reported", (PNIO_UINT32)wait_for_mode(&mode_seen, PNIO_MODE_OPERATE), 1);
    expect("MODE_IND twice for OFFLINE -> OPERATE (CLEAR, OPERATE)",
           (PNIO_UINT32)atomic_load(&mode_calls), 2);
    expect("inside a callback: set_mode", atomic_load(&in_cb_set_mode), PNIO_ERR_SEQUENCE);
    expect("inside a callback: controller_close", atomic_load(&in_cb_close), PNIO_ERR_SEQUENCE);
    expect("inside a callback: register_cbf", atomic_load(&in_cb_register), PNIO_ERR_SEQUENCE);
    /* In CLEAR the device may not be connected yet: allowed means not SEQUENCE. */
    printf("inside a callback: data_read 0x%03x, data_write 0x%03x (allowed)\n",
           atomic_load(&in_cb_read), atomic_load(&in_cb_write));
    if (atomic_load(&in_cb_read) == PNIO_ERR_SEQUENCE || atomic_load(&in_cb_write) == PNIO_ERR_SEQUENCE) {
        printf("    WRONG: the IO data functions are allowed in callbacks\n");
        failures++;
    }
    expect("register_cbf: in OPERATE", PNIO_register_cbf(h, PNIO_CBE_DEV_ACT_CONF, on_record),
           PNIO_ERR_MODE_VALUE);
    expect("CP_register_cbf: in OPERATE",
           PNIO_CP_register_cbf(h, PNIO_CP_CBE_OPFAULT_IND, on_startop), PNIO_ERR_MODE_VALUE);

    /* The echo device connects after OPERATE. */
    for (i = 0; i < 1000; i++) {
        PNIO_UINT8 b[16];
        PNIO_UINT32 n;
        PNIO_IOXS rem;
        if (PNIO_data_read(h, &i0, 16, &n, b, PNIO_S_GOOD, &rem) == PNIO_OK) {
            break;
        }
        sleep_ms(10);
    }
    data_errors(h);

    /* The services' parameter checks. */
    expect("device_activate: pAddr NULL", PNIO_device_activate(h, NULL, PNIO_DA_TRUE),
           PNIO_ERR_PRM_ADD);
    expect("device_activate: DeviceMode 5", PNIO_device_activate(h, &q0, (PNIO_DEV_ACT_TYPE)5),
           PNIO_ERR_PRM_DEV_STATE);
    expect("device_activate: wrong handle", PNIO_device_activate(h + 1000, &q0, PNIO_DA_TRUE),
           PNIO_ERR_WRONG_HND);
    expect("rec_read_req: pAddr NULL", PNIO_rec_read_req(h, NULL, 1, 1, 16), PNIO_ERR_PRM_ADD);
    expect("rec_read_req: wrong handle", PNIO_rec_read_req(h + 1000, &q0, 1, 1, 16),
           PNIO_ERR_WRONG_HND);
    expect("rec_write_req: pBuffer NULL", PNIO_rec_write_req(h, &q0, 1, 1, 4, NULL),
           PNIO_ERR_PRM_BUF);
    expect("rec_write_req: pAddr NULL", PNIO_rec_write_req(h, NULL, 1, 1, 4, rec),
           PNIO_ERR_PRM_ADD);
    expect("ctrl_diag_req: pDiagReq NULL", PNIO_ctrl_diag_req(h, NULL), PNIO_ERR_PRM_POINTER);
    expect("ctrl_diag_req: wrong handle", PNIO_ctrl_diag_req(h + 1000, &diag), PNIO_ERR_WRONG_HND);

    /* Back to OFFLINE, close. */
    expect("set_mode: OFFLINE", PNIO_set_mode(h, PNIO_MODE_OFFLINE), PNIO_OK);
    expect("OFFLINE reported", (PNIO_UINT32)wait_for_mode(&mode_seen, PNIO_MODE_OFFLINE), 1);
    expect("set_mode: OFFLINE again (reported at once)", PNIO_set_mode(h, PNIO_MODE_OFFLINE), PNIO_OK);
    for (i = 0; i < 200 && atomic_load(&mode_calls) < 5; i++) {
        sleep_ms(10);
    }
    expect("MODE_IND calls: CLEAR, OPERATE, CLEAR, OFFLINE, OFFLINE",
           (PNIO_UINT32)atomic_load(&mode_calls), 5);
    expect("close", PNIO_controller_close(h), PNIO_OK);
    expect("close: again", PNIO_controller_close(h), PNIO_ERR_WRONG_HND);
    {
        PNIO_UINT8 b[16];
        PNIO_UINT32 n;
        PNIO_IOXS rem;
        expect("data_read: closed handle", PNIO_data_read(h, &i0, 16, &n, b, PNIO_S_GOOD, &rem),
               PNIO_ERR_WRONG_HND);
    }
    expect("set_mode: closed handle", PNIO_set_mode(h, PNIO_MODE_OPERATE), PNIO_ERR_WRONG_HND);

    /* Without MODE_CTRL the program observes the mode. */
    expect("open: without MODE_CTRL", PNIO_controller_open(1, 0, on_record, on_record, NULL, &h2),
           PNIO_OK);
    expect("a new handle is not the closed one", h2 != h, 1);
    expect("set_mode: without MODE_CTRL", PNIO_set_mode(h2, PNIO_MODE_OPERATE),
           PNIO_ERR_SET_MODE_NOT_ALLOWED);
    expect("device_activate: without MODE_CTRL", PNIO_device_activate(h2, &q0, PNIO_DA_TRUE),
           PNIO_ERR_DEV_ACT_NOT_ALLOWED);
    expect("close", PNIO_controller_close(h2), PNIO_OK);

    printf("%d checks wrong\n", failures);
    return failures != 0;
}
