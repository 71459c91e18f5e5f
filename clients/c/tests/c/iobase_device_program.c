/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * An IO-Base device program that defines its station, in the manual's order, against a
 * procimgd whose configuration names only the station's GSDML file (CpIndex 1 = the
 * instance in PROCIMG_INSTANCE; network = "sim", so procimgd's own PLC connects it):
 *
 *   open -> api_add -> plug the DAP (slot 0) and module 0x4242 (slot 1, 40 bytes each way,
 *   described by the GSDML file only) -> start -> AR_CHECK_IND, AR_INFO_IND (the program's
 *   tree) -> PRM_END_IND -> PNIO_initiate_data_write and _read (steps 14 and 15: the I data
 *   the PLC gets with the ApplicationReady) -> PNIO_set_appl_state_ready -> AR_INDATA_IND
 *   -> data both ways (the PLC's Q data is its I data plus one) -> a process alarm and a
 *   channel diagnosis, acknowledged -> stop -> close.
 *
 * Plugs the GSDML file does not allow are refused before start: a module ident it lacks, a
 * slot its device access point does not have. The callback table is initialised
 * positionally, in the manual's order. Arguments: VendorID DeviceID (the GSDML's).
 * Prints the I data of the first write and "all checks held" at the end.
 */
#define _POSIX_C_SOURCE 200809L

#include "pniousrd.h"
#include "procimg.h"
#include "check.h"
#include "../../examples/device_example.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define WAIT_S 20
#define MODULE_IDENT 0x4242u
#define SUBMODULE_IDENT 0x0001u
#define IO_LEN 40u

static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t cv = PTHREAD_COND_INITIALIZER;

/* What the callbacks saw, under mu. */
static int confirmations, conf_errors;
static int ar_checks, indata, ar_ends, stopped, alarms_done;
static PNIO_UINT32 alarm_status = 0xffffffffu;
static PNIO_UINT16 cur_ar, cur_sk;
static int prm_end;
static PNIO_UINT32 info_module = 0, info_in = 0, info_out = 0;
/* The I data the next DATA_WRITE gives, and the Q data and IOPS the last DATA_READ got. */
static PNIO_UINT8 i_data[IO_LEN];
static PNIO_UINT8 q_data[IO_LEN];
static PNIO_IOXS q_iops = PNIO_S_BAD;
static int writes, reads;

static void signal_all(void) {
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

/* Waits until *counter reaches at least `want`; 0 after WAIT_S seconds. */
static int wait_count(const int *counter, int want) {
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += WAIT_S;
    pthread_mutex_lock(&mu);
    while (*counter < want) {
        if (pthread_cond_timedwait(&cv, &mu, &until) != 0) break;
    }
    int ok = *counter >= want;
    pthread_mutex_unlock(&mu);
    return ok;
}

static PNIO_IOXS data_write(PNIO_UINT32 h, PNIO_DEV_ADDR *a, PNIO_UINT32 len, PNIO_UINT8 *buf,
                            PNIO_IOXS remote) {
    (void)h, (void)remote;
    pthread_mutex_lock(&mu);
    if (a->u.Geo.Slot == 1 && len == IO_LEN) {
        memcpy(buf, i_data, IO_LEN);
        writes++;
    }
    signal_all();
    return PNIO_S_GOOD;
}

static PNIO_IOXS data_read(PNIO_UINT32 h, PNIO_DEV_ADDR *a, PNIO_UINT32 len, PNIO_UINT8 *buf,
                           PNIO_IOXS iops) {
    (void)h;
    pthread_mutex_lock(&mu);
    if (a->u.Geo.Slot == 1 && len == IO_LEN) {
        memcpy(q_data, buf, IO_LEN);
        q_iops = iops;
        reads++;
    }
    signal_all();
    return PNIO_S_GOOD;
}

static void rec_read(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                     PNIO_UINT32 seq, PNIO_DEV_ADDR *a, PNIO_UINT32 index, PNIO_UINT32 *len,
                     PNIO_UINT8 *buf, PNIO_ERR_STAT *err) {
    (void)h, (void)api, (void)ar, (void)sk, (void)seq, (void)a, (void)index, (void)buf;
    *len = 0;
    err->ErrCode = 0xde;
    err->ErrDecode = 0x80;
    err->ErrCode1 = 0xb0; /* invalid index: module 0x4242 has no records */
    err->ErrCode2 = 0;
}

static void rec_write(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                      PNIO_UINT32 seq, PNIO_DEV_ADDR *a, PNIO_UINT32 index, PNIO_UINT32 *len,
                      PNIO_UINT8 *buf, PNIO_ERR_STAT *err) {
    (void)h, (void)api, (void)ar, (void)sk, (void)seq, (void)a, (void)index, (void)len, (void)buf,
        (void)err;
}

static void alarm_done(PNIO_UINT32 h, PNIO_UINT32 user, PNIO_UINT32 status, PNIO_ERR_STAT *err) {
    (void)h, (void)user, (void)err;
    pthread_mutex_lock(&mu);
    alarms_done++;
    alarm_status = status;
    signal_all();
}

static void check_ind(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                      PNIO_DEV_ADDR *a, PNIO_UINT32 *mod, PNIO_UINT16 *mstate, PNIO_UINT32 *sub,
                      PNIO_UINT16 *sstate) {
    (void)h, (void)api, (void)ar, (void)sk, (void)a, (void)mod, (void)mstate, (void)sub,
        (void)sstate;
}

static void ar_check_ind(PNIO_UINT32 h, PNIO_UINT32 host, PNIO_UINT16 type, PNIO_UUID_TYPE uuid,
                         PNIO_UINT32 props, PNIO_UUID_TYPE cmi, PNIO_UINT16 name_len,
                         PNIO_UINT8 *name, PNIO_AR_TYPE *ar) {
    (void)h, (void)host, (void)type, (void)uuid, (void)props, (void)cmi, (void)name_len,
        (void)name;
    pthread_mutex_lock(&mu);
    ar_checks++;
    cur_ar = ar->ArNumber;
    cur_sk = ar->SessionKey;
    signal_all();
}

static void ar_info_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_AR_TYPE *p) {
    (void)h, (void)ar, (void)sk;
    pthread_mutex_lock(&mu);
    for (PNIO_UINT32 i = 0; i < p->NumOfMod; i++) {
        PNIO_MODULE_TYPE *m = &p->pModList[i];
        if (m->SlotNum == 1 && m->NumOfSubmod == 1) {
            info_module = m->ModIdent;
            info_in = m->pSubList[0].InDatLen;
            info_out = m->pSubList[0].OutDatLen;
        }
    }
    signal_all();
}

static void ar_indata_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk) {
    (void)h, (void)ar, (void)sk;
    pthread_mutex_lock(&mu);
    indata++;
    signal_all();
}

static void ar_end_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_AR_REASON reason) {
    (void)h, (void)ar, (void)sk, (void)reason;
    pthread_mutex_lock(&mu);
    ar_ends++;
    signal_all();
}

static void apdu_status_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk,
                            PNIO_APDU_STATUS_IND status) {
    (void)h, (void)ar, (void)sk, (void)status;
}

static void prm_end_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_UINT32 api,
                        PNIO_UINT16 slot, PNIO_UINT16 subslot) {
    (void)h, (void)ar, (void)sk, (void)api, (void)slot, (void)subslot;
    pthread_mutex_lock(&mu);
    prm_end++;
    signal_all();
}

static void cp_stop_req(PNIO_UINT32 h) { (void)h; }

static void device_stopped(PNIO_UINT32 h, PNIO_UINT32 reserved) {
    (void)h, (void)reserved;
    pthread_mutex_lock(&mu);
    stopped++;
    signal_all();
}

static void pull_plug_conf(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_DEV_ACTION action,
                           PNIO_DEV_ADDR *a, PNIO_UINT32 error) {
    (void)h, (void)api, (void)action, (void)a;
    pthread_mutex_lock(&mu);
    confirmations++;
    if (error != PNIO_OK) conf_errors++;
    signal_all();
}

/* Positionally, in the manual's order. */
static PNIO_CBF_FUNCTIONS callbacks = {
    sizeof(PNIO_CBF_FUNCTIONS),
    data_write,
    data_read,
    rec_read,
    rec_write,
    alarm_done,
    check_ind,
    ar_check_ind,
    ar_info_ind,
    ar_indata_ind,
    ar_end_ind,
    ar_end_ind,
    apdu_status_ind,
    prm_end_ind,
    cp_stop_req,
    device_stopped,
    NULL,
    NULL,
    pull_plug_conf,
};

/* Sets the I data to `base + i`, writes it and reads the Q data once. */
static void exchange(PNIO_UINT32 h, PNIO_UINT8 base) {
    pthread_mutex_lock(&mu);
    for (PNIO_UINT32 i = 0; i < IO_LEN; i++) i_data[i] = (PNIO_UINT8)(base + i);
    pthread_mutex_unlock(&mu);
    CHECK_RC(PNIO_initiate_data_write(h), PNIO_OK);
    CHECK_RC(PNIO_initiate_data_read(h), PNIO_OK);
}

/* Whether the Q data last read is the I data `base + i` plus one, with IOPS GOOD. */
static int echoed(PNIO_UINT8 base) {
    int ok = 1;
    pthread_mutex_lock(&mu);
    for (PNIO_UINT32 i = 0; i < IO_LEN; i++) ok = ok && q_data[i] == (PNIO_UINT8)(base + i + 1);
    ok = ok && q_iops == PNIO_S_GOOD;
    pthread_mutex_unlock(&mu);
    return ok;
}

/* Reads the Q data until the PLC answers `base + i` with `base + i + 1`; 0 if not within
 * WAIT_S seconds. Writes nothing meanwhile. */
static int wait_echo(PNIO_UINT32 h, PNIO_UINT8 base) {
    time_t until = time(NULL) + WAIT_S;
    while (time(NULL) < until) {
        CHECK_RC(PNIO_initiate_data_read(h), PNIO_OK);
        if (echoed(base)) return 1;
        struct timespec ms = {0, 2000000};
        nanosleep(&ms, NULL);
    }
    return 0;
}

int main(int argc, char **argv) {
    CHECK(argc == 3, "usage: %s VENDOR_ID DEVICE_ID", argv[0]);
    PNIO_UINT16 vendor = (PNIO_UINT16)strtoul(argv[1], NULL, 0);
    PNIO_UINT16 device = (PNIO_UINT16)strtoul(argv[2], NULL, 0);
    PNIO_ANNOTATION ann;
    memset(&ann, 0, sizeof ann);
    strcpy((char *)ann.deviceType, "procimg test");
    strcpy((char *)ann.orderId, "PROCIMG-TEST");
    ann.hwRevision = 1;
    ann.swRevisionPrefix = 'V';

    PNIO_UINT32 h = 0;
    CHECK_RC(PNIO_device_open(1, PNIO_CEP_MODE_CTRL, vendor, device, 1, 1, &ann, &callbacks, &h),
             PNIO_OK);
    CHECK_RC(PNIO_api_add(h, 0, 0x20, 0x8001), PNIO_OK);

    /* The device access point, as the station's GSDML describes it. */
    PNIO_DEV_ADDR dap = geo(0, 1);
    CHECK_RC(PNIO_mod_plug(h, 0, &dap, 0x1), PNIO_OK);
    CHECK_RC(PNIO_sub_plug_ext_IM(h, 0, &dap, 0x1, PNIO_ALARM_TYPE_PLUG,
                                  PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MOD_DEV),
             PNIO_OK);
    CHECK(wait_count(&confirmations, 2), "no PULL_PLUG_CONF of the DAP");

    /* What the file does not allow: refused at once, naming the ident and the file. */
    PNIO_DEV_ADDR two = geo(2, 1);
    CHECK_RC(PNIO_mod_plug(h, 0, &two, 0x7777), PNIO_OK);
    CHECK_RC(PNIO_sub_plug(h, 0, &two, 0x1), PNIO_ERR_PRM_ADD);
    CHECK(strstr(procimg_last_error(), "0x00007777") != NULL &&
              strstr(procimg_last_error(), ".xml") != NULL,
          "the refusal names the ident and the file");
    CHECK_RC(PNIO_mod_pull(h, 0, &two), PNIO_OK);
    PNIO_DEV_ADDR far = geo(0x1f, 1);
    CHECK_RC(PNIO_mod_plug(h, 0, &far, MODULE_IDENT), PNIO_OK);
    CHECK_RC(PNIO_sub_plug(h, 0, &far, SUBMODULE_IDENT), PNIO_ERR_PRM_ADD);
    CHECK(strstr(procimg_last_error(), "PhysicalSlots") != NULL,
          "the refusal names the DAP's PhysicalSlots");
    CHECK_RC(PNIO_mod_pull(h, 0, &far), PNIO_OK);
    CHECK(wait_count(&confirmations, 6), "no PULL_PLUG_CONF of the refused modules");

    /* The program's module: only the GSDML file knows its 40 bytes each way. */
    PNIO_DEV_ADDR one = geo(1, 1);
    CHECK_RC(PNIO_mod_plug(h, 0, &one, MODULE_IDENT), PNIO_OK);
    CHECK_RC(PNIO_sub_plug(h, 0, &one, SUBMODULE_IDENT), PNIO_OK);
    CHECK(wait_count(&confirmations, 8), "no PULL_PLUG_CONF of module 0x4242");
    CHECK(conf_errors == 0, "%d plugs were confirmed with an error", conf_errors);

    /* The data functions before an AR answer as the manual says. */
    CHECK_RC(PNIO_initiate_data_write(h), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_device_start(h), PNIO_OK);
    CHECK(wait_count(&ar_checks, 1), "no AR_CHECK_IND");
    CHECK(wait_count(&prm_end, 1), "no PRM_END_IND");
    pthread_mutex_lock(&mu);
    PNIO_UINT16 ar = cur_ar, sk = cur_sk;
    CHECK(info_module == MODULE_IDENT && info_in == IO_LEN && info_out == IO_LEN,
          "AR_INFO_IND's slot 1: module 0x%x, %u bytes in, %u out", (unsigned)info_module,
          (unsigned)info_in, (unsigned)info_out);
    pthread_mutex_unlock(&mu);

    /* Steps 14 and 15: the first I data, then the ApplicationReady. */
    exchange(h, 0x30);
    CHECK(writes == 1 && reads == 1, "DATA_WRITE %d times, DATA_READ %d times", writes, reads);
    printf("first I data: 30 31 32 ... with IOPS GOOD\n");
    CHECK_RC(PNIO_set_appl_state_ready(h, ar, sk, NULL), PNIO_OK);
    CHECK(wait_count(&indata, 1), "no AR_INDATA_IND");

    /* The PLC's answer to the first I data, then to the next. */
    CHECK(wait_echo(h, 0x30), "the PLC's Q data never was the first I data plus one");
    exchange(h, 0x90);
    CHECK(wait_echo(h, 0x90), "the PLC's Q data never was the second I data plus one");
    printf("data both ways: Q = I + 1\n");

    /* A process alarm and a channel diagnosis, acknowledged by the PLC. */
    PNIO_UINT8 alarm_data[2] = {0x12, 0x34};
    CHECK_RC(PNIO_process_alarm_send(h, 0, ar, sk, &one, alarm_data, 2, 1, 1), PNIO_OK);
    CHECK(wait_count(&alarms_done, 1), "no REQ_DONE of the process alarm");
    CHECK(alarm_status == PNIO_OK, "process alarm: status 0x%x", (unsigned)alarm_status);
    PNIO_UINT16 appears = PNIO_build_channel_properties(
        h, PNIO_DIAG_CHANPROP_TYPE_SUBMOD, PNIO_DIAG_CHAN_SPEC_ERROR_APPEARS,
        PNIO_DIAG_CHAN_DIRECTION_MANUFACTURE);
    CHECK_RC(PNIO_diag_channel_add(h, 0, &one, 0x8000, appears, 0x0006, 7), PNIO_OK);
    PNIO_UINT8 item[6] = {0x80, 0x00, (PNIO_UINT8)(appears >> 8), (PNIO_UINT8)appears, 0x00,
                          0x06};
    CHECK_RC(PNIO_diag_alarm_send(h, 0, ar, sk, PNIO_STATE_ALARM_APPEARS, &one, item, sizeof item,
                                  PNIO_USR_STRUC_ID_CHANNEL_DIAG, 2),
             PNIO_OK);
    CHECK(wait_count(&alarms_done, 2), "no REQ_DONE of the diagnosis alarm");
    CHECK(alarm_status == PNIO_OK, "diagnosis alarm: status 0x%x", (unsigned)alarm_status);
    CHECK_RC(PNIO_diag_channel_remove(h, 0, &one, 7), PNIO_OK);
    printf("alarms acknowledged\n");

    CHECK_RC(PNIO_device_stop(h), PNIO_OK);
    CHECK(wait_count(&stopped, 1), "no DEVICE_STOPPED");
    CHECK(wait_count(&ar_ends, 1), "no AR_OFFLINE_IND");
    CHECK_RC(PNIO_device_close(h), PNIO_OK);
    printf("all checks held\n");
    return 0;
}
