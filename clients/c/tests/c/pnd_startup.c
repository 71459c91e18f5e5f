/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * A PN Driver program's life against procimg: SERV_CP_init -> SERV_CP_get_network_adapters
 * -> SERV_CP_startup (procimg's configuration from a file) -> PNIO_controller_open ... ->
 * SERV_CP_shutdown -> SERV_CP_undo_init, with the order rules and refusals on the way.
 *
 *   pnd_startup run CONFIG      the whole life; the configuration is the demo's (a
 *                               simulated plant), so the stack needs no root: echo
 *                               (I 0..15, Q 0..15) gives back what the program writes
 *   pnd_startup veth CONFIG ADAPTER
 *                               over a real interface: the stack on the adapter whose
 *                               Description is ADAPTER (the configuration, procimg's TOML
 *                               or TIA Portal's PN Driver XML, names another interface or
 *                               none), its firmware information printed, a controller
 *                               in OPERATE writing the
 *                               station's outputs (Q 0..7) until its inputs (I 0..7, which
 *                               the station's program echoes) bring them back GOOD, then
 *                               the stack's end; prints "veth: all checks held"
 *   pnd_startup crash CONFIG    starts the stack and opens a controller, prints
 *                               "stack serving", then dies by abort(): the stack must end
 *                               with it
 *
 * CpIndex 1 is the instance in PROCIMG_INSTANCE; PROCIMGD names procimgd. `run` also asks
 * SERV_CP_get_fw_info of CP 1 (its stack), of CP 2 (PROCIMG_CP2: a station in the device
 * role) and of CP 3 (PROCIMG_CP3: no procimgd), printing what CP 1 and 2 say. Prints
 * "pnd: all checks held" at the end of `run`.
 */
#define _POSIX_C_SOURCE 200809L

#include "pniousrx.h"
#include "servusrx.h"
#include "iobase_controller.h"
#include "procimg.h"
#include "check.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- The trace ----------------------------------------------------------------------- */

static pthread_mutex_t trace_lock = PTHREAD_MUTEX_INITIALIZER;
static char trace[1 << 20];
static size_t trace_len;
static int trace_calls;

static void trace_full(PNIO_UINT8 *buffer, PNIO_UINT32 size) {
    pthread_mutex_lock(&trace_lock);
    trace_calls++;
    if (trace_len + size < sizeof trace) {
        memcpy(trace + trace_len, buffer, size);
        trace_len += size;
        trace[trace_len] = '\0';
    }
    pthread_mutex_unlock(&trace_lock);
}

static atomic_int level_done;
static void on_level_done(void) { atomic_store(&level_done, 1); }

/* ---- The controller's callbacks -------------------------------------------------------- */

static atomic_int mode_seen = -1;
static void on_event(PNIO_CBE_PRM *p) {
    if (p->CbeType == PNIO_CBE_MODE_IND) atomic_store(&mode_seen, (int)p->ModeInd.Mode);
}

/* ---- Helpers ---------------------------------------------------------------------------- */

static char *read_file(const char *path, PNIO_UINT32 *len) {
    FILE *f = fopen(path, "rb");
    CHECK(f != NULL, "cannot open %s", path);
    static char text[1 << 16];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    *len = (PNIO_UINT32)n;
    return text;
}

static PNIO_UINT32 startup(PNIO_CP_ID_TYPE *cp, const char *config, PNIO_UINT32 len) {
    PNIO_SYSTEM_DESCR sys;
    memset(&sys, 0, sizeof sys);
    strcpy((char *)sys.Vendor, "procimg tests");
    strcpy((char *)sys.ProductFamily, "PN Driver program");
    return SERV_CP_startup(cp, 1, (PNIO_UINT8 *)config, len, NULL, 0, &sys);
}

static void print_fw_info(int cp) {
    SERV_CP_FW_INFO_TYPE fw;
    memset(&fw, 0xEE, sizeof fw);
    CHECK_RC(SERV_CP_get_fw_info((PNIO_UINT32)cp, &fw), PNIO_OK);
    const PNIO_UINT8 *ip = (const PNIO_UINT8 *)&fw.ip_addr;
    printf("fw %d: version %u.%u.%u ser %s mlfb %s hw %u mac %02x:%02x:%02x:%02x:%02x:%02x "
           "ip %u.%u.%u.%u name %s type %s\n",
           cp, (unsigned)fw.fw_version.v1, (unsigned)fw.fw_version.v2,
           (unsigned)fw.fw_version.v3, (const char *)fw.cp_ser_nr, (const char *)fw.mlfb,
           (unsigned)fw.hw_version, fw.mac[0], fw.mac[1], fw.mac[2], fw.mac[3], fw.mac[4],
           fw.mac[5], ip[0], ip[1], ip[2], ip[3], (const char *)fw.name,
           (const char *)fw.TypeOfStation);
}

static PNIO_UINT32 open_operate(void) {
    PNIO_UINT32 h = 0;
    CHECK_RC(PNIO_controller_open(1, PNIO_CEP_MODE_CTRL, on_event, on_event, NULL, &h),
             PNIO_OK);
    CHECK_RC(PNIO_register_cbf(h, PNIO_CBE_MODE_IND, on_event), PNIO_OK);
    CHECK_RC(PNIO_set_mode(h, PNIO_MODE_OPERATE), PNIO_OK);
    CHECK(wait_for_mode(&mode_seen, PNIO_MODE_OPERATE), "OPERATE never reported");
    return h;
}

/* Writes a pattern to echo's outputs until its inputs give it back. */
static void echo_round_trip(PNIO_UINT32 h) {
    PNIO_ADDR q = logical(PNIO_IO_OUT, 0), i = logical(PNIO_IO_IN, 0);
    PNIO_UINT8 out[16], in[16];
    for (int k = 0; k < 16; k++) out[k] = (PNIO_UINT8)(0xA0 + k);
    for (int tries = 0; tries < 2000; tries++) {
        PNIO_IOXS rem = PNIO_S_BAD;
        PNIO_UINT32 got = 0;
        if (PNIO_data_write(h, &q, sizeof out, out, PNIO_S_GOOD, &rem) == PNIO_OK &&
            PNIO_data_read(h, &i, sizeof in, &got, in, PNIO_S_GOOD, &rem) == PNIO_OK &&
            got == sizeof in && memcmp(in, out, sizeof in) == 0) {
            return;
        }
        sleep_ms(10);
    }
    fail(__LINE__, "echo never gave back the outputs written");
}

static void offline_close(PNIO_UINT32 h) {
    CHECK_RC(PNIO_set_mode(h, PNIO_MODE_OFFLINE), PNIO_OK);
    CHECK(wait_for_mode(&mode_seen, PNIO_MODE_OFFLINE), "OFFLINE never reported");
    CHECK_RC(PNIO_controller_close(h), PNIO_OK);
}

/* ---- The parts -------------------------------------------------------------------------- */

static void run(const char *config_path) {
    PNIO_UINT32 config_len = 0;
    const char *config = read_file(config_path, &config_len);
    static PNIO_CP_ID_TYPE cps[PROCIMG_MAX_NETWORK_ADAPTERS];
    PNIO_UINT8 n = 0;
    PNIO_UINT32 h = 0;

    /* Before SERV_CP_init, nothing of PN Driver's. */
    CHECK_RC(SERV_CP_get_network_adapters(cps, &n), PNIO_ERR_SEQUENCE);
    CHECK_RC(startup(cps, config, config_len), PNIO_ERR_SEQUENCE);
    CHECK_RC(SERV_CP_shutdown(), PNIO_ERR_SEQUENCE);
    CHECK_RC(SERV_CP_undo_init(), PNIO_ERR_SEQUENCE);
    CHECK_RC(SERV_CP_set_trace_level(PNIO_TRACE_COMP_PND, PNIO_TRACE_LEVEL_NOTE, NULL),
             PNIO_ERR_SEQUENCE);

    PNIO_DEBUG_SETTINGS_TYPE debug;
    memset(&debug, 0, sizeof debug);
    debug.CbfPntrcBufferFull = trace_full;
    for (int c = 0; c < PNIO_TRACE_COMP_NUM; c++) debug.TraceLevels[c] = PNIO_TRACE_LEVEL_NOTE;
    CHECK_RC(SERV_CP_init(&debug), PNIO_OK);
    CHECK_RC(SERV_CP_init(&debug), PNIO_ERR_SEQUENCE);

    CHECK_RC(SERV_CP_get_network_adapters(cps, &n), PNIO_OK);
    CHECK(n >= 1 && n <= PROCIMG_MAX_NETWORK_ADAPTERS, "%u adapters", (unsigned)n);
    for (int k = 0; k < n; k++) {
        CHECK(cps[k].CpSelection == PNIO_CP_SELECT_WITH_MAC_ADDRESS, "CpSelection %d",
              (int)cps[k].CpSelection);
        printf("adapter %s %02x:%02x:%02x:%02x:%02x:%02x pci %u:%u.%u\n",
               (const char *)cps[k].Description, cps[k].CpMacAddr[0], cps[k].CpMacAddr[1],
               cps[k].CpMacAddr[2], cps[k].CpMacAddr[3], cps[k].CpMacAddr[4],
               cps[k].CpMacAddr[5], (unsigned)cps[k].CpPciLocation.BusNr,
               (unsigned)cps[k].CpPciLocation.DeviceNr,
               (unsigned)cps[k].CpPciLocation.FunctionNr);
    }

    /* Between init and startup there is no controller. */
    CHECK_RC(PNIO_controller_open(1, PNIO_CEP_MODE_CTRL, on_event, on_event, NULL, &h),
             PNIO_ERR_SEQUENCE);

    /* What startup refuses, each leaving it to be called again. */
    CHECK_RC(SERV_CP_startup(cps, 2, (PNIO_UINT8 *)config, config_len, NULL, 0, NULL),
             PNIO_ERR_PRM_INVALIDARG);
    CHECK_RC(SERV_CP_startup(NULL, 1, (PNIO_UINT8 *)config, config_len, NULL, 0, NULL),
             PNIO_ERR_PRM_POINTER);
    CHECK_RC(SERV_CP_startup(cps, 1, (PNIO_UINT8 *)config, 0, NULL, 0, NULL),
             PNIO_ERR_PRM_INVALIDARG);
    PNIO_UINT8 rema[] = "<Rema/>";
    CHECK_RC(SERV_CP_startup(cps, 1, (PNIO_UINT8 *)config, config_len, rema, sizeof rema, NULL),
             PNIO_ERR_INVALID_REMA);
    const char *xml = "<?xml version=\"1.0\"?><HWConfiguration/>";
    CHECK_RC(startup(cps, xml, (PNIO_UINT32)strlen(xml)), PNIO_ERR_CORRUPTED_DATA);
    CHECK(strstr(procimg_last_error(), "not a PN Driver configuration") != NULL,
          "the refusal of XML that is no PN Driver configuration says so");
    const char *bad = "cycle_time = \"1ms\"\nno_such_key = 1\n";
    CHECK_RC(startup(cps, bad, (PNIO_UINT32)strlen(bad)), PNIO_ERR_CORRUPTED_DATA);
    CHECK(strstr(procimg_last_error(), "standard input:2") != NULL &&
              strstr(procimg_last_error(), "no_such_key") != NULL,
          "the refusal names the line and key");
    PNIO_CP_ID_TYPE nowhere = cps[0];
    memset(nowhere.CpMacAddr, 0xEE, sizeof nowhere.CpMacAddr);
    CHECK_RC(startup(&nowhere, config, config_len), PNIO_ERR_CREATE_INSTANCE);
    nowhere.CpSelection = (PNIO_CP_SELECT_TYPE)7;
    CHECK_RC(startup(&nowhere, config, config_len), PNIO_ERR_PRM_INVALIDARG);

    /* The stack, its station named by the retentive data a program kept (the test's
     * configuration lets programs name it). */
    const char *rema_kept =
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        "<RemanentData xmlns=\"urn:procimg:rema:1\"><NameOfStation>plc-from-rema"
        "</NameOfStation><IPSuite Address=\"192.168.0.1\" SubnetMask=\"255.255.255.0\" "
        "DefaultRouter=\"0.0.0.0\"/></RemanentData>\n";
    CHECK_RC(SERV_CP_startup(&cps[0], 1, (PNIO_UINT8 *)config, config_len,
                             (PNIO_UINT8 *)rema_kept, (PNIO_UINT32)strlen(rema_kept), NULL),
             PNIO_OK);
    CHECK_RC(startup(&cps[0], config, config_len), PNIO_ERR_SEQUENCE);
    CHECK_RC(SERV_CP_set_trace_level(PNIO_TRACE_COMP_NUM, PNIO_TRACE_LEVEL_NOTE, NULL),
             PNIO_ERR_PRM_INVALIDARG);
    CHECK_RC(SERV_CP_set_trace_level(PNIO_TRACE_COMP_PND, PNIO_TRACE_LEVEL_NUM, NULL),
             PNIO_ERR_PRM_INVALIDARG);
    CHECK_RC(SERV_CP_set_trace_level(PNIO_TRACE_COMP_PND, PNIO_TRACE_LEVEL_NOTE,
                                     on_level_done),
             PNIO_OK);
    for (int k = 0; k < 1000 && !atomic_load(&level_done); k++) sleep_ms(10);
    CHECK(atomic_load(&level_done), "CbfSetTraceLevelDone never came");

    /* The firmware information of the stack and of another CP. */
    SERV_CP_FW_INFO_TYPE fw;
    CHECK_RC(SERV_CP_get_fw_info(0, &fw), PNIO_ERR_PRM_CP_ID);
    CHECK_RC(SERV_CP_get_fw_info(1, NULL), PNIO_ERR_PRM_POINTER);
    CHECK_RC(SERV_CP_get_fw_info(3, &fw), PNIO_ERR_NO_FW_COMMUNICATION);
    print_fw_info(1);
    print_fw_info(2);

    h = open_operate();
    echo_round_trip(h);
    CHECK_RC(SERV_CP_shutdown(), PNIO_ERR_SEQUENCE); /* a controller is open */
    CHECK_RC(SERV_CP_undo_init(), PNIO_ERR_SEQUENCE); /* the stack runs */
    offline_close(h);

    CHECK_RC(SERV_CP_shutdown(), PNIO_OK);
    CHECK_RC(SERV_CP_shutdown(), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_controller_open(1, PNIO_CEP_MODE_CTRL, on_event, on_event, NULL, &h),
             PNIO_ERR_SEQUENCE);
    CHECK_RC(SERV_CP_undo_init(), PNIO_OK);
    CHECK_RC(SERV_CP_undo_init(), PNIO_ERR_SEQUENCE);

    /* The trace: procimgd's log lines, handed over at shutdown at the latest. */
    pthread_mutex_lock(&trace_lock);
    CHECK(trace_calls >= 1, "CbfPntrcBufferFull never called");
    CHECK(strstr(trace, "cycling every") != NULL, "the trace lacks procimgd's start:\n%s", trace);
    CHECK(strstr(trace, "standard input closed") != NULL,
          "the trace lacks procimgd's stop:\n%s", trace);
    pthread_mutex_unlock(&trace_lock);
    printf("pnd: all checks held\n");
}

static void veth(const char *config_path, const char *adapter) {
    PNIO_UINT32 config_len = 0;
    const char *config = read_file(config_path, &config_len);
    static PNIO_CP_ID_TYPE cps[PROCIMG_MAX_NETWORK_ADAPTERS];
    PNIO_UINT8 n = 0;
    int chosen = -1;
    CHECK_RC(SERV_CP_init(NULL), PNIO_OK);
    CHECK_RC(SERV_CP_get_network_adapters(cps, &n), PNIO_OK);
    for (int k = 0; k < n; k++) {
        if (strcmp((const char *)cps[k].Description, adapter) == 0) chosen = k;
    }
    CHECK(chosen >= 0, "adapter %s is not among the %u listed", adapter, (unsigned)n);
    CHECK_RC(startup(&cps[chosen], config, config_len), PNIO_OK);
    print_fw_info(1);
    PNIO_UINT32 h = open_operate();
    PNIO_ADDR i = logical(PNIO_IO_IN, 0), q = logical(PNIO_IO_OUT, 0);
    PNIO_UINT8 in[8], out[8] = {0x5A, 1, 2, 3, 4, 5, 6, 7};
    int good = 0;
    for (int tries = 0; tries < 3000 && !good; tries++) {
        PNIO_IOXS rem = PNIO_S_BAD;
        PNIO_UINT32 got = 0;
        good = PNIO_data_write(h, &q, sizeof out, out, PNIO_S_GOOD, &rem) == PNIO_OK &&
               PNIO_data_read(h, &i, sizeof in, &got, in, PNIO_S_GOOD, &rem) == PNIO_OK &&
               rem == PNIO_S_GOOD && got == sizeof in && memcmp(in, out, sizeof in) == 0;
        if (!good) sleep_ms(10);
    }
    CHECK(good, "the station never echoed the outputs over %s", adapter);
    printf("the station echoed the outputs over %s\n", adapter);
    offline_close(h);
    CHECK_RC(SERV_CP_shutdown(), PNIO_OK);
    CHECK_RC(SERV_CP_undo_init(), PNIO_OK);
    printf("veth: all checks held\n");
}

static void crash(const char *config_path) {
    PNIO_UINT32 config_len = 0;
    const char *config = read_file(config_path, &config_len);
    static PNIO_CP_ID_TYPE cps[PROCIMG_MAX_NETWORK_ADAPTERS];
    PNIO_UINT8 n = 0;
    CHECK_RC(SERV_CP_init(NULL), PNIO_OK);
    CHECK_RC(SERV_CP_get_network_adapters(cps, &n), PNIO_OK);
    CHECK_RC(startup(&cps[0], config, config_len), PNIO_OK);
    (void)open_operate();
    printf("stack serving\n");
    fflush(stdout);
    abort();
}

int main(int argc, char **argv) {
    if (argc == 3 && strcmp(argv[1], "run") == 0) {
        check_part = "run";
        run(argv[2]);
        return 0;
    }
    if (argc == 4 && strcmp(argv[1], "veth") == 0) {
        check_part = "veth";
        veth(argv[2], argv[3]);
        return 0;
    }
    if (argc == 3 && strcmp(argv[1], "crash") == 0) {
        check_part = "crash";
        crash(argv[2]);
        return 0;
    }
    fprintf(stderr, "usage: pnd_startup run|crash CONFIG | veth CONFIG ADAPTER\n");
    return 2;
}
