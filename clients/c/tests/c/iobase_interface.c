/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * The controller's own interface (PN Driver's PNIO_interface_*), against a procimgd whose
 * [interface] lets programs set the name and address and checks the port's link, with
 * procimg's device "pc-device" as the port's configured neighbour. The test beside it
 * (tests/iobase_interface.rs) acts on the network when this program prints a step's name,
 * and answers "go" on stdin where the program waits for it:
 *
 *   ready       the interface is open and its records read, the CP info interface shows the
 *               port disturbed and both LEDs lit; the test starts the device
 *   peer        the neighbour arrived (its alarm disappeared) and PDPortDataReal names it;
 *               the test takes the link down
 *   down        the link-down alarm came; the test brings the link up
 *   up          the alarms went again
 *   named       PNIO_interface_set_ip_and_nos set the name, with its retentive data; the
 *               test finds it by DCP and says go
 *   addressed   the address is 10.47.0.2; the test checks the interface and renames the
 *               station by DCP
 *   tool-named  the DCP change came as PNIO_CBE_IFC_SET_ADDR_CONF
 *
 * Prints "interface: all checks held" at the end.
 */
#define _POSIX_C_SOURCE 200809L

#include "pniousrx.h"
#include "servusrx.h"
#include "iobase_controller.h"
#include "procimg.h"
#include "check.h"

#include <stdio.h>
#include <string.h>

#define IFC_ADDR 16382
#define PORT_ADDR 16381

static atomic_int reads, alarms, confs, remas, link_down_alarms;
static atomic_uint last_read_err, last_read_add1, last_ref;
static unsigned char last_record[4096];
static atomic_uint last_record_len;
static atomic_uint last_specifier, last_error_type, last_alarm_type, last_subslot;
static atomic_uint conf_err, conf_mode;
static char conf_name[256];
static char rema_text[1024];

/* The CP info interface's view of the same port. */
static atomic_int init_events, link_down_pdevs, led_events;
static atomic_uint init_items, init_port_state, led_bf, led_sf;

static void on_info(SERV_CP_INFO_PRM *p) {
    switch (p->InfoType) {
    case SERV_CP_INFO_PDEV_INIT_DATA:
        atomic_store(&init_items, p->u.PdevInitData.ItemNumber);
        atomic_store(&init_port_state, p->u.PdevInitData.InitState[1].PortState);
        atomic_fetch_add(&init_events, 1);
        break;
    case SERV_CP_INFO_PDEV_DATA:
        if (p->u.PdevData.LogAddr == PORT_ADDR && p->u.PdevData.Diagnostics.ErrType == 0x8000 &&
            p->u.PdevData.Diagnostics.ExtErrType == 0x8000)
            atomic_fetch_add(&link_down_pdevs, 1);
        break;
    case SERV_CP_INFO_LED_STATE:
        if (p->u.LedInfo.LedType == SERV_CIB_LED_BF)
            atomic_store(&led_bf, p->u.LedInfo.LedState);
        else
            atomic_store(&led_sf, p->u.LedInfo.LedState);
        atomic_fetch_add(&led_events, 1);
        break;
    default:
        break;
    }
}

/* Waits up to 30 s for *value to be `want`. */
static int wait_value(atomic_uint *value, unsigned want) {
    for (int i = 0; i < 3000; i++) {
        if (atomic_load(value) == want) return 1;
        sleep_ms(10);
    }
    return 0;
}

static void on_read(PNIO_CBE_PRM *p) {
    if (p->CbeType != PNIO_CBE_IFC_REC_READ_CONF) return;
    const PNIO_CBE_PRM_REC_READ_CONF *r = &p->RecReadConf;
    unsigned n = r->Length < sizeof last_record ? r->Length : sizeof last_record;
    memcpy(last_record, r->pBuffer, n);
    atomic_store(&last_record_len, n);
    atomic_store(&last_read_err, r->Err.ErrCode1);
    atomic_store(&last_read_add1, r->Err.AddValue1);
    atomic_store(&last_ref, r->ReqRef);
    atomic_fetch_add(&reads, 1);
}

static void on_alarm(PNIO_CBE_PRM *p) {
    if (p->CbeType != PNIO_CBE_IFC_ALARM_IND) return;
    const PNIO_CTRL_ALARM_DATA *a = p->AlarmInd.pAlarmData;
    unsigned error_type = 0;
    if (a->AlarmAinfo.UserStrucIdent == 0x8002 && a->AlarmAinfo.UserAlarmDataLen >= 6) {
        const PNIO_UINT8 *d = a->AlarmAinfo.UAData.UserAlarmData;
        error_type = (unsigned)(d[4] << 8 | d[5]);
    }
    CHECK(p->AlarmInd.pAddr->u.Addr == PORT_ADDR, "alarm at address %u",
          (unsigned)p->AlarmInd.pAddr->u.Addr);
    atomic_store(&last_error_type, error_type);
    atomic_store(&last_alarm_type, a->AlarmType);
    atomic_store(&last_subslot, a->SubslotNum);
    atomic_store(&last_specifier, a->AlarmAinfo.AlarmSpecifier);
    /* "Data transmission impossible" appearing: the link went down. */
    if (error_type == 0x8000 && (a->AlarmAinfo.AlarmSpecifier & 0x2000) != 0)
        atomic_fetch_add(&link_down_alarms, 1);
    atomic_fetch_add(&alarms, 1);
}

static void on_addr(PNIO_CBE_PRM *p) {
    if (p->CbeType == PNIO_CBE_IFC_SET_ADDR_CONF) {
        const PNIO_CBE_PRM_SET_ADDR_CONF *c = &p->SetAddrConf;
        unsigned n = c->StationNameLen < sizeof conf_name - 1 ? c->StationNameLen
                                                              : sizeof conf_name - 1;
        memcpy(conf_name, c->pStationName, n);
        conf_name[n] = 0;
        atomic_store(&conf_err, c->Err);
        atomic_store(&conf_mode, c->Mode);
        atomic_fetch_add(&confs, 1);
    } else if (p->CbeType == PNIO_CBE_REMA_READ_CONF) {
        const PNIO_CBE_PRM_REMA_READ_IND *r = &p->RemaReadConf;
        unsigned n = r->RemaXMLBufferLength < sizeof rema_text - 1 ? r->RemaXMLBufferLength
                                                                   : sizeof rema_text - 1;
        memcpy(rema_text, r->RemaXMLBuffer, n);
        rema_text[n] = 0;
        atomic_fetch_add(&remas, 1);
    }
}

/* Waits up to 30 s for *counter to exceed `seen`. */
static int wait_past(atomic_int *counter, int seen) {
    for (int i = 0; i < 3000; i++) {
        if (atomic_load(counter) > seen) return 1;
        sleep_ms(10);
    }
    return 0;
}

/* Whether the record last read holds `what` (len bytes). */
static int record_has(const void *what, size_t len) {
    unsigned n = atomic_load(&last_record_len);
    for (unsigned i = 0; i + len <= n; i++)
        if (memcmp(last_record + i, what, len) == 0) return 1;
    return 0;
}

/* Reads record `index` of the submodule at `addr`; waits for it. */
static void read_record(PNIO_UINT32 h, PNIO_UINT32 addr, PNIO_UINT32 index) {
    PNIO_ADDR a = {PNIO_ADDR_LOG, PNIO_IO_IN, {addr}};
    int seen = atomic_load(&reads);
    CHECK_RC(PNIO_interface_rec_read_req(h, &a, index, 0x4711, 4096), PNIO_OK);
    CHECK(wait_past(&reads, seen), "no confirmation of record 0x%x", (unsigned)index);
    CHECK(atomic_load(&last_ref) == 0x4711, "ReqRef %u", atomic_load(&last_ref));
}

/* Waits for an alarm after `seen` that leaves the port without diagnosis. */
static void wait_clear(int seen) {
    for (int i = 0; i < 3000; i++) {
        if (atomic_load(&alarms) > seen && (atomic_load(&last_specifier) & 0x2000) == 0) return;
        sleep_ms(10);
    }
    CHECK(0, "the port's diagnosis did not clear (%d alarms, last specifier 0x%x)",
          atomic_load(&alarms), atomic_load(&last_specifier));
}

static void step(const char *name) {
    printf("%s\n", name);
    fflush(stdout);
}

static void wait_go(void) {
    char line[16];
    CHECK(fgets(line, sizeof line, stdin) != NULL, "no go from the test");
}

int main(void) {
    check_part = "interface";
    PNIO_UINT32 h = 0, other = 0;
    CHECK_RC(PNIO_interface_open(1, on_read, on_alarm, NULL), PNIO_ERR_PRM_HND);
    CHECK_RC(PNIO_interface_open(0, on_read, on_alarm, &h), PNIO_ERR_PRM_CP_ID);
    CHECK_RC(PNIO_interface_open(1, on_read, on_alarm, &h), PNIO_OK);
    CHECK_RC(PNIO_interface_open(1, NULL, NULL, &other), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_interface_register_cbf(h, PNIO_CBE_IFC_REC_READ_CONF, on_read),
             PNIO_ERR_PRM_TYPE);
    CHECK_RC(PNIO_interface_register_cbf(h, PNIO_CBE_IFC_SET_ADDR_CONF, NULL),
             PNIO_ERR_PRM_CALLBACK);
    CHECK_RC(PNIO_interface_register_cbf(h + 1000, PNIO_CBE_IFC_SET_ADDR_CONF, on_addr),
             PNIO_ERR_WRONG_HND);

    /* Set before its confirmation has somewhere to go: refused. */
    PNIO_IPv4 ip;
    PNIO_NOS nos;
    memset(&ip, 0, sizeof ip);
    memset(&nos, 0, sizeof nos);
    CHECK_RC(PNIO_interface_set_ip_and_nos(h, PNIO_SET_NOS_MODE, ip, nos), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_interface_register_cbf(h, PNIO_CBE_IFC_SET_ADDR_CONF, on_addr), PNIO_OK);
    CHECK_RC(PNIO_interface_register_cbf(h, PNIO_CBE_IFC_SET_ADDR_CONF, on_addr),
             PNIO_ERR_ALREADY_DONE);
    CHECK_RC(PNIO_interface_register_cbf(h, PNIO_CBE_REMA_READ_CONF, on_addr), PNIO_OK);
    CHECK_RC(PNIO_interface_set_ip_and_nos(h, 0, ip, nos), PNIO_ERR_MODE_VALUE);
    nos.Length = 241;
    CHECK_RC(PNIO_interface_set_ip_and_nos(h, PNIO_SET_NOS_MODE, ip, nos), PNIO_ERR_PRM_NOS_LEN);

    /* Addresses other than the interface's and its port's are refused at the call. */
    PNIO_ADDR wrong = {PNIO_ADDR_LOG, PNIO_IO_IN, {0}};
    CHECK_RC(PNIO_interface_rec_read_req(h, &wrong, 0x8080, 1, 4096), PNIO_ERR_PRM_ADD);
    PNIO_ADDR ifc = {PNIO_ADDR_LOG, PNIO_IO_OUT, {IFC_ADDR}};
    CHECK_RC(PNIO_interface_rec_read_req(h, &ifc, 0x8080, 1, 4096), PNIO_ERR_PRM_ADD);
    ifc.IODataType = PNIO_IO_IN;
    CHECK_RC(PNIO_interface_rec_read_req(h, &ifc, 0x8080, 1, 0), PNIO_ERR_VALUE_LEN);
    CHECK_RC(PNIO_interface_rec_read_req(h, &ifc, 0x10000, 1, 4096), PNIO_ERR_PRM_REC_INDEX);

    /* PDInterfaceDataReal: the station's name and address. */
    read_record(h, IFC_ADDR, 0x8080);
    CHECK(atomic_load(&last_read_err) == 0, "0x8080 failed: 0x%x", atomic_load(&last_read_err));
    CHECK(record_has("plc-ifc", 7), "PDInterfaceDataReal lacks the station's name");
    const unsigned char own_ip[4] = {10, 47, 0, 1};
    CHECK(record_has(own_ip, 4), "PDInterfaceDataReal lacks 10.47.0.1");
    /* An index the interface does not have: PNIORW invalid index, AddValue1 the result. */
    read_record(h, IFC_ADDR, 0x1234);
    CHECK(atomic_load(&last_read_err) == 0xb0, "ErrCode1 0x%x", atomic_load(&last_read_err));
    CHECK(atomic_load(&last_read_add1) == (PNIO_ERR_PRM_REC_INDEX & 0xffff), "AddValue1 0x%x",
          atomic_load(&last_read_add1));

    /* The CP info interface: the port's state, both LEDs; no neighbour yet, no device up. */
    PNIO_UINT32 info = 0;
    CHECK_RC(SERV_CP_info_open(1, &info, 0), PNIO_OK);
    CHECK_RC(SERV_CP_info_register_cbf(info, 9, on_info, 0), PNIO_ERR_PRM_TYPE);
    CHECK_RC(SERV_CP_info_register_cbf(info, SERV_CP_INFO_PDEV_DATA, on_info, 0), PNIO_OK);
    CHECK_RC(SERV_CP_info_register_cbf(info, SERV_CP_INFO_PDEV_DATA, on_info, 0),
             PNIO_ERR_ALREADY_DONE);
    CHECK_RC(SERV_CP_info_register_cbf(info, SERV_CP_INFO_LED_STATE, on_info, 0), PNIO_OK);
    CHECK(wait_past(&init_events, 0), "no SERV_CP_INFO_PDEV_INIT_DATA");
    CHECK(atomic_load(&init_items) == 2, "%u items", atomic_load(&init_items));
    CHECK(atomic_load(&init_port_state) ==
              (SERV_CIB_PDEV_PORT_STATE_EXISTS | SERV_CIB_PDEV_PORT_STATE_DISTURBED),
          "port state 0x%x", atomic_load(&init_port_state));
    CHECK(wait_value(&led_sf, SERV_CIB_LED_ON), "SF not lit");
    CHECK(wait_value(&led_bf, SERV_CIB_LED_ON), "BF not lit");

    /* The configured neighbour arrives: its "no peer" diagnosis disappears. */
    int seen = atomic_load(&alarms);
    step("ready");
    wait_clear(seen);
    CHECK(atomic_load(&last_alarm_type) == PNIO_ALARM_PORT_DATA_CHANGED, "alarm type 0x%x",
          atomic_load(&last_alarm_type));
    CHECK(atomic_load(&last_subslot) == 0x8001, "alarm of subslot 0x%x",
          atomic_load(&last_subslot));
    CHECK(wait_value(&led_sf, SERV_CIB_LED_OFF), "SF still lit");
    CHECK(wait_value(&led_bf, SERV_CIB_LED_OFF), "BF still lit: the device is not up");
    read_record(h, PORT_ADDR, 0x802a);
    CHECK(atomic_load(&last_read_err) == 0, "0x802A failed");
    CHECK(record_has("pc-device", 9) && record_has("port-001", 8),
          "PDPortDataReal does not name the neighbour pc-device, port-001");

    /* The link goes down: "data transmission impossible" appears. */
    step("peer");
    CHECK(wait_past(&link_down_alarms, 0), "no link-down alarm (last ChannelErrorType 0x%x)",
          atomic_load(&last_error_type));
    CHECK(wait_past(&link_down_pdevs, 0), "no SERV_CP_INFO_PDEV_DATA for the link");
    CHECK(wait_value(&led_sf, SERV_CIB_LED_ON), "SF not lit by the link");
    seen = atomic_load(&alarms);
    step("down");
    wait_clear(seen);
    step("up");

    /* A program names the station, to be kept: confirmed, with its retentive data. */
    int confs_seen = atomic_load(&confs);
    memset(&nos, 0, sizeof nos);
    memcpy(nos.Nos, "plc-ifc-2", 9);
    nos.Length = 9;
    nos.Remanent = PNIO_TRUE;
    CHECK_RC(PNIO_interface_set_ip_and_nos(h, PNIO_SET_NOS_MODE, ip, nos), PNIO_OK);
    CHECK(wait_past(&confs, confs_seen), "no PNIO_CBE_IFC_SET_ADDR_CONF");
    CHECK(atomic_load(&conf_err) == PNIO_OK, "set name: 0x%x", atomic_load(&conf_err));
    CHECK(atomic_load(&conf_mode) == PNIO_SET_NOS_MODE, "Mode %u", atomic_load(&conf_mode));
    CHECK(strcmp(conf_name, "plc-ifc-2") == 0, "the station is \"%s\"", conf_name);
    CHECK(wait_past(&remas, 0), "no PNIO_CBE_REMA_READ_CONF");
    CHECK(strstr(rema_text, "plc-ifc-2") != NULL, "retentive data without the name:\n%s",
          rema_text);
    read_record(h, IFC_ADDR, 0x8080);
    CHECK(record_has("plc-ifc-2", 9), "PDInterfaceDataReal has the old name");
    step("named");
    wait_go();

    /* A program gives it another address: carried out on the interface. */
    confs_seen = atomic_load(&confs);
    const unsigned char new_ip[4] = {10, 47, 0, 2}, mask[4] = {255, 255, 255, 0};
    memcpy(ip.IpAddress, new_ip, 4);
    memcpy(ip.NetMask, mask, 4);
    CHECK_RC(PNIO_interface_set_ip_and_nos(h, PNIO_SET_IP_MODE, ip, nos), PNIO_OK);
    /* A second call while the first is unconfirmed is refused. On a busy machine the first
     * may be confirmed before the second call: then the second is a change of its own and is
     * confirmed too. Either way every accepted change is confirmed once. */
    PNIO_UINT32 again = PNIO_interface_set_ip_and_nos(h, PNIO_SET_IP_MODE, ip, nos);
    CHECK(again == PNIO_ERR_NOT_REENTERABLE || again == PNIO_OK,
          "a second change returned 0x%x, expected PNIO_ERR_NOT_REENTERABLE", (unsigned)again);
    int expected_confs = confs_seen + (again == PNIO_OK ? 1 : 0);
    CHECK(wait_past(&confs, expected_confs), "no PNIO_CBE_IFC_SET_ADDR_CONF for the address");
    CHECK(atomic_load(&conf_err) == PNIO_OK, "set address: 0x%x", atomic_load(&conf_err));
    /* A second change may come now; an invalid address is refused in the confirmation. */
    confs_seen = atomic_load(&confs);
    const unsigned char bad_mask[4] = {255, 0, 255, 0};
    memcpy(ip.NetMask, bad_mask, 4);
    CHECK_RC(PNIO_interface_set_ip_and_nos(h, PNIO_SET_IP_MODE, ip, nos), PNIO_OK);
    CHECK(wait_past(&confs, confs_seen), "no confirmation of the bad address");
    CHECK(atomic_load(&conf_err) == PNIO_ERR_PRM_IP, "bad address: 0x%x", atomic_load(&conf_err));
    read_record(h, IFC_ADDR, 0x8080);
    CHECK(record_has(new_ip, 4), "PDInterfaceDataReal lacks 10.47.0.2");

    /* An engineering tool renames it by DCP: the program hears of it. */
    confs_seen = atomic_load(&confs);
    step("addressed");
    CHECK(wait_past(&confs, confs_seen), "the DCP change did not come");
    CHECK(atomic_load(&conf_mode) == PNIO_SET_NOS_MODE, "DCP change Mode %u",
          atomic_load(&conf_mode));
    CHECK(strcmp(conf_name, "plc-ifc-3") == 0, "after DCP the station is \"%s\"", conf_name);
    step("tool-named");

    CHECK_RC(SERV_CP_info_close(info), PNIO_OK);
    CHECK_RC(SERV_CP_info_close(info), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_interface_close(h), PNIO_OK);
    CHECK_RC(PNIO_interface_close(h), PNIO_ERR_WRONG_HND);
    printf("interface: all checks held\n");
    return 0;
}
