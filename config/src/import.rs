// SPDX-License-Identifier: MIT OR Apache-2.0
//! Devices and submodules filled in from GSDML files: the keys `gsdml` and `dap` of a device,
//! `module` and `submodule` of a submodule, and the DAP submodules added to slot 0.
//!
//! Lookup errors are [`ConfigError::Invalid`] at the configuration key, with the GSDML file
//! and line in the message and the names to choose from; problems inside the GSDML file are
//! [`ConfigError::Gsdml`] at the key that led there.

use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use toml::Spanned;

use super::context::Cx;
use super::error::ConfigError;
use super::gsdml::{
    Dap, Gsdml, GsdmlError, MAX_LISTED_VALUES, Module, PlugRef, Submodule, SubmoduleKind, ValueList,
};

/// Most names listed in one message.
const MAX_LISTED: usize = 40;

/// The GSDML files of one configuration, each read once.
pub(super) struct Files {
    dir: PathBuf,
    loaded: HashMap<PathBuf, Rc<Gsdml>>,
}

impl Files {
    /// Files whose relative paths start at `dir`.
    pub fn new(dir: &Path) -> Files {
        Files {
            dir: dir.to_path_buf(),
            loaded: HashMap::new(),
        }
    }

    /// The file `written` (as in the configuration), read and parsed, with the path opened.
    fn load(&mut self, written: &str) -> Result<(PathBuf, Rc<Gsdml>), GsdmlError> {
        let path = self.dir.join(written);
        if let Some(gsdml) = self.loaded.get(&path) {
            return Ok((path, Rc::clone(gsdml)));
        }
        let gsdml = Rc::new(Gsdml::load(&path)?);
        self.loaded.insert(path.clone(), Rc::clone(&gsdml));
        Ok((path, gsdml))
    }
}

/// A device described by a GSDML file: the file and the DAP chosen.
pub(super) struct DeviceImport {
    pub path: PathBuf,
    pub gsdml: Rc<Gsdml>,
    pub dap: usize,
    /// Key path of the device's `gsdml` value, and its span.
    pub key: String,
    pub span: Range<usize>,
}

impl DeviceImport {
    pub fn dap(&self) -> &Dap {
        &self.gsdml.daps[self.dap]
    }

    fn file(&self) -> String {
        self.path.display().to_string()
    }

    /// A [`ConfigError::Gsdml`] at the device's `gsdml` key.
    pub fn error_here(&self, cx: &Cx<'_>, error: GsdmlError) -> ConfigError {
        cx.gsdml_error(self.span.clone(), &self.key, error)
    }
}

/// `"name" (ID id)`, or `ID "id"` for an item without a name.
fn item(name: Option<&str>, id: &str) -> String {
    match name {
        Some(name) if name != id => format!("{name:?} (ID {id:?})"),
        _ => format!("ID {id:?}"),
    }
}

/// `items` joined with "; ", at most [`MAX_LISTED`] of them.
fn listing(items: Vec<String>) -> String {
    let n = items.len();
    if n <= MAX_LISTED {
        return items.join("; ");
    }
    let mut shown = items[..MAX_LISTED].join("; ");
    shown.push_str(&format!("; and {} more", n - MAX_LISTED));
    shown
}

/// Loads the device's GSDML file and picks its DAP (keys `gsdml`, `dap`, `vendor_id`,
/// `device_id` of `device[d]`).
pub(super) fn device(
    d: usize,
    gsdml: &Spanned<String>,
    dap: Option<&Spanned<String>>,
    files: &mut Files,
    cx: &Cx<'_>,
) -> Result<DeviceImport, ConfigError> {
    let key = format!("device[{d}].gsdml");
    if gsdml.get_ref().trim().is_empty() {
        return Err(cx.invalid(
            gsdml.span(),
            key,
            "the path is empty; give the device's GSDML file, e.g. \
             \"GSDML-V2.4-Vendor-Family-20250101.xml\" (relative to this file's directory)",
        ));
    }
    let (path, file) = files
        .load(gsdml.get_ref())
        .map_err(|e| cx.gsdml_error(gsdml.span(), &key, e))?;
    let daps = || {
        listing(
            file.daps
                .iter()
                .map(|d| item(d.name.as_deref(), &d.id))
                .collect(),
        )
    };
    let index = match dap {
        Some(wanted) => {
            let w = wanted.get_ref().as_str();
            let by_id = file.daps.iter().position(|d| d.id == w);
            let by_name: Vec<usize> = (0..file.daps.len())
                .filter(|&i| file.daps[i].name.as_deref() == Some(w))
                .collect();
            match (by_id, by_name.as_slice()) {
                (Some(i), _) => i,
                (None, [i]) => *i,
                (None, []) => {
                    return Err(cx.invalid(
                        wanted.span(),
                        format!("device[{d}].dap"),
                        format!(
                            "{} has no device access point {w:?}; its DAPs: {}; give one of \
                             these IDs or names",
                            path.display(),
                            daps()
                        ),
                    ));
                }
                (None, _) => {
                    return Err(cx.invalid(
                        wanted.span(),
                        format!("device[{d}].dap"),
                        format!(
                            "{} has several device access points named {w:?}: {}; give the \
                             ID of one",
                            path.display(),
                            daps()
                        ),
                    ));
                }
            }
        }
        None if file.daps.len() == 1 => 0,
        None => {
            return Err(cx.invalid(
                gsdml.span(),
                key,
                format!(
                    "{} describes {} device access points (DAPs): {}; say which one the \
                     device has with `dap = \"<ID>\"`",
                    path.display(),
                    file.daps.len(),
                    daps()
                ),
            ));
        }
    };
    Ok(DeviceImport {
        path,
        gsdml: file,
        dap: index,
        key,
        span: gsdml.span(),
    })
}

/// Where a submodule candidate may go.
enum Where<'g> {
    /// Fixed in the subslots of this list.
    Fixed(&'g ValueList),
    /// Pluggable as the module's reference says.
    Plug(&'g PlugRef),
}

struct Candidate<'g> {
    sub: &'g Submodule,
    place: Where<'g>,
}

impl Candidate<'_> {
    fn fixed(&self) -> bool {
        matches!(self.place, Where::Fixed(_))
    }

    fn allows(&self, subslot: u32) -> bool {
        match self.place {
            Where::Fixed(list) => list.contains(subslot),
            Where::Plug(r) => r.allows(subslot).unwrap_or(true),
        }
    }

    /// The subslot taken when none is given.
    fn default_subslot(&self) -> Option<u32> {
        match self.place {
            Where::Fixed(list) => Some(list.min()),
            Where::Plug(r) => [&r.fixed, &r.used, &r.allowed]
                .into_iter()
                .flatten()
                .map(ValueList::min)
                .next(),
        }
    }

    fn describe(&self) -> String {
        let subslots = match self.place {
            Where::Fixed(list) => list.to_string(),
            Where::Plug(r) => r.positions(),
        };
        format!(
            "{} in subslot(s) {subslots}",
            item(self.sub.name.as_deref(), &self.sub.id)
        )
    }
}

/// What a `module` (and `submodule`) entry resolved to.
pub(super) struct Found<'g> {
    pub sub: &'g Submodule,
    pub module_ident: u32,
    pub subslot: u16,
    /// The module, for messages: `module "in1" (ID "M1", FILE:65)`.
    pub module: String,
    /// The submodule, for messages.
    pub submodule: String,
}

/// The raw keys of a submodule that take part in the lookup.
pub(super) struct Lookup<'r> {
    pub base: &'r str,
    pub module: &'r Spanned<String>,
    pub submodule: Option<&'r Spanned<String>>,
    pub slot: &'r Spanned<u16>,
    pub subslot: Option<&'r Spanned<u16>>,
}

/// Finds the module and submodule `lookup` names in the device's GSDML file, checking that
/// the DAP takes it in that slot.
pub(super) fn find<'g>(
    dev: &'g DeviceImport,
    lookup: &Lookup<'_>,
    cx: &Cx<'_>,
) -> Result<Found<'g>, ConfigError> {
    let g = &*dev.gsdml;
    let dap = dev.dap();
    let file = dev.file();
    let key = |k: &str| format!("{}.{k}", lookup.base);
    let wanted = lookup.module.get_ref().as_str();
    let slot = *lookup.slot.get_ref();

    let module: Option<&Module> = if dap.id == wanted || dap.name.as_deref() == Some(wanted) {
        None
    } else if let Some(m) = g.module(wanted) {
        Some(m)
    } else {
        let named: Vec<&Module> = g
            .modules
            .iter()
            .filter(|m| m.name.as_deref() == Some(wanted))
            .collect();
        match named.as_slice() {
            [m] => Some(*m),
            [] => {
                let message = if let Some(other) = g.dap(wanted) {
                    format!(
                        "{wanted:?} is the device access point {} of {file}, but this device \
                         uses the DAP {} (key `dap`); name that one, or change `dap`",
                        item(other.name.as_deref(), &other.id),
                        item(dap.name.as_deref(), &dap.id)
                    )
                } else {
                    format!(
                        "{file} has no module {wanted:?}; {}; give one of these names or IDs",
                        usable(g, dap)
                    )
                };
                return Err(cx.invalid(lookup.module.span(), key("module"), message));
            }
            several => {
                let ids: Vec<String> = several.iter().map(|m| format!("{:?}", m.id)).collect();
                return Err(cx.invalid(
                    lookup.module.span(),
                    key("module"),
                    format!(
                        "{file} has {} modules named {wanted:?} (IDs {}); give the ID of the \
                         one plugged here",
                        several.len(),
                        ids.join(", ")
                    ),
                ));
            }
        }
    };

    let (module_ident, candidates, described) = match module {
        None => {
            if !dap.fixed_in_slots.contains(u32::from(slot)) {
                return Err(cx.invalid(
                    lookup.slot.span(),
                    key("slot"),
                    format!(
                        "the device access point {} ({file}:{}) sits in slot {}, not {slot}; \
                         put it there",
                        item(dap.name.as_deref(), &dap.id),
                        dap.line,
                        dap.fixed_in_slots
                    ),
                ));
            }
            let candidates: Vec<Candidate<'_>> = dap
                .submodules
                .iter()
                .filter_map(|sub| {
                    sub.subslots.as_ref().map(|list| Candidate {
                        sub,
                        place: Where::Fixed(list),
                    })
                })
                .collect();
            let described = format!(
                "DAP {} ({file}:{})",
                item(dap.name.as_deref(), &dap.id),
                dap.line
            );
            (dap.module_ident, candidates, described)
        }
        Some(m) => {
            let described = format!(
                "module {} ({file}:{})",
                item(m.name.as_deref(), &m.id),
                m.line
            );
            let Some(plug) = dap.useable_modules.iter().find(|r| r.target == m.id) else {
                return Err(cx.invalid(
                    lookup.module.span(),
                    key("module"),
                    format!(
                        "{described} cannot be plugged into the device access point {} (it is \
                         not among the DAP's UseableModules); {}",
                        item(dap.name.as_deref(), &dap.id),
                        usable(g, dap)
                    ),
                ));
            };
            if plug.allows(u32::from(slot)) == Some(false) {
                return Err(cx.invalid(
                    lookup.slot.span(),
                    key("slot"),
                    format!(
                        "{described} goes in slot(s) {} of this DAP ({file}:{}), not in slot \
                         {slot}; move it",
                        plug.positions(),
                        plug.line
                    ),
                ));
            }
            if let Some(slots) = &dap.physical_slots
                && !slots.contains(u32::from(slot))
            {
                return Err(cx.invalid(
                    lookup.slot.span(),
                    key("slot"),
                    format!(
                        "the device has slots {slots} (PhysicalSlots of its DAP, {file}:{}), \
                         not slot {slot}",
                        dap.line
                    ),
                ));
            }
            let mut candidates: Vec<Candidate<'_>> = m
                .submodules
                .iter()
                .filter_map(|sub| {
                    sub.subslots.as_ref().map(|list| Candidate {
                        sub,
                        place: Where::Fixed(list),
                    })
                })
                .collect();
            for r in &m.useable_submodules {
                if let Some(sub) = g.pluggable(&r.target) {
                    candidates.push(Candidate {
                        sub,
                        place: Where::Plug(r),
                    });
                }
            }
            (m.module_ident, candidates, described)
        }
    };

    let choices = || listing(candidates.iter().map(Candidate::describe).collect());
    let chosen: &Candidate<'_> = if let Some(wanted_sub) = lookup.submodule {
        let w = wanted_sub.get_ref().as_str();
        let by_id = candidates.iter().find(|c| c.sub.id == w);
        let by_name: Vec<&Candidate<'_>> = candidates
            .iter()
            .filter(|c| c.sub.name.as_deref() == Some(w))
            .collect();
        match (by_id, by_name.as_slice()) {
            (Some(c), _) => c,
            (None, [c]) => c,
            _ => {
                return Err(cx.invalid(
                    wanted_sub.span(),
                    key("submodule"),
                    format!(
                        "{described} has no submodule {w:?} (or several of that name); its \
                         submodules: {}; give one of these IDs",
                        choices()
                    ),
                ));
            }
        }
    } else if let Some(subslot) = lookup.subslot {
        let s = u32::from(*subslot.get_ref());
        let fitting: Vec<&Candidate<'_>> = candidates.iter().filter(|c| c.allows(s)).collect();
        let fixed: Vec<&&Candidate<'_>> = fitting.iter().filter(|c| c.fixed()).collect();
        match (fitting.as_slice(), fixed.as_slice()) {
            ([c], _) => c,
            (_, [c]) => c,
            ([], _) => {
                return Err(cx.invalid(
                    subslot.span(),
                    key("subslot"),
                    format!(
                        "{described} has no submodule for subslot {s}; its submodules: {}; \
                         correct the subslot, or leave it out for the submodule's own",
                        choices()
                    ),
                ));
            }
            _ => {
                return Err(cx.invalid(
                    subslot.span(),
                    key("subslot"),
                    format!(
                        "several submodules of {described} can go in subslot {s}: {}; pick one \
                         with `submodule = \"<ID>\"`",
                        choices()
                    ),
                ));
            }
        }
    } else {
        let fixed: Vec<&Candidate<'_>> = candidates.iter().filter(|c| c.fixed()).collect();
        let virtual_: Vec<&&Candidate<'_>> = fixed
            .iter()
            .filter(|c| c.sub.kind == SubmoduleKind::Virtual)
            .collect();
        match (candidates.as_slice(), fixed.as_slice(), virtual_.as_slice()) {
            ([c], _, _) => c,
            (_, [c], _) => c,
            (_, _, [c]) => c,
            ([], _, _) => {
                return Err(cx.invalid(
                    lookup.module.span(),
                    key("module"),
                    format!(
                        "{described} has no submodules to configure; correct the GSDML file or \
                         give module_ident, submodule_ident and the lengths instead"
                    ),
                ));
            }
            _ => {
                return Err(cx.invalid(
                    lookup.module.span(),
                    key("module"),
                    format!(
                        "{described} has several submodules: {}; add one [[device.submodule]] \
                         for each you use, with `submodule = \"<ID>\"` or its `subslot`",
                        choices()
                    ),
                ));
            }
        }
    };

    let subslot = match lookup.subslot {
        Some(given) => {
            let s = *given.get_ref();
            if !chosen.allows(u32::from(s)) {
                return Err(cx.invalid(
                    given.span(),
                    key("subslot"),
                    format!(
                        "submodule {} of {described} cannot go in subslot {s}; correct the \
                         subslot, or leave it out for the submodule's own",
                        chosen.describe()
                    ),
                ));
            }
            s
        }
        None => {
            let at = lookup.submodule.map_or(lookup.module.span(), Spanned::span);
            let which = if lookup.submodule.is_some() {
                "submodule"
            } else {
                "module"
            };
            match chosen.default_subslot().map(u16::try_from) {
                Some(Ok(s)) => s,
                _ => {
                    return Err(cx.invalid(
                        at,
                        key(which),
                        format!(
                            "submodule {} of {described} has no subslot of its own; give \
                             `subslot`",
                            chosen.describe()
                        ),
                    ));
                }
            }
        }
    };

    Ok(Found {
        sub: chosen.sub,
        module_ident,
        subslot,
        module: described,
        submodule: format!(
            "submodule {} ({file}:{})",
            item(chosen.sub.name.as_deref(), &chosen.sub.id),
            chosen.sub.line
        ),
    })
}

/// The modules the DAP takes, for messages.
fn usable(g: &Gsdml, dap: &Dap) -> String {
    let items: Vec<String> = dap
        .useable_modules
        .iter()
        .filter_map(|r| {
            g.module(&r.target).map(|m| {
                format!(
                    "{} in slot(s) {}",
                    item(m.name.as_deref(), &m.id),
                    r.positions()
                )
            })
        })
        .collect();
    if items.is_empty() {
        return format!(
            "the device access point {} takes no modules",
            item(dap.name.as_deref(), &dap.id)
        );
    }
    format!(
        "the modules of the device access point {} are: {}",
        item(dap.name.as_deref(), &dap.id),
        listing(items)
    )
}

/// The DAP's own submodules as (subslot, submodule), in subslot order: what goes into slot 0
/// when the configuration leaves it out.
pub(super) fn dap_submodules<'g>(
    dev: &'g DeviceImport,
    cx: &Cx<'_>,
) -> Result<Vec<(u16, &'g Submodule)>, ConfigError> {
    let dap = dev.dap();
    let mut out = Vec::new();
    for sub in &dap.submodules {
        let Some(list) = &sub.subslots else { continue };
        let values = list.values(MAX_LISTED_VALUES).unwrap_or_default();
        let subslots: Vec<u16> = values
            .iter()
            .filter_map(|&v| u16::try_from(v).ok())
            .filter(|&v| v != 0)
            .collect();
        if subslots.is_empty() || subslots.len() != values.len() {
            return Err(cx.invalid(
                dev.span.clone(),
                &dev.key,
                format!(
                    "the submodule {} of the device's DAP ({}:{}) has subslots {list}, which \
                     cannot all be added automatically (subslots are 1 to 65535); list slot 0 \
                     in the configuration yourself",
                    item(sub.name.as_deref(), &sub.id),
                    dev.file(),
                    sub.line
                ),
            ));
        }
        out.extend(subslots.into_iter().map(|s| (s, sub)));
    }
    out.sort_by_key(|&(s, _)| s);
    if let Some(pair) = out.windows(2).find(|w| w[0].0 == w[1].0) {
        let (subslot, first) = pair[0];
        let second = pair[1].1;
        return Err(cx.invalid(
            dev.span.clone(),
            &dev.key,
            format!(
                "the device's DAP has two submodules in subslot {subslot}, {} ({file}:{}) and \
                 {} ({file}:{}); list slot 0 in the configuration yourself",
                item(first.name.as_deref(), &first.id),
                first.line,
                item(second.name.as_deref(), &second.id),
                second.line,
                file = dev.file(),
            ),
        ));
    }
    Ok(out)
}
