// SPDX-License-Identifier: MIT OR Apache-2.0
//! The committed C header `include/procimg.h` must equal what cbindgen generates from
//! `src/native`, and C11 and C++17 compilers must agree with Rust on every size, offset,
//! constant and function signature in it.
//!
//! After changing the native API, regenerate the header with
//! `PROCIMG_BLESS=1 cargo test -p procimg-c --test native_header`.

use procimg::native::attach::*;
use procimg::native::cycle::procimg_submodule_ioxs_t;
use procimg::native::error::*;
use procimg::native::events::*;
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::mem::{offset_of, size_of};
use std::path::{Path, PathBuf};
use std::process::Command;

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The overview at the top of the header: the module documentation of `src/native/mod.rs`.
fn overview() -> String {
    let src = std::fs::read_to_string(crate_dir().join("src/native/mod.rs"))
        .expect("read src/native/mod.rs");
    let mut s = String::from("/*\n");
    for line in src.lines().filter_map(|l| l.strip_prefix("//!")) {
        let line = line.strip_prefix(' ').unwrap_or(line);
        // A nested comment would end this one early.
        let line = line.replace("*/", "* /").replace("/*", "/ *");
        if line.is_empty() {
            s.push_str(" *\n");
        } else {
            writeln!(s, " * {line}").unwrap();
        }
    }
    s.push_str(" */");
    s
}

fn generate() -> String {
    let after_includes = format!(
        "{}\n\n/**\n * An attached client (opaque): made by `procimg_attach`, freed by \
         `procimg_detach`.\n */\ntypedef struct procimg_client procimg_client_t;",
        overview()
    );
    let mut config = cbindgen::Config {
        language: cbindgen::Language::C,
        include_guard: Some("PROCIMG_H".into()),
        header: Some("/* SPDX-License-Identifier: MIT OR Apache-2.0 */".into()),
        autogen_warning: Some(
            "/* Generated from clients/c/src/native by cbindgen: do not edit. Regenerate with\n \
             * PROCIMG_BLESS=1 cargo test -p procimg-c --test native_header */"
                .into(),
        ),
        cpp_compat: true,
        usize_is_size_t: true,
        no_includes: true,
        includes: vec!["procimg_shm.h".into()],
        after_includes: Some(after_includes),
        style: cbindgen::Style::Type,
        documentation: true,
        ..Default::default()
    };
    // The handle is opaque: its typedef is written above, with the struct tag C expects.
    config.export.exclude.push("Handle".into());
    for (rust, c) in [
        ("Handle", "procimg_client_t"),
        ("CycleInfo", "procimg_cycle_info_t"),
        ("SubmoduleEntry", "procimg_submodule_entry_t"),
    ] {
        config.export.rename.insert(rust.into(), c.into());
    }
    let mut out = Vec::new();
    cbindgen::Builder::new()
        .with_src(crate_dir().join("src/native/mod.rs"))
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header")
        .write(&mut out);
    String::from_utf8(out).expect("header is UTF-8")
}

#[test]
fn committed_header_matches_the_rust_source() {
    let path = crate_dir().join("include/procimg.h");
    let generated = generate();
    if std::env::var_os("PROCIMG_BLESS").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "{} differs from the Rust source: regenerate it with \
         PROCIMG_BLESS=1 cargo test -p procimg-c --test native_header",
        path.display()
    );
}

/// Every constant of procimg.h with its Rust value.
fn constants() -> Vec<(&'static str, i64)> {
    macro_rules! consts {
        ($($name:ident),* $(,)?) => { vec![$((stringify!($name), $name as i64)),*] };
    }
    consts![
        PROCIMG_OK,
        PROCIMG_ERR_NULL_POINTER,
        PROCIMG_ERR_INVALID_ARGUMENT,
        PROCIMG_ERR_NO_SERVER,
        PROCIMG_ERR_REFUSED,
        PROCIMG_ERR_LAYOUT,
        PROCIMG_ERR_TIMEOUT,
        PROCIMG_ERR_SERVER_GONE,
        PROCIMG_ERR_NOT_IN_CYCLE,
        PROCIMG_ERR_UNKNOWN_ADDRESS,
        PROCIMG_ERR_LENGTH,
        PROCIMG_ERR_NOT_CLAIMED,
        PROCIMG_ERR_NO_IMAGE,
        PROCIMG_ERR_NOT_DELIVERED,
        PROCIMG_ERR_WRONG_ROLE,
        PROCIMG_ERR_NO_EVENT,
        PROCIMG_ERR_BUSY,
        PROCIMG_ERR_INTERNAL,
        PROCIMG_ROLE_SYNCHRONOUS,
        PROCIMG_ROLE_ASYNCHRONOUS,
        PROCIMG_ATTACH_SLICE_ACCESS,
        PROCIMG_ATTACH_NEWCYCLE,
        PROCIMG_ATTACH_BUSY_POLL,
        PROCIMG_ATTACH_EXPECT_LAYOUT_HASH,
        PROCIMG_ATTACH_SLEEP_ONLY,
        PROCIMG_DEFAULT_ATTACH_TIMEOUT_MS,
        PROCIMG_EVENT_MODE,
        PROCIMG_EVENT_OPFAULT,
        PROCIMG_EVENT_NEWCYCLE,
        PROCIMG_EVENT_SERVER_SHUTDOWN,
        PROCIMG_EVENT_REATTACHED,
        PROCIMG_EVENT_CLAIM_LOST,
        PROCIMG_EVENT_LAYOUT_CHANGED,
    ]
}

/// `(C type, C field, Rust offset)` for every field, and `(C type, Rust size)`.
type FieldFacts = Vec<(&'static str, &'static str, usize)>;
type SizeFacts = Vec<(&'static str, usize)>;

fn layout_facts() -> (FieldFacts, SizeFacts) {
    macro_rules! fields {
        ($v:ident, $t:ident, [$($f:ident),* $(,)?]) => {
            $( $v.push((stringify!($t), stringify!($f), offset_of!($t, $f))); )*
        };
    }
    let mut f = Vec::new();
    fields!(
        f,
        procimg_attach_options_t,
        [struct_size, role, flags, timeout_ms, layout_hash]
    );
    fields!(
        f,
        procimg_event_t,
        [kind, mode, cycle, generation, submodule]
    );
    fields!(
        f,
        procimg_submodule_ioxs_t,
        [input_remote, input_local, output_local, output_remote]
    );
    let sizes = vec![
        (
            "procimg_attach_options_t",
            size_of::<procimg_attach_options_t>(),
        ),
        ("procimg_event_t", size_of::<procimg_event_t>()),
        (
            "procimg_submodule_ioxs_t",
            size_of::<procimg_submodule_ioxs_t>(),
        ),
    ];
    (f, sizes)
}

/// Every function with the exact C signature the API promises; a compiler that sees another
/// one in the header rejects the assignment.
const SIGNATURES: &[(&str, &str)] = &[
    ("procimg_strerror", "const char *(*)(procimg_error_t)"),
    ("procimg_last_error", "const char *(*)(void)"),
    (
        "procimg_attach_options_init",
        "void (*)(procimg_attach_options_t *)",
    ),
    (
        "procimg_attach",
        "procimg_error_t (*)(const char *, const char *, const procimg_attach_options_t *, \
         procimg_client_t **)",
    ),
    ("procimg_detach", "procimg_error_t (*)(procimg_client_t *)"),
    (
        "procimg_submodules",
        "procimg_error_t (*)(const procimg_client_t *, const procimg_submodule_entry_t **, \
         size_t *)",
    ),
    (
        "procimg_find_submodule",
        "procimg_error_t (*)(const procimg_client_t *, const char *, uint16_t, uint16_t, \
         size_t *)",
    ),
    (
        "procimg_device_name",
        "procimg_error_t (*)(const procimg_client_t *, uint16_t, const char **)",
    ),
    (
        "procimg_layout_hash",
        "procimg_error_t (*)(const procimg_client_t *, uint64_t *)",
    ),
    (
        "procimg_claim",
        "procimg_error_t (*)(procimg_client_t *, const size_t *, size_t)",
    ),
    (
        "procimg_release",
        "procimg_error_t (*)(procimg_client_t *, const size_t *, size_t)",
    ),
    (
        "procimg_claim_device",
        "procimg_error_t (*)(procimg_client_t *, const char *)",
    ),
    (
        "procimg_wait_startop",
        "procimg_error_t (*)(procimg_client_t *, uint32_t, procimg_cycle_info_t *)",
    ),
    (
        "procimg_inputs",
        "procimg_error_t (*)(procimg_client_t *, const uint8_t **, size_t *)",
    ),
    (
        "procimg_input",
        "procimg_error_t (*)(procimg_client_t *, size_t, const uint8_t **, size_t *)",
    ),
    (
        "procimg_outputs",
        "procimg_error_t (*)(procimg_client_t *, uint8_t **, size_t *)",
    ),
    (
        "procimg_output",
        "procimg_error_t (*)(procimg_client_t *, size_t, uint8_t **, size_t *)",
    ),
    (
        "procimg_submodule_status",
        "procimg_error_t (*)(procimg_client_t *, size_t, procimg_submodule_ioxs_t *)",
    ),
    (
        "procimg_set_output_status",
        "procimg_error_t (*)(procimg_client_t *, size_t, uint8_t)",
    ),
    (
        "procimg_set_opdone",
        "procimg_error_t (*)(procimg_client_t *, procimg_cycle_info_t *)",
    ),
    (
        "procimg_data_read",
        "procimg_error_t (*)(procimg_client_t *, uint32_t, uint8_t *, size_t, size_t *, \
         uint8_t, uint8_t *)",
    ),
    (
        "procimg_output_data_read",
        "procimg_error_t (*)(procimg_client_t *, uint32_t, uint8_t *, size_t, size_t *, \
         uint8_t *, uint8_t *)",
    ),
    (
        "procimg_data_write",
        "procimg_error_t (*)(procimg_client_t *, uint32_t, const uint8_t *, size_t, uint8_t, \
         uint8_t *)",
    ),
    (
        "procimg_read_cache_refresh",
        "procimg_error_t (*)(procimg_client_t *)",
    ),
    (
        "procimg_read_cache",
        "procimg_error_t (*)(procimg_client_t *, uint32_t, uint8_t *, size_t, size_t *, \
         uint8_t, uint8_t *)",
    ),
    (
        "procimg_write_cache",
        "procimg_error_t (*)(procimg_client_t *, uint32_t, const uint8_t *, size_t, uint8_t, \
         uint8_t *)",
    ),
    (
        "procimg_write_cache_flush",
        "procimg_error_t (*)(procimg_client_t *)",
    ),
    (
        "procimg_set_mode",
        "procimg_error_t (*)(procimg_client_t *, uint32_t)",
    ),
    (
        "procimg_mode",
        "procimg_error_t (*)(procimg_client_t *, uint32_t *)",
    ),
    (
        "procimg_next_event",
        "procimg_error_t (*)(procimg_client_t *, procimg_event_t *)",
    ),
    (
        "procimg_event_fd",
        "procimg_error_t (*)(procimg_client_t *, int *)",
    ),
];

fn check_program() -> String {
    let (fields, sizes) = layout_facts();
    let mut s = String::from(
        "#include \"procimg.h\"\n#include \"procimg.h\" /* the include guard holds */\n\
         #include <stddef.h>\n",
    );
    s.push_str(
        "#ifdef __cplusplus\n#define SA static_assert\n#else\n#define SA _Static_assert\n#endif\n",
    );
    s.push_str("SA(sizeof(procimg_error_t) == 4 && (procimg_error_t)-1 < 0, \"int32_t\");\n");
    for (t, f, off) in fields {
        writeln!(s, "SA(offsetof({t}, {f}) == {off}, \"offset of {t}.{f}\");").unwrap();
    }
    for (t, size) in sizes {
        writeln!(s, "SA(sizeof({t}) == {size}, \"size of {t}\");").unwrap();
    }
    for (name, value) in constants() {
        writeln!(s, "SA({name} == {value}, \"value of {name}\");").unwrap();
    }
    // A function-pointer type alias per signature, then one assignment each.
    for (i, (_, sig)) in SIGNATURES.iter().enumerate() {
        let decl = sig.replacen("(*)", &format!("(*sig{i})"), 1);
        writeln!(s, "typedef {decl};").unwrap();
    }
    s.push_str("void check_signatures(void);\nvoid check_signatures(void) {\n");
    for (i, (name, _)) in SIGNATURES.iter().enumerate() {
        writeln!(s, "    sig{i} f{i} = {name};\n    (void)f{i};").unwrap();
    }
    s.push_str("}\n");
    s
}

fn compile(compiler: &str, std: &str, ext: &str) {
    let dir = std::env::temp_dir().join(format!("procimg-native-h-{}-{ext}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src = dir.join(format!("check.{ext}"));
    std::fs::write(&src, check_program()).unwrap();
    // When blessing, check the header just generated (the committed one is being rewritten).
    let include = if std::env::var_os("PROCIMG_BLESS").is_some() {
        std::fs::write(dir.join("procimg.h"), generate()).unwrap();
        dir.clone()
    } else {
        crate_dir().join("include")
    };
    let include: &Path = &include;
    let out = Command::new(compiler)
        .args([std, "-Wall", "-Wextra", "-Werror", "-pedantic", "-c", "-I"])
        .arg(include)
        .arg("-I")
        .arg(crate_dir().join("../../shm-layout/include"))
        .arg(&src)
        .arg("-o")
        .arg(dir.join("check.o"))
        .output()
        .unwrap_or_else(|e| panic!("cannot run {compiler}: {e}; install gcc and g++"));
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        out.status.success(),
        "{compiler} {std} rejects procimg.h or disagrees with Rust:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn c11_agrees_with_rust_on_every_size_constant_and_signature() {
    compile("cc", "-std=c11", "c");
}

#[test]
fn cxx17_agrees_with_rust_on_every_size_constant_and_signature() {
    compile("c++", "-std=c++17", "cpp");
}

/// The checks above cover every constant and function the header declares: a new one must
/// be added to them.
#[test]
fn the_checks_cover_the_whole_header() {
    let header = generate();
    let defines: BTreeSet<&str> = header
        .lines()
        .filter_map(|l| l.strip_prefix("#define "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|n| *n != "PROCIMG_H")
        .collect();
    let checked: BTreeSet<&str> = constants().into_iter().map(|(n, _)| n).collect();
    assert_eq!(
        defines, checked,
        "constants of procimg.h vs. the checked ones"
    );
    // A declaration line: not a comment, the function's name right before '('.
    let functions: BTreeSet<&str> = header
        .lines()
        .filter(|l| !l.trim_start().starts_with(['*', '/', '#']))
        .filter_map(|l| l.split_once('(').map(|(head, _)| head))
        .filter_map(|head| head.rsplit([' ', '*']).next())
        .collect();
    let signed: BTreeSet<&str> = SIGNATURES.iter().map(|(n, _)| *n).collect();
    assert_eq!(
        functions, signed,
        "functions of procimg.h vs. the checked ones"
    );
}

#[test]
fn the_header_begins_with_procimg_shm_h_and_names_everything_procimg() {
    let header = generate();
    let first_include = header.lines().find(|l| l.starts_with("#include"));
    assert_eq!(first_include, Some("#include \"procimg_shm.h\""));
    for line in header.lines() {
        if let Some(name) = line.strip_prefix("#define ") {
            assert!(name.starts_with("PROCIMG_"), "{line}");
        }
        if line.starts_with("} ") && !line.contains("extern") {
            assert!(
                line.starts_with("} procimg_") && line.ends_with("_t;"),
                "{line}"
            );
        }
    }
}
