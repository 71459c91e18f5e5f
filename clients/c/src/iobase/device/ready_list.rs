// SPDX-License-Identifier: MIT OR Apache-2.0
//! The list `PNIO_set_appl_state_ready` takes: the submodules the program is not ready for,
//! as IO-Base's circular lists of APIs, their slots and their subslots.

use super::Pos;
use crate::iobase::device_types::*;

/// More entries than this in one list: it does not end (a list the program broke).
const MAX_ENTRIES: usize = 4096;

/// The elements of the circular list at `head`, as pointers to their first member (their
/// link); none for an empty head (Flink NULL or the head itself).
///
/// # Safety
/// `head` points to a readable list head whose entries are readable list entries.
unsafe fn entries(
    head: *const PNIO_LIST_ENTRY_TYPE,
) -> Result<Vec<*const PNIO_LIST_ENTRY_TYPE>, ()> {
    let mut out = Vec::new();
    // SAFETY: readable by the caller's contract.
    let mut e = unsafe { (*head).Flink } as *const PNIO_LIST_ENTRY_TYPE;
    while !e.is_null() && e != head {
        if out.len() == MAX_ENTRIES {
            return Err(());
        }
        out.push(e);
        // SAFETY: an entry of the list, readable by the caller's contract.
        e = unsafe { (*e).Flink };
    }
    Ok(out)
}

/// The (API, slot, subslot) of every submodule in `list` (NULL: none); `Err` for a list
/// that does not end.
///
/// # Safety
/// `list` is NULL or points to a readable `PNIO_APPL_READY_LIST_TYPE` built as the manual
/// says: each entry the `link` of its element type.
pub(crate) unsafe fn not_ready(list: *const PNIO_APPL_READY_LIST_TYPE) -> Result<Vec<Pos>, ()> {
    let mut out = Vec::new();
    if list.is_null() {
        return Ok(out);
    }
    // SAFETY: not NULL; readable by the caller's contract; the link is the first member of
    // each element, so an entry pointer is one to its element.
    unsafe {
        for a in entries(&raw const (*list).ap_list)? {
            let ap = a.cast::<PNIO_APPL_READY_AP_TYPE>();
            let api = (*ap).api;
            for m in entries(&raw const (*ap).module_list)? {
                let module = m.cast::<PNIO_APPL_READY_MODULE_TYPE>();
                let slot = (*module).slot_nr;
                for s in entries(&raw const (*module).submodule_list)? {
                    let sub = s.cast::<PNIO_APPL_READY_SUBMODULE_TYPE>();
                    let at = (api, slot, (*sub).subslot_nr);
                    if !out.contains(&at) {
                        out.push(at);
                    }
                    if out.len() > MAX_ENTRIES {
                        return Err(());
                    }
                }
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ptr::null_mut;

    fn empty() -> PNIO_LIST_ENTRY_TYPE {
        PNIO_LIST_ENTRY_TYPE {
            Flink: null_mut(),
            Blink: null_mut(),
        }
    }

    /// Makes `head` a circular list of `entries`, in order.
    fn link(head: *mut PNIO_LIST_ENTRY_TYPE, entries: &[*mut PNIO_LIST_ENTRY_TYPE]) {
        let all: Vec<_> = std::iter::once(head)
            .chain(entries.iter().copied())
            .collect();
        for (i, &e) in all.iter().enumerate() {
            // SAFETY: the test's own live entries.
            unsafe {
                (*e).Flink = all[(i + 1) % all.len()];
                (*e).Blink = all[(i + all.len() - 1) % all.len()];
            }
        }
    }

    #[test]
    fn the_lists_give_each_submodule_once_and_a_list_that_does_not_end_is_refused() {
        let mut list = PNIO_APPL_READY_LIST_TYPE { ap_list: empty() };
        let mut ap = PNIO_APPL_READY_AP_TYPE {
            link: empty(),
            api: 0,
            module_list: empty(),
        };
        let mut slot = PNIO_APPL_READY_MODULE_TYPE {
            link: empty(),
            slot_nr: 1,
            submodule_list: empty(),
        };
        let mut sub = [1u16, 2, 1].map(|subslot_nr| PNIO_APPL_READY_SUBMODULE_TYPE {
            link: empty(),
            subslot_nr,
        });
        // SAFETY: NULL is no list.
        assert_eq!(unsafe { not_ready(std::ptr::null()) }, Ok(vec![]));
        // SAFETY: a head with a NULL Flink is an empty list.
        assert_eq!(unsafe { not_ready(&list) }, Ok(vec![]));
        link(&raw mut list.ap_list, &[&raw mut ap.link]);
        link(&raw mut ap.module_list, &[&raw mut slot.link]);
        let subs: Vec<_> = sub.iter_mut().map(|s| &raw mut s.link).collect();
        link(&raw mut slot.submodule_list, &subs);
        // SAFETY: the lists just built.
        assert_eq!(unsafe { not_ready(&list) }, Ok(vec![(0, 1, 1), (0, 1, 2)]));
        // An entry that points at itself: the list never comes back to its head.
        let second = subs[1];
        // SAFETY: the test's own live entry.
        unsafe { (*second).Flink = second };
        // SAFETY: still readable, only no longer ending.
        assert_eq!(unsafe { not_ready(&list) }, Err(()));
    }
}
