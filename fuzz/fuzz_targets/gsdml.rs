// SPDX-License-Identifier: MIT OR Apache-2.0
//! GSDML device descriptions as arbitrary XML text: the reader, and everything a
//! configuration asks of a description that was read (access points, modules, submodules,
//! where they may be plugged, IO lengths, parameter records), plus value lists.
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_runtime::config::gsdml::{Gsdml, PlugRef, Submodule, ValueList};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match Gsdml::parse(&text, "GSDML-V2.4-fuzz-20260101.xml") {
        Ok(g) => description(&g),
        Err(e) => {
            let _ = (e.to_string(), e.line());
        }
    }
    // Value lists as the attributes hold them ("1..3 5"), from the first line.
    if let Some(line) = text.lines().next()
        && let Some(v) = ValueList::parse(line)
    {
        let _ = (v.min(), v.contains(0), v.contains(u32::MAX), v.values(256));
    }
});

fn description(g: &Gsdml) {
    let mut subs: Vec<&Submodule> = g.submodules.iter().collect();
    for dap in &g.daps {
        assert!(g.dap(&dap.id).is_some());
        let _ = (
            dap.fixed_in_slots.min(),
            dap.physical_slots.as_ref().map(ValueList::min),
        );
        plug_refs(&dap.useable_modules);
        subs.extend(&dap.submodules);
    }
    for m in &g.modules {
        assert!(g.module(&m.id).is_some());
        plug_refs(&m.useable_submodules);
        subs.extend(&m.submodules);
    }
    for s in subs {
        let _ = g.pluggable(&s.id);
        let _ = (s.kind.element(), s.subslots.as_ref().map(|v| v.values(256)));
        match g.io_lengths(s) {
            Ok(l) => {
                let _ = (l.input, l.output);
            }
            Err(e) => {
                let _ = e.to_string();
            }
        }
        match g.records(s) {
            Ok(records) => {
                let _ = records.iter().map(|r| r.data.len()).sum::<usize>();
            }
            Err(e) => {
                let _ = e.to_string();
            }
        }
    }
}

fn plug_refs(refs: &[PlugRef]) {
    for r in refs {
        let _ = (r.allows(0), r.allows(1), r.allows(u32::MAX), r.positions());
    }
}
