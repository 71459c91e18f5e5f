// SPDX-License-Identifier: MIT OR Apache-2.0
//! The hand-written IO-Base device header `pniousrd.h` must agree with the Rust mirrors in
//! `src/iobase/device_types.rs`: every struct's size, alignment and field offsets, every
//! constant's value, every callback typedef and every function prototype, as a C11 and a
//! C++17 compiler see them. A program generated from the Rust facts checks them all and
//! names each mismatch.
//!
//! Not every device function is implemented yet, so the programs do not use them: a
//! prototype is compared in unevaluated contexts only, C11 with `_Generic` on the function's
//! address, C++17 with `std::is_same` on its `decltype`. C's `_Generic` takes an
//! enum for the integer type it is compatible with; C++ tells them apart. The size of each
//! parameter's Rust type is compared with its C type's as well, so that the Rust prototypes
//! in `device_types::prototypes` and the callback aliases say what the header says.

use procimg::iobase::device_types::*;
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::mem::{align_of, offset_of, size_of};
use std::path::PathBuf;

#[macro_use]
mod layout_check;
use layout_check::{Offsets, Sizes};

fn include_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("include")
}

fn header() -> String {
    std::fs::read_to_string(include_dir().join("pniousrd.h")).expect("read include/pniousrd.h")
}

fn layout_facts() -> (Sizes, Offsets) {
    let mut sizes: Sizes = Vec::new();
    let mut offs: Offsets = Vec::new();
    macro_rules! ty {
        ($($layout:tt)*) => { record_layout!(sizes, offs, $($layout)*) };
    }
    ty!(PNIO_DEV_ADDR, [AddrType, IODataType, u]);
    // The union's members, and the fields of the unnamed struct Geo.
    let u = offset_of!(PNIO_DEV_ADDR, u);
    offs.push(("PNIO_DEV_ADDR", "u.RESERVED", u));
    offs.push(("PNIO_DEV_ADDR", "u.Geo", u));
    for (f, o) in [
        ("u.Geo.RESERVED1", offset_of!(PNIO_DEV_ADDR_Geo, RESERVED1)),
        ("u.Geo.Slot", offset_of!(PNIO_DEV_ADDR_Geo, Slot)),
        ("u.Geo.Subslot", offset_of!(PNIO_DEV_ADDR_Geo, Subslot)),
        ("u.Geo.RESERVED2", offset_of!(PNIO_DEV_ADDR_Geo, RESERVED2)),
    ] {
        offs.push(("PNIO_DEV_ADDR", f, u + o));
    }
    ty!(
        PNIO_ANNOTATION,
        [
            deviceType,
            orderId,
            hwRevision,
            swRevisionPrefix,
            swRevision1,
            swRevision2,
            swRevision3
        ]
    );
    ty!(
        PNIO_UUID_TYPE,
        [
            TimeLow,
            TimeMid,
            TimeHiAndVersion,
            ClockSeqHiAndReserved,
            ClockSeqLow,
            Node
        ]
    );
    ty!(PNIO_IOCS_TYPE, [SlotNum, SubslotNum, reserved]);
    ty!(
        PNIO_IOCR_TYPE,
        [
            CycleTime,
            Direction,
            IOCRProperties,
            SendClock,
            ReductioFactor,
            Phase,
            NumOfIoCs,
            pIoCsList,
            reserved
        ]
    );
    ty!(
        PNIO_SUBMOD_TYPE,
        [
            SlotNum,
            SubSlotNum,
            SubMProperties,
            SubMIdent,
            InDatLen,
            InIopsLen,
            InIocsLen,
            OutDatLen,
            OutIopsLen,
            OutIocsLen,
            reserved
        ]
    );
    ty!(
        PNIO_MODULE_TYPE,
        [Api, SlotNum, NumOfSubmod, ModProperties, ModIdent, pSubList]
    );
    // The manual's name of the same field (an anonymous union in C).
    offs.push(("PNIO_MODULE_TYPE", "API", offset_of!(PNIO_MODULE_TYPE, Api)));
    ty!(
        PNIO_AR_TYPE,
        [
            pNextAr, ArNumber, SessionKey, NumOfIocr, pIoCrList, NumOfMod, pModList
        ]
    );
    offs.push((
        "PNIO_AR_TYPE",
        "pReserved",
        offset_of!(PNIO_AR_TYPE, pNextAr),
    ));
    ty!(PNIO_LIST_ENTRY_TYPE, [Flink, Blink]);
    ty!(PNIO_APPL_READY_LIST_TYPE, [ap_list]);
    ty!(PNIO_APPL_READY_AP_TYPE, [link, api, module_list]);
    ty!(PNIO_APPL_READY_MODULE_TYPE, [link, slot_nr, submodule_list]);
    ty!(PNIO_APPL_READY_SUBMODULE_TYPE, [link, subslot_nr]);
    ty!(
        PNIO_BLOCK_HEADER,
        [BlockType, BlockLength, BlockVersionHigh, BlockVersionLow]
    );
    ty!(
        PNIO_IM0_TYPE,
        [
            BlockHeader,
            VendorIDHigh,
            VendorIDLow,
            OrderID,
            IM_Serial_Number,
            IM_Hardware_Revision,
            IM_Software_Revision,
            IM_Revision_Counter,
            IM_Profile_ID,
            IM_Profile_Specific_Type,
            IM_Version_Major,
            IM_Version_Minor,
            IM_Supported
        ]
    );
    ty!(
        PNIO_IM1_TYPE,
        [BlockHeader, IM_Tag_Function, IM_Tag_Location]
    );
    ty!(PNIO_IM2_TYPE, [BlockHeader, IM_Date]);
    ty!(PNIO_IM3_TYPE, [BlockHeader, IM_Descriptor]);
    ty!(PNIO_IM4_TYPE, [BlockHeader, IM_Signature]);
    ty!(
        PNIO_CBF_FUNCTIONS,
        [
            size,
            cbf_data_write,
            cbf_data_read,
            cbf_rec_read,
            cbf_rec_write,
            cbf_alarm_done,
            cbf_check_ind,
            cbf_ar_check_ind,
            cbf_ar_info_ind,
            cbf_ar_indata_ind,
            cbf_ar_abort_ind,
            cbf_ar_offline_ind,
            cbf_apdu_status_ind,
            cbf_prm_end_ind,
            cbf_cp_stop_req,
            cbf_device_stopped,
            cbf_start_led_flash,
            cbf_stop_led_flash,
            cbf_pull_plug_conf
        ]
    );
    // The manual's names of two members (the members; IO-Base's header's are macros) and of
    // the struct.
    offs.push((
        "PNIO_CBF_FUNCTIONS",
        "pnio_cbf_cp_stop_req",
        offset_of!(PNIO_CBF_FUNCTIONS, cbf_cp_stop_req),
    ));
    offs.push((
        "PNIO_CBF_FUNCTIONS",
        "pnio_cbf_device_stopped",
        offset_of!(PNIO_CBF_FUNCTIONS, cbf_device_stopped),
    ));
    sizes.push((
        "PNIO_CFB_FUNCTIONS",
        size_of::<PNIO_CFB_FUNCTIONS>(),
        align_of::<PNIO_CFB_FUNCTIONS>(),
    ));
    // Enums are int-sized.
    for e in [
        "PNIO_ACCESS_ENUM",
        "PNIO_DEV_ACTION",
        "PNIO_PLUG_IM0_BITS",
        "PNIO_AR_TYPE_ENUM",
        "PNIO_AR_REASON",
        "PNIO_APDU_STATUS_IND",
        "PNIO_IOCR_TYPE_ENUM",
        "PNIO_IOCR_PROP_ENUM",
        "PNIO_MODULE_STATE",
        "PNIO_SUBMODULE_STATE",
        "PNIO_SUB_CHECK_STATE",
        "enum PNIO_SUB_PROPERTIES_ENUM_USER",
    ] {
        sizes.push((e, size_of::<u32>(), align_of::<u32>()));
    }
    // Callback typedefs: a function pointer, NULL for "not supported".
    macro_rules! callback_sizes {
        ($($t:ident),* $(,)?) => {
            $( sizes.push((stringify!($t), size_of::<$t>(), align_of::<$t>())); )*
        };
    }
    callback_sizes!(
        PNIO_CBF_DATA_WRITE,
        PNIO_CBF_DATA_READ,
        PNIO_CBF_REC_READ,
        PNIO_CBF_REC_WRITE,
        PNIO_CBF_REQ_DONE,
        PNIO_CBF_CHECK_IND,
        PNIO_CBF_AR_CHECK_IND,
        PNIO_CBF_AR_INFO_IND,
        PNIO_CBF_AR_INDATA_IND,
        PNIO_CBF_AR_ABORT_IND,
        PNIO_CBF_AR_OFFLINE_IND,
        PNIO_CBF_APDU_STATUS_IND,
        PNIO_CBF_PRM_END_IND,
        PNIO_CBF_CP_STOP_REQ,
        PNIO_CBF_DEVICE_STOPPED,
        PNIO_CBF_START_LED_FLASH,
        PNIO_CBF_STOP_LED_FLASH,
        PNIO_CBF_PULL_PLUG_CONF,
    );
    (sizes, offs)
}

/// Every constant of the header with its Rust value: the names of its `#define`s and
/// enumerators, and C expressions of its one function-like macro.
fn constants() -> Vec<(String, u64)> {
    let mut v: Vec<(String, u64)> = Vec::new();
    macro_rules! c {
        ($($n:ident),* $(,)?) => { $( v.push((stringify!($n).to_string(), u64::from($n))); )* };
    }
    c!(
        MAX_DEVICE_TYPE_LENGTH,
        MAX_ORDER_ID_LENGTH,
        PNIO_DEVSTAT_OK,
        PNIO_DEVSTAT_STATION_PROBLEM,
        PNIO_ACCESS_ALL_WITH_LOCK,
        PNIO_ACCESS_ALL_WITHOUT_LOCK,
        PNIO_ACCESS_RT_WITH_LOCK,
        PNIO_ACCESS_RT_WITHOUT_LOCK,
        PNIO_ACCESS_IRT_WITH_LOCK,
        PNIO_ACCESS_IRT_WITHOUT_LOCK,
        PNIO_MOD_PULL,
        PNIO_MOD_PLUG,
        PNIO_SUB_PULL,
        PNIO_SUB_PLUG,
        PNIO_PLUG_IM0_BITS_NOTHING,
        PNIO_PLUG_IM0_BITS_SUBMODULE,
        PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MODULE,
        PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MOD_DEV,
        PNIO_AR_TYPE_SINGLE,
        PNIO_AR_TYPE_SUPERVISOR,
        PNIO_AR_TYPE_SINGLE_RTC3,
        PNIO_AR_REASON_NONE,
        PNIO_AR_REASON_RESERVED1,
        PNIO_AR_REASON_RESERVED2,
        PNIO_AR_REASON_MEM,
        PNIO_AR_REASON_FRAME,
        PNIO_AR_REASON_MISS,
        PNIO_AR_REASON_TIMER,
        PNIO_AR_REASON_ALARM,
        PNIO_AR_REASON_ALSND,
        PNIO_AR_REASON_ALACK,
        PNIO_AR_REASON_ALLEN,
        PNIO_AR_REASON_ASRT,
        PNIO_AR_REASON_RPC,
        PNIO_AR_REASON_ABORT,
        PNIO_AR_REASON_RERUN,
        PNIO_AR_REASON_REL,
        PNIO_AR_REASON_PAS,
        PNIO_AR_REASON_RMV,
        PNIO_AR_REASON_PROT,
        PNIO_AR_REASON_NARE,
        PNIO_AR_REASON_BIND,
        PNIO_AR_REASON_CONNECT,
        PNIO_AR_REASON_READ,
        PNIO_AR_REASON_WRITE,
        PNIO_AR_REASON_CONTROL,
        PNIO_AR_REASON_PULLPLUG,
        PNIO_AR_REASON_AP_RMV,
        PNIO_AR_REASON_LNK_DWN,
        PNIO_AR_REASON_MMAC,
        PNIO_AR_REASON_SYNC,
        PNIO_AR_REASON_TOPO,
        PNIO_AR_REASON_DCP_NAME,
        PNIO_AR_REASON_DCP_RESET,
        PNIO_AR_REASON_PRM,
        PNIO_AR_REASON_IRDATA,
        PNIO_AR_REASON_MAX,
        PNIO_EVENT_APDU_STATUS_STOP,
        PNIO_EVENT_APDU_STATUS_RUN,
        PNIO_EVENT_APDU_STATUS_STATION_OK,
        PNIO_EVENT_APDU_STATUS_STATION_PROBLEM,
        PNIO_EVENT_APDU_STATUS_PRIMARY,
        PNIO_EVENT_APDU_STATUS_BACKUP,
        PNIO_IOCR_TYPE_RESERVED_0,
        PNIO_IOCR_TYPE_INPUT,
        PNIO_IOCR_TYPE_OUTPUT,
        PNIO_IOCR_TYPE_MULTICAST_PROVIDER,
        PNIO_IOCR_TYPE_MULTICAST_CONSUMER,
        PNIO_IOCR_PROP_RT_CLASS_MASK,
        PNIO_IOCR_PROP_RT_CLASS_1,
        PNIO_IOCR_PROP_RT_CLASS_2,
        PNIO_IOCR_PROP_RT_CLASS_3,
        PNIO_IOCR_PROP_RT_CLASS_1_UDP,
        PNIO_MOD_STATE_NO_MODULE,
        PNIO_MOD_STATE_WRONG_MODULE,
        PNIO_MOD_STATE_PROPER_MODULE,
        PNIO_MOD_STATE_SUBSTITUTED_MODULE,
        PNIO_SUB_STATE_IDENT_MASK,
        PNIO_SUB_STATE_IDENT_NO_SUBMODULE,
        PNIO_SUB_STATE_IDENT_WRONG,
        PNIO_SUB_STATE_IDENT_SUBSTITUTE,
        PNIO_SUB_STATE_IDENT_OK,
        PNIO_SUB_STATE_FORMAT_1,
        PNIO_SUB_CHECK_NO_SUBMODULE,
        PNIO_SUB_CHECK_WRONG_SUBMODULE,
        PNIO_SUB_CHECK_SUBSTITUTED_SUBMODULE,
        PNIO_SUB_CHECK_PROPER_SUBMODULE,
        CM_SUB_PROP_USER_TYPE_MASK,
        CM_SUB_PROP_USER_TYPE_NO_DATA,
        CM_SUB_PROP_USER_TYPE_INPUT,
        CM_SUB_PROP_USER_TYPE_OUTPUT,
        CM_SUB_PROP_USER_TYPE_INPUT_OUTPUT,
        CM_SUB_PROP_USER_SHARED_INP_MASK,
        CM_SUB_PROP_USER_REDUCE_INP_LEN_MASK,
        CM_SUB_PROP_USER_REDUCE_OUT_LEN_MASK,
        CM_SUB_PROP_USER_DISCARD_IOXS_MASK,
        PNIO_SUB_PROP_TYPE_MASK,
        PNIO_SUB_PROP_TYPE_NO_DATA,
        PNIO_SUB_PROP_TYPE_INPUT,
        PNIO_SUB_PROP_TYPE_OUTPUT,
        PNIO_SUB_PROP_TYPE_INPUT_OUTPUT,
        PNIO_ALARM_TYPE_PLUG,
        PNIO_ALARM_TYPE_PLUG_WRONG,
        PNIO_STATE_ALARM_APPEARS,
        PNIO_STATE_ALARM_DISAPPEARS,
        PNIO_USR_STRUC_ID_CHANNEL_DIAG,
        PNIO_USR_STRUC_ID_MULTI_MANUFAC_DIAG,
        PNIO_USR_STRUC_ID_EXTCHANNEL_DIAG,
        PNIO_DIAG_CHANPROP_TYPE_SUBMOD,
        PNIO_DIAG_CHANPROP_TYPE_1BIT,
        PNIO_DIAG_CHANPROP_TYPE_2BIT,
        PNIO_DIAG_CHANPROP_TYPE_4BIT,
        PNIO_DIAG_CHANPROP_TYPE_BYTE,
        PNIO_DIAG_CHANPROP_TYPE_WORD,
        PNIO_DIAG_CHANPROP_TYPE_DWORD,
        PNIO_DIAG_CHANPROP_TYPE_LWORD,
        PNIO_DIAG_CHAN_SPEC_ERROR_APPEARS,
        PNIO_DIAG_CHAN_SPEC_ERROR_DISAPP_FREE,
        PNIO_DIAG_CHAN_SPEC_ERROR_DISAPP_REMAIN,
        PNIO_DIAG_CHAN_DIRECTION_MANUFACTURE,
        PNIO_DIAG_CHAN_DIRECTION_INPUT,
        PNIO_DIAG_CHAN_DIRECTION_OUTPUT,
        PNIO_DIAG_CHAN_DIRECTION_BIDIRECT,
        PNIO_CHAN_PROP_MAINT_REQUIRED_BIT,
        PNIO_CHAN_PROP_MAINT_DEMANDED_BIT,
    );
    for &(n, code) in PNIO_DIAG_CHAN_ERRORS {
        v.push((n.to_string(), u64::from(code)));
    }
    // The MaxAr encoding, including what its masks cut off.
    for (a, b, c) in [(2, 1, 3), (1, 0, 0), (0x12, 0x3, 0x21), (0xF, 0xF, 0xF)] {
        v.push((
            format!("PNIO_DEVICE_SET_MAXAR_BY_TYPE({a}, {b}, {c})"),
            u64::from(PNIO_DEVICE_SET_MAXAR_BY_TYPE(a, b, c)),
        ));
    }
    v
}

/// The list macros build and walk a list as the Rust mirrors' layout has it: an empty head
/// (self-linked or NULL), one entry inserted at the tail and one at the head, removed again.
const LIST_CHECK: &str = r#"
static int list_macros_work(void) {
    PNIO_APPL_READY_LIST_TYPE list;
    PNIO_APPL_READY_AP_TYPE ap1, ap2;
    int ok = 1;
    PNIO_LIST_INITIALIZE(&list.ap_list);
    ok = ok && PNIO_LIST_IS_EMPTY(&list.ap_list);
    ok = ok && PNIO_LIST_FIRST(&list.ap_list, PNIO_APPL_READY_AP_TYPE *) == NULL;
    PNIO_LIST_INSERT_TAIL(&list.ap_list, &ap1.link);
    PNIO_LIST_INSERT_HEAD(&list.ap_list, &ap2.link);
    ok = ok && !PNIO_LIST_IS_EMPTY(&list.ap_list);
    ok = ok && PNIO_LIST_FIRST(&list.ap_list, PNIO_APPL_READY_AP_TYPE *) == &ap2;
    ok = ok && PNIO_LIST_NEXT(&list.ap_list, &ap2.link, PNIO_APPL_READY_AP_TYPE *) == &ap1;
    ok = ok && PNIO_LIST_NEXT(&list.ap_list, &ap1.link, PNIO_APPL_READY_AP_TYPE *) == NULL;
    PNIO_LIST_REMOVE_ENTRY(&ap2.link);
    PNIO_LIST_REMOVE_ENTRY(&ap1.link);
    ok = ok && PNIO_LIST_IS_EMPTY(&list.ap_list);
    list.ap_list.Flink = list.ap_list.Blink = NULL;
    ok = ok && PNIO_LIST_IS_EMPTY(&list.ap_list);
    return ok;
}
"#;

/// The generated program and the number of checks it makes.
fn program(cpp: bool) -> (String, usize) {
    let (sizes, offsets) = layout_facts();
    let constants = constants();
    let mut checks = 0;
    let mut s = String::new();
    // With the controller header: a program may use both roles.
    writeln!(s, "#include \"pniousrd.h\"\n#include \"pniousrx.h\"").unwrap();
    if cpp {
        writeln!(s, "#include <type_traits>").unwrap();
    }
    layout_check::prelude(&mut s, cpp);
    s.push_str(LIST_CHECK);
    writeln!(s, "int main(void) {{").unwrap();
    checks += layout_check::layout_checks(&mut s, &sizes, &offsets);
    for (n, v) in &constants {
        writeln!(s, "    check((unsigned long long)({n}), {v}ull, \"{n}\");").unwrap();
        checks += 1;
    }
    // Prototypes and callback typedefs: the whole type (1 if the same), then the size of
    // each parameter's and the result's Rust type against its C type.
    for (sig, is_function) in DEVICE_FUNCTIONS
        .iter()
        .map(|s| (s, true))
        .chain(DEVICE_CALLBACKS.iter().map(|s| (s, false)))
    {
        let (name, t) = (sig.name, sig.c_pointer_type());
        let same = match (cpp, is_function) {
            (false, true) => format!("_Generic(&{name}, {t}: 1, default: 0)"),
            (false, false) => format!("_Generic(({name})0, {t}: 1, default: 0)"),
            (true, true) => format!("std::is_same<decltype(&{name}), {t}>::value"),
            (true, false) => format!("std::is_same<{name}, {t}>::value"),
        };
        writeln!(s, "    check({same}, 1, \"{name} is {t}\");").unwrap();
        checks += 1;
        for (p, ty) in sig.params {
            writeln!(
                s,
                "    check(sizeof({c}), {size}u, \"{name}: parameter {p} ({c})\");",
                c = ty.c,
                size = ty.size
            )
            .unwrap();
            checks += 1;
        }
        if sig.result.c != "void" {
            writeln!(
                s,
                "    check(sizeof({c}), {size}u, \"{name}: result ({c})\");",
                c = sig.result.c,
                size = sig.result.size
            )
            .unwrap();
            checks += 1;
        }
    }
    writeln!(
        s,
        "    check(list_macros_work(), 1, \"the PNIO_LIST_* macros\");"
    )
    .unwrap();
    checks += 1;
    writeln!(
        s,
        "    printf(\"%d mismatches, %d checks\\n\", fails, {checks});\n    return fails != 0;\n}}"
    )
    .unwrap();
    (s, checks)
}

#[test]
fn c11_and_cpp17_agree_with_rust() {
    let mirrors = "src/iobase/device_types.rs";
    let [c11, cpp17] = layout_check::build_and_run_c11_and_cpp17(
        "iobase-device-header",
        |cpp| program(cpp).0,
        mirrors,
    );
    println!("C11: {}\nC++17: {}", c11.trim(), cpp17.trim());
}

/// The header stands alone, may be included twice, and goes with the controller's header.
#[test]
fn header_compiles_alone_and_with_the_controller_header() {
    layout_check::headers_compile_alone(
        "iobase-device-alone",
        &[
            &["pniousrd.h", "pniousrd.h"],
            &["pniousrd.h", "pniousrx.h"],
            &["pniousrx.h", "pniousrd.h"],
        ],
    );
}

/// The manual's callback table initialised as C allows for a plain struct: positionally
/// (C and C++) and by designators (C, with both names of the two members IO-Base's header
/// spells otherwise), compiled with every warning an error.
#[test]
fn the_callback_table_takes_positional_and_designated_initializers() {
    let dir = procimg_testkit::c::scratch("iobase-device-cbf-init");
    let positional = r#"#include "pniousrd.h"
#include <stddef.h>
static void any(void) {}
#define CB(t) ((t)(void (*)(void))any)
static PNIO_CFB_FUNCTIONS positional = {
    sizeof(PNIO_CFB_FUNCTIONS),
    CB(PNIO_CBF_DATA_WRITE), CB(PNIO_CBF_DATA_READ), CB(PNIO_CBF_REC_READ),
    CB(PNIO_CBF_REC_WRITE), CB(PNIO_CBF_REQ_DONE), CB(PNIO_CBF_CHECK_IND),
    CB(PNIO_CBF_AR_CHECK_IND), CB(PNIO_CBF_AR_INFO_IND), CB(PNIO_CBF_AR_INDATA_IND),
    CB(PNIO_CBF_AR_ABORT_IND), CB(PNIO_CBF_AR_OFFLINE_IND), CB(PNIO_CBF_APDU_STATUS_IND),
    CB(PNIO_CBF_PRM_END_IND), CB(PNIO_CBF_CP_STOP_REQ), CB(PNIO_CBF_DEVICE_STOPPED),
    NULL, NULL, NULL
};
"#;
    let designated = r#"static PNIO_CBF_FUNCTIONS designated = {
    .size = sizeof(PNIO_CBF_FUNCTIONS),
    .cbf_prm_end_ind = CB(PNIO_CBF_PRM_END_IND),
    .cbf_cp_stop_req = CB(PNIO_CBF_CP_STOP_REQ),
    .pnio_cbf_device_stopped = CB(PNIO_CBF_DEVICE_STOPPED),
};
int main(void) {
    return positional.cbf_device_stopped == designated.cbf_device_stopped
        && positional.pnio_cbf_cp_stop_req == designated.cbf_cp_stop_req
        && positional.cbf_prm_end_ind == designated.cbf_prm_end_ind ? 0 : 1;
}
"#;
    let positional_only = "int main() {\n    return positional.cbf_cp_stop_req != nullptr \
                           && positional.cbf_stop_led_flash == nullptr ? 0 : 1;\n}\n";
    for (name, text) in [
        ("init.c", format!("{positional}{designated}")),
        ("init.cpp", format!("{positional}{positional_only}")),
    ] {
        let src = dir.join(name);
        std::fs::write(&src, text).unwrap();
        let exe = dir.join(name.replace('.', "_"));
        procimg_testkit::c::compile(&[src], &exe, procimg_testkit::c::Link::Static, false);
        let out = std::process::Command::new(&exe).output().unwrap();
        assert!(
            out.status.success(),
            "{name}: the members are not where they should be"
        );
    }
}

/// The names that follow `what` in the header's text, up to the next parenthesis, e.g. the
/// functions after `PNIO_CODE_ATTR ` or the callback typedefs after `(*`.
fn names_after(text: &str, what: &str) -> BTreeSet<String> {
    text.match_indices(what)
        .filter_map(|(i, _)| {
            let rest = &text[i + what.len()..];
            let end = rest.find(['(', ')'])?;
            let name = rest[..end].trim();
            (!name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
                .then(|| name.to_string())
        })
        .collect()
}

/// What the header declares is what the Rust lists hold, so the C programs check it all:
/// every function, every callback typedef, and every `#define` and enumerator with a value.
#[test]
fn header_declares_what_the_rust_lists_hold() {
    let text = header();
    let functions = names_after(&text, "PNIO_CODE_ATTR ");
    let listed: BTreeSet<String> = DEVICE_FUNCTIONS.iter().map(|f| f.name.into()).collect();
    assert_eq!(
        functions, listed,
        "functions of pniousrd.h vs DEVICE_FUNCTIONS"
    );
    assert_eq!(DEVICE_FUNCTIONS.len(), 31);

    let callbacks: BTreeSet<String> = names_after(&text, "(*")
        .into_iter()
        .filter(|n| n.starts_with("PNIO_CBF_"))
        .collect();
    let listed: BTreeSet<String> = DEVICE_CALLBACKS.iter().map(|f| f.name.into()).collect();
    assert_eq!(
        callbacks, listed,
        "callback typedefs of pniousrd.h vs DEVICE_CALLBACKS"
    );
    assert_eq!(DEVICE_CALLBACKS.len(), 18);

    // Object-like macros with a value (not the guard, not the other names of the struct and
    // of two of its members), and enumerators (`NAME = value`).
    let mut declared = BTreeSet::new();
    for line in text.lines() {
        let line = line.trim();
        if let Some(rest) = line.strip_prefix("#define ") {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            let function_like = rest[name.len()..].starts_with('(');
            let aliases = [
                "PNIOUSRD_H",
                "PNIO_CFB_FUNCTIONS",
                "cbf_cp_stop_req",
                "cbf_device_stopped",
            ];
            if !function_like && !aliases.contains(&name.as_str()) {
                declared.insert(name);
            }
        } else if let Some((name, _)) = line.split_once(" = ")
            && name
                .chars()
                .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
        {
            declared.insert(name.to_string());
        }
    }
    let checked: BTreeSet<String> = constants().into_iter().map(|(n, _)| n).collect();
    let unchecked: Vec<&String> = declared.difference(&checked).collect();
    assert!(
        unchecked.is_empty(),
        "constants of pniousrd.h the test does not check: {unchecked:?}"
    );
    let (sizes, offsets) = layout_facts();
    let checks = program(false).1;
    println!(
        "{} types, {} offsets, {} constants, {} functions, {} callback typedefs: {checks} checks",
        sizes.len(),
        offsets.len(),
        checked.len(),
        DEVICE_FUNCTIONS.len(),
        DEVICE_CALLBACKS.len()
    );
}

/// Every code the manual names for a device function is in `pnioerrx.h` and `errors.rs`
/// already (`iobase_header.rs` checks their values).
#[test]
fn the_device_role_needs_no_new_error_codes() {
    use procimg::iobase::errors;
    for n in [
        "PNIO_ERR_CONFIG_IN_UPDATE",
        "PNIO_ERR_CREATE_INSTANCE",
        "PNIO_ERR_INTERNAL",
        "PNIO_ERR_NO_FW_COMMUNICATION",
        "PNIO_ERR_OS_RES",
        "PNIO_ERR_PRM_CALLBACK",
        "PNIO_ERR_PRM_CP_ID",
        "PNIO_ERR_PRM_DEV_ANNOTATION",
        "PNIO_ERR_PRM_EXT_PAR",
        "PNIO_ERR_PRM_HND",
        "PNIO_ERR_PRM_MAX_AR_VALUE",
        "PNIO_ERR_PRM_PCBF",
        "PNIO_ERR_SEQUENCE",
        "PNIO_ERR_WRONG_HND",
        "PNIO_ERR_PRM_ADD",
        "PNIO_ERR_PRM_ACCESS_TYPE",
        "PNIO_ERR_PRM_BUF",
        "PNIO_ERR_PRM_LEN",
        "PNIO_ERR_PRM_TYPE",
        "PNIO_ERR_SESSION",
        "PNIO_ERR_UNKNOWN_ADDR",
        "PNIO_ERR_VALUE_LEN",
        "PNIO_ERR_ALLREADY_DONE",
        "PNIO_ERR_INVALID_CONFIG",
        "PNIO_ERR_OPFAULT_NOT_REG",
        "PNIO_ERR_NEWCYCLE_SEQUENCE_REG",
        "PNIO_WARN_IRT_INCONSISTENT",
        "PNIO_WARN_NO_SUBMODULES",
    ] {
        assert!(
            errors::ALL.iter().any(|(name, _)| *name == n),
            "{n} is missing from pnioerrx.h and errors.rs"
        );
    }
}
