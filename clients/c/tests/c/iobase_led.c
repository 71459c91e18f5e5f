/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * The controller's LED events: a program opens controller 1 (the instance in
 * PROCIMG_INSTANCE), registers PNIO_CBE_START_LED_FLASH and PNIO_CBE_STOP_LED_FLASH, prints
 * "ready" and waits until an engineering tool's DCP Signal to the controller's station has
 * started the flashing (at 2 Hz) and, three seconds later, stopped it. Prints
 * "led: all checks held" at the end.
 */
#define _POSIX_C_SOURCE 200809L

#include "pniousrx.h"
#include "iobase_controller.h"
#include "procimg.h"
#include "check.h"

#include <stdio.h>

static atomic_int starts, stops;
static atomic_uint frequency;

static void on_event(PNIO_CBE_PRM *p) {
    if (p->CbeType == PNIO_CBE_START_LED_FLASH) {
        atomic_store(&frequency, p->LedFlash.Frequency);
        atomic_fetch_add(&starts, 1);
    } else if (p->CbeType == PNIO_CBE_STOP_LED_FLASH) {
        atomic_fetch_add(&stops, 1);
    }
}

int main(void) {
    check_part = "led";
    PNIO_UINT32 h = 0;
    /* Without PNIO_CEP_MODE_CTRL: the program watches, the server keeps its mode. */
    CHECK_RC(PNIO_controller_open(1, 0, on_event, on_event, NULL, &h), PNIO_OK);
    CHECK_RC(PNIO_register_cbf(h, PNIO_CBE_START_LED_FLASH, on_event), PNIO_OK);
    CHECK_RC(PNIO_register_cbf(h, PNIO_CBE_STOP_LED_FLASH, on_event), PNIO_OK);
    printf("ready\n");
    fflush(stdout);
    for (int i = 0; i < 3000 && atomic_load(&stops) == 0; i++) sleep_ms(10);
    CHECK(atomic_load(&starts) == 1, "%d starts", atomic_load(&starts));
    CHECK(atomic_load(&stops) == 1, "%d stops", atomic_load(&stops));
    CHECK(atomic_load(&frequency) == 2, "flashing at %u Hz", atomic_load(&frequency));
    CHECK_RC(PNIO_controller_close(h), PNIO_OK);
    printf("led: all checks held\n");
    return 0;
}
