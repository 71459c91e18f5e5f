// SPDX-License-Identifier: MIT OR Apache-2.0
//! The network interfaces of this machine, for messages that name the ones there are when a
//! name is wrong.
//!
//! The list comes from `getifaddrs(3)` (through pnet), which answers for the network namespace
//! of the calling thread; `/sys/class/net` answers for the namespace sysfs was mounted in.

/// The names of the network interfaces in this thread's network namespace, sorted.
pub fn names() -> Vec<String> {
    let mut names: Vec<String> = pnet_datalink::interfaces()
        .into_iter()
        .map(|i| i.name)
        .collect();
    names.sort();
    names.dedup();
    names
}

/// Whether an interface called `name` exists in this thread's network namespace.
pub fn exists(name: &str) -> bool {
    pnet_datalink::interfaces().iter().any(|i| i.name == name)
}

/// `Ok` if interface `name` exists, else [`missing`]'s words: the interface check
/// `procimg_config::load` takes.
pub fn check(name: &str) -> Result<(), String> {
    if exists(name) {
        Ok(())
    } else {
        Err(missing(name))
    }
}

/// The first IPv4 address of interface `name`, if it has one.
pub fn ipv4(name: &str) -> Option<std::net::Ipv4Addr> {
    pnet_datalink::interfaces()
        .into_iter()
        .find(|i| i.name == name)?
        .ips
        .into_iter()
        .find_map(|ip| match ip.ip() {
            std::net::IpAddr::V4(v4) => Some(v4),
            _ => None,
        })
}

/// `names`, for a message: `eth0, lo`, or `none` when there are none.
pub fn list(names: &[String]) -> String {
    if names.is_empty() {
        "none".to_owned()
    } else {
        names.join(", ")
    }
}

/// What to say when there is no interface `name`: that it does not exist, and which do.
/// Callers add what to do in the words of their own command (a configuration key, an
/// option).
pub fn missing(name: &str) -> String {
    format!(
        "network interface \"{name}\" does not exist on this machine (its interfaces: {})",
        list(&names())
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loopback_is_listed_and_a_made_up_name_is_not() {
        // Every network namespace has its loopback interface.
        assert!(exists("lo"));
        assert!(names().iter().any(|n| n == "lo"));
        assert!(!exists("nosuchif0"));
        assert_eq!(ipv4("lo"), Some(std::net::Ipv4Addr::LOCALHOST));
        assert_eq!(ipv4("nosuchif0"), None);
        let m = missing("nosuchif0");
        assert!(m.contains("\"nosuchif0\" does not exist"), "{m}");
        assert!(m.contains("lo"), "{m}");
        assert_eq!(list(&[]), "none");
    }
}
