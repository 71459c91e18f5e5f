// SPDX-License-Identifier: MIT OR Apache-2.0
//! The notification subscribers a role's client services know of: announced with
//! `Subscribe`, withdrawn with `Unsubscribe`, forgotten when their process is gone, listed in
//! the status report. Notifications go to every client of the notification service either
//! way; the table is what the server knows of who listens (for the status report and, in the
//! IO controller, for whom an alarm waits).

use procimg_control::{Refusal, SubscriberReport};
use std::collections::{HashMap, HashSet};

/// An announced subscriber.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Subscriber {
    /// The name it announced.
    pub name: String,
    /// Its process id.
    pub pid: u32,
    /// The iceoryx2 node id it announced, to tell when its process is gone.
    pub node_id: String,
    /// It asked to take part in alarm acknowledgement.
    pub acknowledges: bool,
}

impl std::fmt::Display for Subscriber {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} (pid {})", self.name, self.pid)
    }
}

/// The announced subscribers, by the id each chose.
#[derive(Debug, Default)]
pub struct Subscribers {
    table: HashMap<u64, Subscriber>,
}

impl Subscribers {
    /// Announces subscriber `id` (again: its settings are replaced).
    pub fn subscribe(&mut self, id: u64, subscriber: Subscriber) {
        self.table.insert(id, subscriber);
    }

    /// Withdraws subscriber `id`; refused when it is not known (the server restarted, or
    /// reaped it).
    pub fn unsubscribe(&mut self, id: u64) -> Result<Subscriber, Refusal> {
        self.table.remove(&id).ok_or(Refusal::UnknownSubscriber)
    }

    /// Forgets the subscribers whose process is gone (`alive`: the live iceoryx2 node ids);
    /// returns them.
    pub fn reap(&mut self, alive: &HashSet<String>) -> Vec<(u64, Subscriber)> {
        let dead: Vec<u64> = self
            .table
            .iter()
            .filter(|(_, s)| !alive.contains(&s.node_id))
            .map(|(&id, _)| id)
            .collect();
        dead.into_iter()
            .filter_map(|id| Some((id, self.table.remove(&id)?)))
            .collect()
    }

    /// Subscriber `id`, if announced.
    pub fn get(&self, id: u64) -> Option<&Subscriber> {
        self.table.get(&id)
    }

    /// The ids of the subscribers that take part in alarm acknowledgement.
    pub fn acknowledging(&self) -> Vec<u64> {
        self.table
            .iter()
            .filter(|(_, s)| s.acknowledges)
            .map(|(&id, _)| id)
            .collect()
    }

    /// The subscribers for the status report, in a stable order (by pid, then name);
    /// `waiting` tells how many alarms wait for a subscriber's acknowledgement.
    pub fn report(&self, waiting: impl Fn(u64) -> u32) -> Vec<SubscriberReport> {
        let mut v: Vec<SubscriberReport> = self
            .table
            .iter()
            .map(|(&id, s)| SubscriberReport {
                name: s.name.clone(),
                pid: s.pid,
                acknowledges_alarms: s.acknowledges,
                alarms_waiting: waiting(id),
            })
            .collect();
        v.sort_by(|a, b| (a.pid, &a.name).cmp(&(b.pid, &b.name)));
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn subscriber(name: &str, pid: u32, node: &str) -> Subscriber {
        Subscriber {
            name: name.into(),
            pid,
            node_id: node.into(),
            acknowledges: false,
        }
    }

    #[test]
    fn a_subscriber_is_reported_until_it_leaves_or_its_process_is_gone() {
        let mut t = Subscribers::default();
        t.subscribe(1, subscriber("a", 20, "node-a"));
        t.subscribe(2, subscriber("b", 10, "node-b"));
        t.subscribe(3, subscriber("c", 30, "node-c"));
        let names = |t: &Subscribers| -> Vec<String> {
            t.report(|_| 0).into_iter().map(|r| r.name).collect()
        };
        assert_eq!(names(&t), ["b", "a", "c"]);

        assert_eq!(t.unsubscribe(3).map(|s| s.name), Ok("c".to_owned()));
        assert_eq!(t.unsubscribe(3), Err(Refusal::UnknownSubscriber));

        let alive = HashSet::from(["node-a".to_owned()]);
        let gone = t.reap(&alive);
        assert_eq!(gone.len(), 1);
        assert_eq!((gone[0].0, gone[0].1.to_string()), (2, "b (pid 10)".into()));
        assert_eq!(names(&t), ["a"]);
    }

    #[test]
    fn announcing_again_replaces_the_settings() {
        let mut t = Subscribers::default();
        t.subscribe(7, subscriber("a", 1, "n"));
        assert!(t.acknowledging().is_empty());
        t.subscribe(
            7,
            Subscriber {
                acknowledges: true,
                ..subscriber("a", 1, "n")
            },
        );
        assert_eq!(t.acknowledging(), [7]);
        let r = t.report(|id| if id == 7 { 2 } else { 0 });
        assert_eq!(
            (r.len(), r[0].acknowledges_alarms, r[0].alarms_waiting),
            (1, true, 2)
        );
    }
}
