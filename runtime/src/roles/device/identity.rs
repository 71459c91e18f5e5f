// SPDX-License-Identifier: MIT OR Apache-2.0
//! DCP's changes of the station's identity: its name, its IP suite, a reset to factory. The
//! engine applies them without an event of its own, so the role compares what the engine
//! holds after each step with what it saw before.

use procimg_profinet::device::{Application, Device, KeptIdentity};
use std::net::Ipv4Addr;

/// The station's name and IP suite, as DCP may set them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Identity {
    /// NameOfStation (empty: none).
    pub name: String,
    /// IP address (unspecified: none).
    pub ip: Ipv4Addr,
    /// Subnet mask.
    pub netmask: Ipv4Addr,
    /// Default gateway.
    pub gateway: Ipv4Addr,
}

impl Identity {
    /// What `device` holds now.
    pub fn of<A: Application>(device: &Device<A>) -> Identity {
        let (mask, gateway) = device.station().mask_and_gateway();
        Identity {
            name: device.station().name().to_owned(),
            ip: Ipv4Addr::from(device.station().ip()),
            netmask: Ipv4Addr::from(mask),
            gateway: Ipv4Addr::from(gateway),
        }
    }

    /// No name, no address: what a reset to factory leaves.
    fn is_factory(&self) -> bool {
        self.name.is_empty() && self.ip.is_unspecified()
    }
}

/// A change DCP made: the identity now, whether it is kept across a restart, whether it was
/// a reset to factory (see `StationEvent::Identity`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct IdentityChange {
    /// The name and IP suite now.
    pub identity: Identity,
    /// DCP set it to be kept: the engine's count of kept changes grew.
    pub permanent: bool,
    /// A reset to factory, as told from the state it leaves.
    pub factory_reset: bool,
}

/// What the role saw last of the station's identity.
#[derive(Debug)]
pub struct IdentityWatch {
    seen: Identity,
    /// The engine's count of changes to keep, when last seen.
    kept_changes: u64,
}

impl IdentityWatch {
    /// Starts from what `device` holds now (the configuration's, or what the state file
    /// kept): nothing to report.
    pub fn new<A: Application>(device: &Device<A>) -> IdentityWatch {
        IdentityWatch {
            seen: Identity::of(device),
            kept_changes: device.station().kept_identity().changes,
        }
    }

    /// What DCP changed since the last look, if anything.
    pub fn check<A: Application>(&mut self, device: &Device<A>) -> Option<IdentityChange> {
        self.compare(Identity::of(device), device.station().kept_identity())
    }

    /// `now` against what was seen, with the engine's kept identity `kept`. A Set to keep
    /// reports even when the value stays (it is now kept across a restart).
    fn compare(&mut self, now: Identity, kept: &KeptIdentity) -> Option<IdentityChange> {
        let permanent = kept.changes != self.kept_changes;
        if now == self.seen && !permanent {
            return None;
        }
        self.kept_changes = kept.changes;
        self.seen = now.clone();
        // A reset keeps the factory state (no name, no address) for the next start too.
        let kept_factory = kept.name.as_deref() == Some("") && kept.ip_suite == Some([[0; 4]; 3]);
        Some(IdentityChange {
            factory_reset: permanent && kept_factory && now.is_factory(),
            identity: now,
            permanent,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn identity(name: &str, ip: [u8; 4]) -> Identity {
        Identity {
            name: name.into(),
            ip: ip.into(),
            netmask: if ip == [0; 4] {
                Ipv4Addr::UNSPECIFIED
            } else {
                Ipv4Addr::new(255, 255, 255, 0)
            },
            gateway: Ipv4Addr::UNSPECIFIED,
        }
    }

    fn watch() -> IdentityWatch {
        IdentityWatch {
            seen: identity("pc-device", [10, 47, 0, 50]),
            kept_changes: 0,
        }
    }

    fn kept(changes: u64, name: Option<&str>, ip: Option<[u8; 4]>) -> KeptIdentity {
        KeptIdentity {
            name: name.map(Into::into),
            ip_suite: ip.map(|ip| {
                let i = identity("", ip);
                [ip, i.netmask.octets(), i.gateway.octets()]
            }),
            changes,
        }
    }

    fn reported(e: Option<IdentityChange>) -> Option<(String, bool, bool)> {
        e.map(|c| (c.identity.name, c.permanent, c.factory_reset))
    }

    #[test]
    fn nothing_changed_nothing_reported() {
        let mut w = watch();
        let same = identity("pc-device", [10, 47, 0, 50]);
        assert_eq!(w.compare(same, &KeptIdentity::default()), None);
    }

    #[test]
    fn a_temporary_name_is_reported_once_and_not_as_permanent() {
        let mut w = watch();
        let k = KeptIdentity::default();
        let renamed = identity("other", [10, 47, 0, 50]);
        assert_eq!(
            reported(w.compare(renamed.clone(), &k)),
            Some(("other".into(), false, false))
        );
        assert_eq!(w.compare(renamed, &k), None);
    }

    #[test]
    fn a_permanent_set_is_reported_even_with_the_same_value() {
        let mut w = watch();
        let same = identity("pc-device", [10, 47, 0, 50]);
        let k = kept(1, Some("pc-device"), None);
        assert_eq!(
            reported(w.compare(same.clone(), &k)),
            Some(("pc-device".into(), true, false))
        );
        assert_eq!(w.compare(same, &k), None);
    }

    #[test]
    fn a_reset_to_factory_is_no_name_and_no_address_kept_so() {
        let mut w = watch();
        let k = kept(1, Some(""), Some([0; 4]));
        assert_eq!(
            reported(w.compare(identity("", [0; 4]), &k)),
            Some((String::new(), true, true))
        );
    }

    #[test]
    fn clearing_only_for_now_is_no_reset_to_factory() {
        let mut w = watch();
        // Cleared temporarily: the next start comes back with the kept identity.
        assert_eq!(
            reported(w.compare(identity("", [0; 4]), &KeptIdentity::default())),
            Some((String::new(), false, false))
        );
        // Only the name cleared for good, the address cleared for now.
        let mut w = watch();
        let k = kept(1, Some(""), None);
        assert_eq!(
            reported(w.compare(identity("", [0; 4]), &k)),
            Some((String::new(), true, false))
        );
    }
}
