/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * PROFIenergy from a controller program (pniousrx.h's PNIO_register_pe_cbf and
 * PNIO_pe_cmd_req) against the demo, whose devices answer as stations without
 * energy-saving modes: the call's refusals, then each command's confirmation with its
 * state, struct_id and answer. Prints "pe: all checks held".
 */
#define _POSIX_C_SOURCE 200809L

#include "pniousrx.h"
#include "iobase_controller.h"
#include "procimg.h"
#include "check.h"

#include <stdio.h>
#include <string.h>

/* The echo device's head module: the diagnostic address of its slot 0 subslot 1. */
#define ECHO_HEAD 22

static atomic_int confirmations;
static PNIO_PE_CBE_PRM last;

static void on_pe(PNIO_PE_CBE_PRM *p) {
    last = *p;
    atomic_fetch_add(&confirmations, 1);
}

static void on_record(PNIO_CBE_PRM *p) { (void)p; }

/* Sends `prm` to the echo device and waits for its confirmation. */
static PNIO_PE_CBE_PRM command(PNIO_UINT32 h, PNIO_PE_REQ_PRM *prm, PNIO_REF ref) {
    PNIO_ADDR head = {PNIO_ADDR_LOG, PNIO_IO_IN, {ECHO_HEAD}};
    int seen = atomic_load(&confirmations);
    CHECK_RC(PNIO_pe_cmd_req(h, &head, ref, prm), PNIO_OK);
    for (int i = 0; i < 1500 && atomic_load(&confirmations) == seen; i++) sleep_ms(10);
    CHECK(atomic_load(&confirmations) > seen, "no PE confirmation of command %u",
          (unsigned)prm->CmdId);
    CHECK(last.pe_hdr.Ref == ref && last.pe_hdr.Handle == h && last.pe_hdr.CmdId == prm->CmdId,
          "the confirmation is another command's");
    CHECK(last.pe_hdr.Addr.u.Addr == ECHO_HEAD, "address %u", (unsigned)last.pe_hdr.Addr.u.Addr);
    return last;
}

int main(void) {
    check_part = "pe";
    PNIO_UINT32 h = 0;
    CHECK_RC(PNIO_controller_open(1, 0, on_record, on_record, NULL, &h), PNIO_OK);
    PNIO_PE_REQ_PRM prm;
    memset(&prm, 0, sizeof prm);
    prm.CmdId = PNIO_PE_CMD_PE_IDENTIFY;
    PNIO_ADDR head = {PNIO_ADDR_LOG, PNIO_IO_IN, {ECHO_HEAD}};
    CHECK_RC(PNIO_pe_cmd_req(h, &head, 1, &prm), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_register_pe_cbf(h, NULL), PNIO_ERR_PRM_CALLBACK);
    CHECK_RC(PNIO_register_pe_cbf(h + 1000, on_pe), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_register_pe_cbf(h, on_pe), PNIO_OK);
    CHECK_RC(PNIO_register_pe_cbf(h, on_pe), PNIO_ERR_ALREADY_DONE);
    CHECK_RC(PNIO_pe_cmd_req(h, NULL, 1, &prm), PNIO_ERR_PRM_ADD);
    CHECK_RC(PNIO_pe_cmd_req(h, &head, 1, NULL), PNIO_ERR_PRM_BUF);
    PNIO_ADDR nowhere = {PNIO_ADDR_LOG, PNIO_IO_IN, {999}};
    CHECK_RC(PNIO_pe_cmd_req(h, &nowhere, 1, &prm), PNIO_ERR_PRM_ADD);
    prm.CmdModifier = PE_CMD_MODIF_Q_MODE_GET_MODE; /* PE_Identify takes none */
    CHECK_RC(PNIO_pe_cmd_req(h, &head, 1, &prm), PNIO_ERR_PRM_INVALIDARG);

    prm.CmdModifier = PE_CMD_MODIF_NOT_USED;
    PNIO_PE_CBE_PRM c = command(h, &prm, 10);
    CHECK(c.pe_hdr.state == 1 && c.pe_hdr.struct_id == PE_CNF_STRUCT_ID_UNIQUE,
          "PE_Identify: state %u struct_id %u", c.pe_hdr.state, c.pe_hdr.struct_id);
    CHECK(c.pe_prm.PeIdentify.numServices >= 2 && c.pe_prm.PeIdentify.serviceId[0] == 1 &&
              c.pe_prm.PeIdentify.serviceId[1] == 2,
          "PE_Identify lists %u services", c.pe_prm.PeIdentify.numServices);

    /* The station cannot save energy: its refusal. */
    memset(&prm, 0, sizeof prm);
    prm.CmdId = PNIO_PE_CMD_START_PAUSE;
    prm.rq.StartPause.time_ms = 5000;
    c = command(h, &prm, 11);
    CHECK(c.pe_hdr.state == 2 && c.pe_hdr.struct_id == PE_CNF_STRUCT_ID_ERROR,
          "Start_Pause: state %u struct_id %u", c.pe_hdr.state, c.pe_hdr.struct_id);
    CHECK(c.pe_prm.RespNegative.err_code == 0x06, "Start_Pause refused with 0x%x",
          c.pe_prm.RespNegative.err_code);

    memset(&prm, 0, sizeof prm);
    prm.CmdId = PNIO_PE_CMD_END_PAUSE;
    c = command(h, &prm, 12);
    CHECK(c.pe_hdr.state == 1 && c.pe_prm.EndPause.time_ms == 0, "End_Pause: state %u",
          c.pe_hdr.state);

    prm.CmdId = PNIO_PE_CMD_Q_MODES;
    prm.CmdModifier = PE_CMD_MODIF_Q_MODE_LIST_ALL;
    c = command(h, &prm, 13);
    CHECK(c.pe_hdr.struct_id == PE_CNF_STRUCT_ID_QMODE_LIST_ALL &&
              c.pe_prm.ModeList.numModeIds == 1 && c.pe_prm.ModeList.peModeId[0] == 0xFF,
          "Query_Modes list");

    prm.CmdModifier = PE_CMD_MODIF_Q_MODE_GET_MODE;
    prm.rq.ModeGet.peModeId = 0xFF;
    c = command(h, &prm, 14);
    CHECK(c.pe_hdr.struct_id == PE_CNF_STRUCT_ID_QMODE_GET_MODE &&
              c.pe_prm.ModeGet.peModeId == 0xFF,
          "Query_Modes Get_Mode");

    memset(&prm, 0, sizeof prm);
    prm.CmdId = PNIO_PE_CMD_PEM_STATUS;
    c = command(h, &prm, 15);
    CHECK(c.pe_prm.PemStatus.PE_Mode_ID_Source == 0xFF &&
              c.pe_prm.PemStatus.PE_Mode_ID_Destination == 0xFF,
          "PEM_Status");

    prm.CmdId = PNIO_PE_CMD_Q_MSRMT;
    prm.CmdModifier = PE_CMD_MODIF_Q_MSRMT_GET_VAL;
    prm.rq.MeasurementValue.num = 2;
    prm.rq.MeasurementValue.Measurement_ID[0] = 13;
    prm.rq.MeasurementValue.Measurement_ID[1] = 14;
    c = command(h, &prm, 16);
    CHECK(c.pe_hdr.struct_id == PE_CNF_STRUCT_ID_QMSRMT_GET_VAL &&
              c.pe_prm.MeasurementValue.numMeasurementValues == 2 &&
              c.pe_prm.MeasurementValue.value[1].Measurement_ID == 14 &&
              c.pe_prm.MeasurementValue.value[1].Status_of_Measurement_Value == 2,
          "Query_Measurement values");

    CHECK_RC(PNIO_controller_close(h), PNIO_OK);
    printf("pe: all checks held\n");
    return 0;
}
