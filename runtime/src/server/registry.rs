// SPDX-License-Identifier: MIT OR Apache-2.0
//! Who is attached, and who holds which outputs.

use crate::cycle::{Command, Shared};
use procimg_control::{ClientRole, Refusal};
use procimg_shm_layout::{MAX_CLIENTS, NO_ADDRESS, SubmoduleEntry};
use std::collections::BTreeSet;
use std::sync::atomic::Ordering;

/// One attached client.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ClientEntry {
    /// Token of this registration.
    pub token: u64,
    /// Name it gave.
    pub name: String,
    /// Process id.
    pub pid: u32,
    /// Role.
    pub role: ClientRole,
    /// iceoryx2 node id (hex), for liveness.
    pub node_id: String,
    /// Claimed submodules.
    pub claims: BTreeSet<u32>,
}

/// The clients of the server, by slot.
pub struct Registry {
    slots: Vec<Option<ClientEntry>>,
    next_token: u64,
}

impl Registry {
    /// An empty registry whose tokens start from `seed` (tokens of different server runs
    /// differ).
    pub fn new(seed: u64) -> Registry {
        Registry {
            slots: vec![None; MAX_CLIENTS],
            next_token: seed | 1,
        }
    }

    /// Attached clients with their slots.
    pub fn clients(&self) -> impl Iterator<Item = (u32, &ClientEntry)> {
        self.slots
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.as_ref().map(|c| (i as u32, c)))
    }

    /// Whether `slot` holds the registration of `token`.
    pub fn is_registered(&self, slot: u32, token: u64) -> bool {
        matches!(self.slots.get(slot as usize), Some(Some(c)) if c.token == token)
    }

    /// The client in `slot` if `token` matches.
    fn client_mut(&mut self, slot: u32, token: u64) -> Result<&mut ClientEntry, Refusal> {
        match self.slots.get_mut(slot as usize) {
            Some(Some(c)) if c.token == token => Ok(c),
            _ => Err(Refusal::UnknownClient),
        }
    }

    /// Registers a client and tells the cycle thread.
    ///
    /// A client's node registers once: a second registration from the same node is a retry
    /// whose answer the client did not wait for (a re-attachment with a short timeout on a
    /// loaded machine), so it replaces the first, which the client never learnt of and
    /// would otherwise hold a slot, and its claims, for as long as the process lives.
    pub fn register(
        &mut self,
        shared: &Shared,
        name: String,
        pid: u32,
        role: ClientRole,
        newcycle: bool,
        node_id: String,
    ) -> Result<(u32, u64), Refusal> {
        let earlier: Vec<u32> = self
            .clients()
            .filter(|(_, c)| !node_id.is_empty() && c.node_id == node_id)
            .map(|(slot, _)| slot)
            .collect();
        for slot in earlier {
            self.unregister(shared, slot);
        }
        let slot = self
            .slots
            .iter()
            .position(Option::is_none)
            .ok_or(Refusal::TooManyClients {
                max: MAX_CLIENTS as u32,
            })?;
        let token = random_token().unwrap_or(self.next_token);
        self.next_token = self.next_token.wrapping_add(2);
        self.slots[slot] = Some(ClientEntry {
            token,
            name,
            pid,
            role,
            node_id,
            claims: BTreeSet::new(),
        });
        let joined = shared.command(Command::Join {
            slot: slot as u32,
            token,
            synchronous: role == ClientRole::Synchronous,
            newcycle,
        });
        if !joined {
            self.slots[slot] = None;
            return Err(Refusal::ServerBusy);
        }
        Ok((slot as u32, token))
    }

    /// Removes a client, releasing its claims. Returns the removed entry.
    pub fn unregister(&mut self, shared: &Shared, slot: u32) -> Option<ClientEntry> {
        let entry = self.slots.get_mut(slot as usize)?.take()?;
        for &s in &entry.claims {
            if let Some(c) = shared.claims.get(s as usize) {
                let _ = c.compare_exchange(entry.token, 0, Ordering::AcqRel, Ordering::Acquire);
            }
        }
        shared.command(Command::Leave { slot });
        Some(entry)
    }

    /// Removes a client after checking its token.
    pub fn unregister_checked(
        &mut self,
        shared: &Shared,
        slot: u32,
        token: u64,
    ) -> Result<(), Refusal> {
        self.client_mut(slot, token)?;
        self.unregister(shared, slot);
        Ok(())
    }

    /// Claims the outputs of `submodules` for a client: all or none.
    pub fn claim(
        &mut self,
        shared: &Shared,
        table: &[SubmoduleEntry],
        slot: u32,
        token: u64,
        submodules: &[u32],
    ) -> Result<(), Refusal> {
        self.client_mut(slot, token)?;
        for &s in submodules {
            let e = table
                .get(s as usize)
                .ok_or(Refusal::NoSuchSubmodule { submodule: s })?;
            if e.output_length == 0 || e.output_address == NO_ADDRESS {
                return Err(Refusal::NoOutputs { submodule: s });
            }
            let owner = shared.owner(s as usize);
            if owner != 0 && owner != token {
                return Err(self.holder_of(s, owner));
            }
        }
        for &s in submodules {
            shared.claims[s as usize].store(token, Ordering::Release);
        }
        self.client_mut(slot, token)?
            .claims
            .extend(submodules.iter().copied());
        Ok(())
    }

    /// Releases claims of a client (those it does not hold are ignored).
    pub fn release(
        &mut self,
        shared: &Shared,
        slot: u32,
        token: u64,
        submodules: &[u32],
    ) -> Result<(), Refusal> {
        let c = self.client_mut(slot, token)?;
        for s in submodules {
            if c.claims.remove(s) {
                let _ = shared.claims[*s as usize].compare_exchange(
                    token,
                    0,
                    Ordering::AcqRel,
                    Ordering::Acquire,
                );
            }
        }
        Ok(())
    }

    fn holder_of(&self, submodule: u32, owner: u64) -> Refusal {
        let (slot, c) = self
            .clients()
            .find(|(_, c)| c.token == owner)
            .map(|(s, c)| (s, Some(c)))
            .unwrap_or((u32::MAX, None));
        Refusal::ClaimHeld {
            submodule,
            holder: c.map_or_else(|| "?".into(), |c| c.name.clone()),
            holder_pid: c.map_or(0, |c| c.pid),
            holder_slot: slot,
        }
    }
}

/// A token nobody can guess from what is published (the generation, other tokens): 64 bits
/// from the kernel's random source; never 0 (which means "unclaimed").
fn random_token() -> Option<u64> {
    let mut b = [0u8; 8];
    crate::sys::random::fill(&mut b).then(|| u64::from_ne_bytes(b) | 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn register(r: &mut Registry, shared: &Shared, node: &str) -> (u32, u64) {
        r.register(
            shared,
            "client".into(),
            1,
            ClientRole::Synchronous,
            false,
            node.into(),
        )
        .expect("a free slot")
    }

    #[test]
    fn a_repeated_registration_of_one_node_replaces_the_first() {
        let shared = Shared::new(4);
        let mut r = Registry::new(7);
        let (a, _) = register(&mut r, &shared, "node-a");
        let (b, _) = register(&mut r, &shared, "node-b");
        let (again, token) = register(&mut r, &shared, "node-a");
        let nodes: Vec<(u32, &str)> = r.clients().map(|(s, c)| (s, c.node_id.as_str())).collect();
        assert_eq!(nodes.len(), 2, "{nodes:?}");
        assert!(nodes.contains(&(b, "node-b")));
        assert!(nodes.contains(&(again, "node-a")));
        assert!(r.client_mut(again, token).is_ok());
        if again != a {
            assert!(r.slots[a as usize].is_none());
        }
    }
}
