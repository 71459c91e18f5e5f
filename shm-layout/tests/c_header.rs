// SPDX-License-Identifier: MIT OR Apache-2.0
//! The committed C header `include/procimg_shm.h` must equal what cbindgen generates from the
//! Rust source, and C11 and C++17 compilers must agree with Rust on every size and offset.
//!
//! After changing a shared type, regenerate the header with
//! `PROCIMG_BLESS=1 cargo test -p procimg-shm-layout --test c_header`.

use procimg_shm_layout::*;
use std::fmt::Write as _;
use std::mem::{offset_of, size_of};
use std::path::{Path, PathBuf};
use std::process::Command;

const TYPES: &[(&str, &str)] = &[
    ("CycleInfo", "procimg_cycle_info_t"),
    ("ImageHeader", "procimg_image_header_t"),
    ("DeviceEntry", "procimg_device_entry_t"),
    ("SubmoduleEntry", "procimg_submodule_entry_t"),
    ("SubmoduleStatus", "procimg_submodule_status_t"),
    ("ClientSubmoduleStatus", "procimg_client_submodule_status_t"),
    ("LayoutHeader", "procimg_layout_header_t"),
    ("OutputHeader", "procimg_output_header_t"),
];

const CONSTANTS: &[&str] = &[
    "IMAGE_MAGIC",
    "LAYOUT_VERSION",
    "MAX_CLIENTS",
    "NO_ADDRESS",
    "CYCLE_COUNT_UNIT_NS",
    "STATION_NAME_LEN",
    "MODE_OFFLINE",
    "MODE_CLEAR",
    "MODE_OPERATE",
    "IOXS_GOOD",
    "IOXS_BAD",
    "IOXS_BAD_BY_CONTROLLER",
    "CLIENT_WROTE_OUTPUTS",
    "CLIENT_SET_OUTPUT_IOPS",
    "CLIENT_SET_INPUT_IOCS",
    "OUTPUT_SYNCHRONOUS",
    "RT_CLASS_1",
    "RT_CLASS_3",
    "MAX_SUBMODULE_DATA_LEN",
    "EVENT_STARTOP",
    "EVENT_NEWCYCLE",
    "EVENT_MODE",
    "EVENT_SHUTDOWN",
    "EVENT_OPFAULT_BASE",
    "EVENT_ID_MAX",
    "MODE_HISTORY",
];

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn generate() -> String {
    let mut config = cbindgen::Config {
        language: cbindgen::Language::C,
        include_guard: Some("PROCIMG_SHM_H".into()),
        header: Some("/* SPDX-License-Identifier: MIT OR Apache-2.0 */".into()),
        autogen_warning: Some(
            "/* Generated from shm-layout/src by cbindgen: do not edit. Regenerate with\n \
             * PROCIMG_BLESS=1 cargo test -p procimg-shm-layout --test c_header */"
                .into(),
        ),
        cpp_compat: true,
        usize_is_size_t: true,
        no_includes: true,
        sys_includes: vec!["stdint.h".into(), "stddef.h".into()],
        style: cbindgen::Style::Type,
        documentation: true,
        ..Default::default()
    };
    config.export.include = TYPES.iter().map(|(r, _)| r.to_string()).collect();
    for (rust, c) in TYPES {
        config.export.rename.insert(rust.to_string(), c.to_string());
    }
    for name in CONSTANTS {
        config
            .export
            .rename
            .insert(name.to_string(), format!("PROCIMG_{name}"));
    }
    let mut out = Vec::new();
    cbindgen::Builder::new()
        .with_crate(crate_dir())
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header")
        .write(&mut out);
    String::from_utf8(out).expect("header is UTF-8")
}

#[test]
fn committed_header_matches_the_rust_source() {
    let path = crate_dir().join("include/procimg_shm.h");
    let generated = generate();
    if std::env::var_os("PROCIMG_BLESS").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "{} differs from the Rust source: regenerate it with \
         PROCIMG_BLESS=1 cargo test -p procimg-shm-layout --test c_header",
        path.display()
    );
}

/// `(C type, C field, Rust offset)` for every field C can see, and `(C type, Rust size)`.
/// `(C type, C field, Rust offset)`.
type FieldFacts = Vec<(&'static str, &'static str, usize)>;
/// `(C type, Rust size)`.
type SizeFacts = Vec<(&'static str, usize)>;

fn layout_facts() -> (FieldFacts, SizeFacts) {
    macro_rules! fields {
        ($v:ident, $c:literal, $t:ty, [$($f:ident),* $(,)?]) => {
            $( $v.push(($c, stringify!($f), offset_of!($t, $f))); )*
        };
    }
    let mut f = Vec::new();
    fields!(
        f,
        "procimg_cycle_info_t",
        CycleInfo,
        [
            cycle_number,
            cycle_start_ns,
            clock_ns,
            since_cycle_start_ns,
            cycle_count,
            reserved
        ]
    );
    fields!(
        f,
        "procimg_image_header_t",
        ImageHeader,
        [
            magic,
            layout_version,
            header_size,
            layout_hash,
            generation,
            cycle,
            mode,
            submodule_count,
            payload_size,
            mode_changes,
            cycle_ns,
            opdone_deadline_ns,
            opfault_cycle,
            mode_history
        ]
    );
    fields!(
        f,
        "procimg_device_entry_t",
        DeviceEntry,
        [
            station_name,
            vendor_id,
            device_id,
            instance,
            reduction_ratio,
            ip_address,
            first_submodule,
            submodule_count,
            watchdog_factor,
            reserved
        ]
    );
    fields!(
        f,
        "procimg_submodule_entry_t",
        SubmoduleEntry,
        [
            device,
            slot,
            subslot,
            rt_class,
            reserved0,
            api,
            module_ident,
            submodule_ident,
            input_address,
            output_address,
            input_length,
            output_length,
            input_offset,
            output_offset,
            output_mirror_offset,
            status_offset,
            client_status_offset,
            reserved1,
            reserved2,
            reserved3
        ]
    );
    fields!(
        f,
        "procimg_submodule_status_t",
        SubmoduleStatus,
        [input_iops, input_iocs, output_iops, output_iocs]
    );
    fields!(
        f,
        "procimg_client_submodule_status_t",
        ClientSubmoduleStatus,
        [output_iops, input_iocs, flags, reserved]
    );
    fields!(
        f,
        "procimg_layout_header_t",
        LayoutHeader,
        [
            magic,
            layout_version,
            header_size,
            layout_hash,
            generation,
            cycle_ns,
            opdone_deadline_ns,
            device_count,
            submodule_count,
            input_size,
            output_size,
            input_payload_size,
            output_payload_size,
            device_table_offset,
            submodule_table_offset,
            status_offset,
            output_mirror_offset,
            client_status_offset,
            role
        ]
    );
    fields!(
        f,
        "procimg_output_header_t",
        OutputHeader,
        [
            magic,
            layout_hash,
            cycle_number,
            client_token,
            client_slot,
            flags
        ]
    );
    let sizes = vec![
        ("procimg_cycle_info_t", size_of::<CycleInfo>()),
        ("procimg_image_header_t", size_of::<ImageHeader>()),
        ("procimg_device_entry_t", size_of::<DeviceEntry>()),
        ("procimg_submodule_entry_t", size_of::<SubmoduleEntry>()),
        ("procimg_submodule_status_t", size_of::<SubmoduleStatus>()),
        (
            "procimg_client_submodule_status_t",
            size_of::<ClientSubmoduleStatus>(),
        ),
        ("procimg_layout_header_t", size_of::<LayoutHeader>()),
        ("procimg_output_header_t", size_of::<OutputHeader>()),
    ];
    (f, sizes)
}

fn check_program() -> String {
    let (fields, sizes) = layout_facts();
    let mut s = String::from("#include \"procimg_shm.h\"\n#include <stddef.h>\n");
    s.push_str(
        "#ifdef __cplusplus\n#define SA static_assert\n#else\n#define SA _Static_assert\n#endif\n",
    );
    for (t, f, off) in fields {
        writeln!(s, "SA(offsetof({t}, {f}) == {off}, \"offset of {t}.{f}\");").unwrap();
    }
    for (t, size) in sizes {
        writeln!(s, "SA(sizeof({t}) == {size}, \"size of {t}\");").unwrap();
    }
    writeln!(
        s,
        "SA(PROCIMG_LAYOUT_VERSION == {LAYOUT_VERSION}, \"layout version\");\n\
         SA(PROCIMG_MAX_CLIENTS == {MAX_CLIENTS}, \"max clients\");\n\
         int main(void) {{ return PROCIMG_IMAGE_MAGIC == {IMAGE_MAGIC}ULL ? 0 : 1; }}"
    )
    .unwrap();
    s
}

fn compile_and_run(compiler: &str, std: &str, ext: &str) {
    let dir = std::env::temp_dir().join(format!("procimg-c-header-{}-{ext}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src = dir.join(format!("check.{ext}"));
    std::fs::write(&src, check_program()).unwrap();
    let exe = dir.join("check");
    // When blessing, check the header just generated (the committed one is being rewritten).
    let include = if std::env::var_os("PROCIMG_BLESS").is_some() {
        std::fs::write(dir.join("procimg_shm.h"), generate()).unwrap();
        dir.clone()
    } else {
        crate_dir().join("include")
    };
    let include: &Path = &include;
    let out = Command::new(compiler)
        .args([std, "-Wall", "-Wextra", "-Werror", "-pedantic", "-I"])
        .arg(include)
        .arg(&src)
        .arg("-o")
        .arg(&exe)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {compiler}: {e}; install gcc and g++"));
    assert!(
        out.status.success(),
        "{compiler} {std} rejects the header:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let status = Command::new(&exe).status().unwrap();
    assert!(
        status.success(),
        "{compiler}: magic differs between C and Rust"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn c11_agrees_with_rust_on_every_offset() {
    compile_and_run("cc", "-std=c11", "c");
}

#[test]
fn cxx17_agrees_with_rust_on_every_offset() {
    compile_and_run("c++", "-std=c++17", "cpp");
}

#[test]
fn magic_spells_procimg1() {
    assert_eq!(IMAGE_MAGIC.to_le_bytes(), *b"PROCIMG1");
}
