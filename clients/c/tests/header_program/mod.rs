// SPDX-License-Identifier: MIT OR Apache-2.0
//! The program a header test of the controller side generates (`iobase_header.rs`,
//! `pn_driver_header.rs`): every prototype, callback type, size, offset and constant of
//! one header checked against the Rust facts, with [`layout_check`](crate::layout_check)'s
//! parts.

use crate::layout_check::{Offsets, Sizes, layout_checks, prelude};
use std::fmt::Write as _;

/// What a header test checks of one header: its functions' prototypes and callback types
/// (each spelled as a C pointer type with `(*)`), the layout of its types, its constants.
pub struct HeaderFacts<'a> {
    /// The header to include.
    pub header: &'a str,
    /// `(function, C pointer type)`.
    pub functions: &'a [(&'a str, &'a str)],
    /// `(C pointer type, typedef)`: a callback typedef must be that type.
    pub callbacks: &'a [(&'a str, &'a str)],
    /// Sizes and alignments.
    pub sizes: &'a Sizes,
    /// Field offsets.
    pub offsets: &'a Offsets,
    /// `(constant, value)`.
    pub constants: &'a [(&'static str, u64)],
}

/// The C (`cpp` false) or C++ program that checks `facts` against the compiler: each
/// prototype has exactly the manual's type (assigning the function to a pointer of that type
/// compiles only then: C++ is strict about it, C warns, -Werror), each callback typedef
/// converts to its shape, and every size, offset and value agrees. It prints the mismatches.
pub fn header_program(cpp: bool, facts: &HeaderFacts<'_>) -> String {
    let mut s = String::new();
    writeln!(s, "#include \"{}\"", facts.header).unwrap();
    prelude(&mut s, cpp);
    for (i, (f, t)) in facts.functions.iter().enumerate() {
        let decl = t.replacen("(*)", &format!("(*fn{i})"), 1);
        writeln!(s, "static {decl} = {f};").unwrap();
    }
    for (i, (shape, typedef)) in facts.callbacks.iter().enumerate() {
        let decl = shape.replacen("(*)", &format!("(*shape{i})"), 1);
        writeln!(s, "static {decl} = ({typedef})0;").unwrap();
    }
    writeln!(s, "int main(void) {{").unwrap();
    for (i, (f, _)) in facts.functions.iter().enumerate() {
        writeln!(s, "    check(fn{i} == NULL, 0, \"{f}\");").unwrap();
    }
    for (i, (_, typedef)) in facts.callbacks.iter().enumerate() {
        writeln!(s, "    check(shape{i} != NULL, 0, \"{typedef}\");").unwrap();
    }
    let layout = layout_checks(&mut s, facts.sizes, facts.offsets);
    for (n, v) in facts.constants {
        writeln!(s, "    check((unsigned long long)({n}), {v}ull, \"{n}\");").unwrap();
    }
    writeln!(
        s,
        "    printf(\"%d mismatches, %d checks\\n\", fails, {});\n    return fails != 0;\n}}",
        layout + facts.constants.len() + facts.functions.len() + facts.callbacks.len()
    )
    .unwrap();
    s
}
