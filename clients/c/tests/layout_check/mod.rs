// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the IO-Base header tests share: the C and C++ programs they generate from the Rust
//! mirrors (a `check` that counts and names mismatches, one check per size, alignment and
//! field offset), and building and running such a program.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

/// Records the size and alignment of the mirror type `$t` in `$sizes` and the offset of each
/// of its fields `$f` in `$offsets`, named as the C header names them.
macro_rules! record_layout {
    ($sizes:ident, $offsets:ident, $t:ident, [$($f:ident),* $(,)?]) => {
        $sizes.push((stringify!($t), size_of::<$t>(), align_of::<$t>()));
        $( $offsets.push((stringify!($t), stringify!($f), offset_of!($t, $f))); )*
    };
}

/// `(C type, size, alignment)`.
pub type Sizes = Vec<(&'static str, usize, usize)>;
/// `(C type, C field, offset)`.
pub type Offsets = Vec<(&'static str, &'static str, usize)>;

/// The generated program's start after its own includes: the standard headers it uses,
/// `ALIGN_OF` of the language, and `check`, which prints and counts every mismatch.
pub fn prelude(s: &mut String, cpp: bool) {
    writeln!(s, "#include <stddef.h>\n#include <stdio.h>").unwrap();
    if cpp {
        writeln!(s, "#define ALIGN_OF(t) alignof(t)").unwrap();
    } else {
        writeln!(s, "#define ALIGN_OF(t) _Alignof(t)").unwrap();
    }
    writeln!(
        s,
        "static int fails;\n\
         static void check(unsigned long long c, unsigned long long rust, const char *what) {{\n\
         \x20   if (c != rust) {{\n\
         \x20       printf(\"MISMATCH %s: C %llu, Rust %llu\\n\", what, c, rust);\n\
         \x20       fails++;\n\
         \x20   }}\n\
         }}"
    )
    .unwrap();
}

/// The checks of every size, alignment and field offset (inside `main`); how many.
pub fn layout_checks(s: &mut String, sizes: &Sizes, offsets: &Offsets) -> usize {
    for (t, size, align) in sizes {
        writeln!(
            s,
            "    check(sizeof({t}), {size}u, \"sizeof({t})\");\n    \
             check(ALIGN_OF({t}), {align}u, \"alignof({t})\");"
        )
        .unwrap();
    }
    for (t, f, o) in offsets {
        writeln!(
            s,
            "    check(offsetof({t}, {f}), {o}u, \"offsetof({t}, {f})\");"
        )
        .unwrap();
    }
    sizes.len() * 2 + offsets.len()
}

/// Builds `program` as C11 or C++17 in scratch directory `tag`, linked with libprocimg, and
/// runs it: fails naming the mismatches it printed and `mirrors`, where the Rust side is.
/// Returns what it printed.
pub fn build_and_run(tag: &str, program: &str, cpp: bool, mirrors: &str) -> String {
    let dir = procimg_testkit::c::scratch(tag);
    let (src, exe) = if cpp {
        (dir.join("check.cpp"), dir.join("check-cpp"))
    } else {
        (dir.join("check.c"), dir.join("check-c"))
    };
    std::fs::write(&src, program).unwrap();
    procimg_testkit::c::compile(&[src], &exe, procimg_testkit::c::Link::Static, false);
    run(&exe, cpp, mirrors)
}

/// [`build_and_run`] for the program `program` generates for C11 (`false`) and for C++17
/// (`true`), in that order. Returns what each printed.
pub fn build_and_run_c11_and_cpp17(
    tag: &str,
    program: impl Fn(bool) -> String,
    mirrors: &str,
) -> [String; 2] {
    [false, true].map(|cpp| build_and_run(tag, &program(cpp), cpp, mirrors))
}

fn run(exe: &Path, cpp: bool, mirrors: &str) -> String {
    let run = Command::new(exe).output().expect("run the check program");
    let stdout = String::from_utf8_lossy(&run.stdout).into_owned();
    assert!(
        run.status.success(),
        "the {} compiler disagrees with the Rust mirrors in {mirrors}:\n{stdout}",
        if cpp { "C++17" } else { "C11" },
    );
    stdout
}

/// Compiles a program that includes each set of headers in `include_sets` (in that order)
/// as C11 and as C++17, with every warning an error: each set must compile on its own.
/// Fails naming every set that did not.
pub fn headers_compile_alone(tag: &str, include_sets: &[&[&str]]) {
    let dir = procimg_testkit::c::scratch(tag);
    let include = Path::new(env!("CARGO_MANIFEST_DIR")).join("include");
    let mut failures = Vec::new();
    for includes in include_sets {
        for (cc, std, ext) in [("gcc", "-std=c11", "c"), ("g++", "-std=c++17", "cpp")] {
            let src = dir.join(format!("alone.{ext}"));
            let mut text = String::new();
            for h in *includes {
                writeln!(text, "#include \"{h}\"").unwrap();
            }
            text.push_str("int main(void) { return 0; }\n");
            std::fs::write(&src, text).unwrap();
            let out = Command::new(cc)
                .arg(std)
                .args(["-Wall", "-Wextra", "-Werror", "-pedantic", "-fsyntax-only"])
                .arg("-I")
                .arg(&include)
                .arg(&src)
                .output()
                .expect("run the C compiler");
            if !out.status.success() {
                failures.push(format!(
                    "{includes:?} ({cc}): {}",
                    String::from_utf8_lossy(&out.stderr)
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
