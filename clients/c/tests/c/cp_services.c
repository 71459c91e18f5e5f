/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * The CP service functions against a running procimgd started with -c FILE.
 *
 *   cp_services hold      opens controller 1 with PNIO_CBE_CP_STOP_REQ registered, prints
 *                         "ready", waits for the stop request, closes, prints "closed".
 *   cp_services service   the type of station for the next start, the refusals, a SAFE
 *                         reset refused while "hold" runs, then a download of the
 *                         configuration in the file PROCIMG_TEST_CONFIG, which "hold" is
 *                         asked to stop for; then the firmware information of the new
 *                         procimgd. Prints "cp: all checks held".
 */
#define _POSIX_C_SOURCE 200809L

#include "pniousrx.h"
#include "servusrx.h"
#include "iobase_controller.h"
#include "procimg.h"
#include "check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static atomic_int stop_requests;

static void on_event(PNIO_CBE_PRM *p) {
    if (p->CbeType == PNIO_CBE_CP_STOP_REQ) atomic_fetch_add(&stop_requests, 1);
}

static int hold(void) {
    check_part = "hold";
    PNIO_UINT32 h = 0;
    CHECK_RC(PNIO_controller_open(1, 0, on_event, on_event, NULL, &h), PNIO_OK);
    CHECK_RC(PNIO_register_cbf(h, PNIO_CBE_CP_STOP_REQ, on_event), PNIO_OK);
    printf("ready\n");
    fflush(stdout);
    for (int i = 0; i < 3000 && atomic_load(&stop_requests) == 0; i++) sleep_ms(10);
    CHECK(atomic_load(&stop_requests) == 1, "%d stop requests", atomic_load(&stop_requests));
    CHECK_RC(PNIO_controller_close(h), PNIO_OK);
    printf("closed\n");
    return 0;
}

static char *read_file(const char *path, PNIO_UINT32 *len) {
    FILE *f = fopen(path, "rb");
    CHECK(f != NULL, "cannot open %s", path);
    static char text[65536];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = 0;
    *len = (PNIO_UINT32)n;
    return text;
}

static int service(void) {
    check_part = "service";
    char type[] = "procimg cp test";
    CHECK_RC(SERV_CP_set_type_of_station(0, type), PNIO_ERR_PRM_CP_ID);
    CHECK_RC(SERV_CP_set_type_of_station(1, NULL), PNIO_ERR_PRM_POINTER);
    CHECK_RC(SERV_CP_set_type_of_station(1, type), PNIO_OK);

    /* What a download refuses, changing nothing. */
    PNIO_UINT8 firmware[] = "FWL";
    CHECK_RC(SERV_CP_download(1, PNIO_CP_DLD_FIRMWARE, firmware, sizeof firmware),
             PNIO_ERR_PRM_TYPE);
    PNIO_UINT8 xdb[] = "<?xml version=\"1.0\"?><XDB/>";
    CHECK_RC(SERV_CP_download(1, PNIO_CP_DLD_CONFIG, xdb, sizeof xdb), PNIO_ERR_CORRUPTED_DATA);
    PNIO_UINT8 bad[] = "cycle_time = \"3us\"\n";
    CHECK_RC(SERV_CP_download(1, PNIO_CP_DLD_CONFIG, bad, sizeof bad), PNIO_ERR_CORRUPTED_DATA);
    CHECK(strstr(procimg_last_error(), "cycle_time") != NULL, "the refusal names the key: %s",
          procimg_last_error());
    CHECK_RC(SERV_CP_download(1, PNIO_CP_DLD_CONFIG, NULL, 0), PNIO_ERR_CORRUPTED_DATA);
    CHECK_RC(SERV_CP_reset(1, 7), PNIO_ERR_PRM_TYPE);
    /* "hold" is attached: a SAFE reset waits for nobody. */
    CHECK_RC(SERV_CP_reset(1, PNIO_CP_RESET_SAFE), PNIO_ERR_MAX_REACHED);

    /* A handle of this program's own open: exclusive access is refused. */
    PNIO_UINT32 h = 0;
    CHECK_RC(PNIO_interface_open(1, NULL, NULL, &h), PNIO_OK);
    CHECK_RC(SERV_CP_reset(1, PNIO_CP_RESET_FORCE), PNIO_ERR_MAX_REACHED);
    CHECK_RC(PNIO_interface_close(h), PNIO_OK);

    /* The download: "hold" is asked to stop, closes, and the new configuration runs. */
    PNIO_UINT32 len = 0;
    char *config = read_file(getenv("PROCIMG_TEST_CONFIG"), &len);
    CHECK_RC(SERV_CP_download(1, PNIO_CP_DLD_CONFIG, (PNIO_UINT8 *)config, len), PNIO_OK);
    SERV_CP_FW_INFO_TYPE fw;
    CHECK_RC(SERV_CP_get_fw_info(1, &fw), PNIO_OK);
    CHECK(strcmp((const char *)fw.TypeOfStation, type) == 0, "type of station \"%s\"",
          (const char *)fw.TypeOfStation);
    printf("cp: all checks held\n");
    return 0;
}

int main(int argc, char **argv) {
    if (argc == 2 && strcmp(argv[1], "hold") == 0) return hold();
    if (argc == 2 && strcmp(argv[1], "service") == 0) return service();
    fprintf(stderr, "usage: cp_services hold|service\n");
    return 2;
}
